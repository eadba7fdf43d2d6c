"""
What a node serves from its parameter values: a machine, and a single cam as a machine of one axis.

One path for one axis and for many: a params file without `axes` is the single cam, served as a
machine whose only axis is the joint `follower` and which has no interference pairs; a machine
file's axes are its own.

A running machine takes an update only if no interference pair collides, neither in the new
machine nor with any changed axis left on its old cam (a change's move may be refused when it is
planned, and the axis then stays there): every pair with a changed axis is checked with each of
its axes old or new. The moves onto the new cams are checked when they are planned.
"""
from __future__ import annotations

import math
from dataclasses import replace
from itertools import product
from typing import Any, Mapping

from ..cam_angles import cam_degrees
from ..config.parameters import ParameterSpec, PARAMETERS, SPECS, UNITS
from ..config.schema import parse_parameters
from ..design_from_config import build_design
from .config import is_machine, MachineConfig, parse_machine
from .interference import check_interference, PairCheck
from .machine import Axis, build_machine, Machine
from ..rounding import ceil_sig, floor_sig
from .parameters import MACHINE_SPECS, MACHINE_WIDE, PER_AXIS

#: The joint (and axis name) of a single cam.
SINGLE_AXIS = 'follower'


def machine_from_values(values: Mapping[str, Any]) -> Machine:
    """Return the machine a node serves from flat parameter values (see the module)."""
    if is_machine(values):
        return build_machine(parse_machine(values))
    config = parse_parameters(values)
    design = build_design(config)
    return Machine(MachineConfig((SINGLE_AXIS,), (config,), config.parameters,
                                 config.length_unit, ()),
                   (Axis(SINGLE_AXIS, design, design.electronic_cam),))


def pair_name(check: PairCheck) -> str:
    """Return a pair's type and axes: 'clearance feeder-jaw'."""
    return f'{check.pair.type} {check.pair.axis_a}-{check.pair.axis_b}'


def pair_line(check: PairCheck, length_unit: str) -> str:
    """Say one pair's verdict in one line: its smallest gap (in the machine's length_unit and
    in m) or margin, where, and its limit; figures rounded to the safe side (rounding)."""
    pair, state = check.pair, 'ok' if check.ok else 'COLLIDES'
    at = f'{cam_degrees(check.at, 2):.2f} deg'
    if pair.type == 'clearance':
        metre = UNITS[length_unit]
        return (f'{pair_name(check)}: smallest gap {floor_sig(check.value / metre)} '
                f'{length_unit} ({floor_sig(check.value)} m) at {at}, limit >= '
                f'{pair.min_clearance / metre:.6g} {length_unit}: {state}')
    limit = f'limit >= {math.degrees(pair.min_margin):.6g} deg: {state}'
    if check.value == math.inf:
        return f'{pair_name(check)}: an axis never enters its zone: {limit}'
    if check.value == -math.inf:
        return (f'{pair_name(check)}: an axis never leaves its zone, the other enters it at '
                f'{at}: {limit}')
    if check.value < 0.0:
        return (f'{pair_name(check)}: both in the zone for '
                f'{ceil_sig(-math.degrees(check.value))} deg of machine angle from {at} '
                f'(margin {floor_sig(math.degrees(check.value))} deg): {limit}')
    return (f'{pair_name(check)}: smallest margin {floor_sig(math.degrees(check.value))} deg '
            f'of machine angle, from one leaving the zone at {at} to the other entering: {limit}')


def collisions(machine: Machine) -> str:
    """Say every pair of the machine that collides ('' if none)."""
    return '; '.join(pair_line(check, machine.config.length_unit)
                     for check in check_interference(machine) if not check.ok)


def update_refusal(old: Machine, new: Machine) -> str:
    """Say why a running machine must not take an update ('' if it may; see the module)."""
    changed = {name for name, before, after in zip(new.config.names, old.axes, new.axes)
               if dict(before.design.config.parameters) != dict(after.design.config.parameters)}
    for pair in new.config.interference:
        names = (pair.axis_a, pair.axis_b)
        choices = [(old, new) if name in changed else (new,) for name in names]
        for sources in product(*choices):
            axes = {name: source.axis(name) for name, source in zip(names, sources)}
            config = replace(new.config, names=names, interference=(pair,),
                             axes=tuple(axes[name].design.config for name in names))
            check = check_interference(Machine(config, tuple(axes.values())))[0]
            if not check.ok:
                mix = ', '.join(f'{name} {"new" if source is new else "as now"}'
                                for name, source in zip(names, sources) if name in changed)
                return f'{pair_line(check, new.config.length_unit)} ({mix})'
    return ''


def served_specs(values: Mapping[str, Any]) -> dict[str, ParameterSpec]:
    """Return the parameters a node declares for values, by full name, in a stable order.

    A single cam's are the cam format's; a machine's are its machine-wide ones, its own (axes,
    length_unit, interference.*) and every per-axis one under each axis's prefix.
    """
    if not is_machine(values):
        return {spec.name: spec for spec in PARAMETERS}
    specs = {name: SPECS[name] for name in MACHINE_WIDE if name != 'length_unit'}
    specs.update(MACHINE_SPECS)
    for axis in parse_machine(values).names:
        specs.update({f'{axis}.{name}': SPECS[name] for name in PER_AXIS})
    return specs
