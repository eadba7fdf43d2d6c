"""The core's answers remembered for the values they depend on, so an edit asks only anew.

An edit changes one value; in a machine of many axes, the core would rebuild every axis and
check every pair again. An axis's design depends on its own values and the machine-wide ones
(not on the interference section), a pair's check on the pair and its two axes' electronic
cams (their positions over the machine angle, a rotary axis's modulo a turn: not on cam_speed,
say): each is kept under those and asked of the core again only when one of them changed. The
answers are the core's own (build_design, check_interference), never a copy of their work.
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace
from typing import Any, Callable, Hashable, Mapping, TypeVar

from cam_ros.core import build_design, CamDesign, InvalidParameter
from cam_ros.core.machine import (Axis, check_interference, is_machine, Machine, PairCheck,
                                  parse_machine)
from cam_ros.core.machine.config import axis_error
from cam_ros.core.machine.interference import rotary
from cam_ros.core.machine.served import machine_from_values

#: Answers kept of each kind: a few edits' worth of every axis and pair of a large machine.
KEPT = 256
T = TypeVar('T')
_DESIGNS: OrderedDict[Hashable, CamDesign] = OrderedDict()
_PAIRS: OrderedDict[Hashable, PairCheck] = OrderedDict()


def _kept(store: OrderedDict[Hashable, T], key: Hashable, make: Callable[[], T]) -> T:
    """Return the answer kept under key, else make it and keep it (the oldest go first)."""
    if key not in store:
        store[key] = make()
        while len(store) > KEPT:
            store.popitem(last=False)
    store.move_to_end(key)
    return store[key]


def _values_key(values: Mapping[str, Any], keep: Callable[[str], bool]) -> tuple:
    """Return the values whose names keep() takes, as a key (4 and 4.0 told apart)."""
    return tuple(sorted((name, repr(value)) for name, value in values.items() if keep(name)))


def machine_and_checks(values: Mapping[str, Any]) -> tuple[Machine, tuple[PairCheck, ...]]:
    """Return machine_from_values(values) and check_interference of it, answers remembered."""
    if not is_machine(values):
        machine = machine_from_values(values)
        return machine, check_interference(machine)
    config = parse_machine(values)
    names = config.names
    shared = _values_key(values, lambda name: name.split('.')[0] not in names
                         and not name.startswith('interference.'))
    keys = {name: (name, _values_key(values, lambda key: key.startswith(f'{name}.')), shared)
            for name in names}

    def build(name: str, axis_config: Any) -> CamDesign:
        try:
            return build_design(axis_config)
        except InvalidParameter as err:
            raise axis_error(name, err) from err

    axes = []
    for name, axis_config in zip(names, config.axes):
        design = _kept(_DESIGNS, keys[name], lambda: build(name, axis_config))
        axes.append(Axis(name, design, design.electronic_cam))
    machine = Machine(config, tuple(axes))
    cams = {axis.name: (repr(axis.cam), rotary(axis)) for axis in axes}  # all a pair reads
    pair_keys = [(pair, cams[pair.axis_a], cams[pair.axis_b]) for pair in config.interference]
    missing = tuple(pair for pair, key in zip(config.interference, pair_keys)
                    if key not in _PAIRS)
    found = dict(zip(missing, check_interference(
        Machine(replace(config, interference=missing), machine.axes)))) if missing else {}
    checks = tuple(_kept(_PAIRS, key, lambda: found[key[0]]) for key in pair_keys)
    return machine, checks
