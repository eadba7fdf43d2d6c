"""A machine file: many cam axes on one master, and the pairs of them checked for collisions.

A ROS 2 parameters file with ``axes`` (string array) describes a machine::

    length_unit: mm               # the machine's: the interference section's lengths
    cam_speed: 6.283              # rad/s of machine angle; master.*, output.*, ... likewise
    axes: [feeder, knife]
    feeder:                       # every per-axis key of a single-cam file, under the axis
      length_unit: mm
      motion: {laws: [...], ...}
      master: {offset_deg: 30.0, scaling: 0.5}
    interference:                 # parallel arrays, one entry per checked pair
      axis_a: [feeder]
      ...

Machine-wide keys (:data:`~.parameters.MACHINE_WIDE`) are given once, at the top; every other
key is per axis. Each axis's CamConfig is parsed by the single-cam parse_parameters from the
machine-wide keys (except switches.*, which are the machine's, and the machine's length_unit)
plus its own, so an axis obeys today's rules and defaults; every error names the key as the
file spells it (``knife.motion.laws``).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, Mapping

from ..config.parameters import (check_parameter, check_type, REQUIRED,
                                 ROS_NODE_PARAMETERS, SPECS, UNITS)
from ..config.schema import CamConfig, check_switches, parse_parameters
from ..errors import did_you_mean, InvalidParameter
from .parameters import (INTERFERENCE, MACHINE_SPECS, MACHINE_WIDE, MAX_AXES, PAIR_TYPES,
                         PER_AXIS, RESERVED_NAMES)

AXIS_NAME = re.compile(r'[A-Za-z_][A-Za-z0-9_]*')
#: How far 1 / master.scaling may be from a whole number (relative): 0.3333333333 passes.
WHOLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class InterferencePair:
    """One checked pair of axes, in SI (see the interference module for the checks).

    gain_a, gain_b: m of gap per SI unit of the axis's position (m, or rad of an angular axis);
    zone_a, zone_b: in the axis's SI unit; min_margin: rad of machine angle. Fields a pair's type
    does not use are as the file gives them (0.0).
    """

    axis_a: str
    axis_b: str
    type: str  # 'clearance' or 'zones'
    offset: float  # m
    gain_a: float
    gain_b: float
    min_clearance: float  # m
    zone_a: float
    zone_b: float
    min_margin: float  # rad of machine angle


@dataclass(frozen=True)
class MachineConfig:
    """A machine file checked: its axes' configs in axes order and its interference pairs.

    parameters: the machine-wide flat values, checked, with their defaults (incl. axes,
    length_unit and interference.*).
    """

    names: tuple[str, ...]
    axes: tuple[CamConfig, ...]
    parameters: Mapping[str, Any]
    length_unit: str
    interference: tuple[InterferencePair, ...]

    def axis(self, name: str) -> CamConfig:
        """Return the config of the axis called name."""
        return self.axes[axis_index(self.names, name)]


def axis_index(names: tuple[str, ...], name: str) -> int:
    """Return where name is in names, else raise naming the axes."""
    if name not in names:
        raise InvalidParameter('axis', name, f'is not an axis of the machine (axes: '
                               f'{", ".join(names)}){did_you_mean(name, names)}')
    return names.index(name)


def is_machine(values: Mapping[str, Any]) -> bool:
    """Say whether flat parameters (read_parameters_file's) describe a machine: they have axes."""
    return 'axes' in values


def parse_machine(values: Mapping[str, Any]) -> MachineConfig:
    """Check a machine's flat parameters and parse each axis; errors name the key as written."""
    names = _axis_names(values)
    wide: dict[str, Any] = {'axes': names}
    own: dict[str, dict[str, Any]] = {name: {} for name in names}
    for key, value in values.items():
        if key == 'axes':
            continue
        head, _, rest = key.partition('.')
        if key in ROS_NODE_PARAMETERS:
            check_type(ROS_NODE_PARAMETERS[key], value)
        elif key in MACHINE_SPECS:
            wide[key] = check_parameter(key, value, MACHINE_SPECS)
        elif key in MACHINE_WIDE:
            wide[key] = check_parameter(key, value)
        elif head in own and rest in PER_AXIS:
            own[head][rest] = value
        elif head in own and rest in MACHINE_WIDE:
            raise InvalidParameter(key, value, 'is machine-wide: give it once, at the top (write '
                                   f'{rest})')
        elif key in SPECS:
            raise InvalidParameter(key, value, 'is per axis in a machine file (write '
                                   f'{names[0]}.{key}, ...)')
        else:
            known = (*MACHINE_SPECS, *MACHINE_WIDE,
                     *(f'{name}.{item}' for name in names for item in PER_AXIS))
            raise InvalidParameter(key, value,
                                   f'is not a machine parameter{did_you_mean(key, known)}')
    for spec in (*MACHINE_SPECS.values(), *(SPECS[name] for name in MACHINE_WIDE)):
        if spec.name not in wide:
            if spec.default is REQUIRED:
                raise InvalidParameter(spec.name, None, f'is required in a machine file '
                                       f'({spec.rule})')
            wide[spec.name] = check_parameter(spec.name, spec.default, MACHINE_SPECS
                                              if spec.name in MACHINE_SPECS else SPECS)
    check_switches(wide)
    shared = {name: value for name, value in wide.items()
              if name in MACHINE_WIDE and name != 'length_unit'
              and not name.startswith('switches.')}
    axes = tuple(_parse_axis(name, {**shared, **own[name]}) for name in names)
    return MachineConfig(names, axes, wide, wide['length_unit'],
                         _pairs(wide, names, axes))


def _axis_names(values: Mapping[str, Any]) -> tuple[str, ...]:
    """Return the checked axis names: ROS name parts, not a parameter's first word, once each."""
    names = check_parameter('axes', values.get('axes'), MACHINE_SPECS)
    if not names:
        raise InvalidParameter('axes', [], 'must name at least one axis')
    if len(names) > MAX_AXES:
        raise InvalidParameter('axes', list(names), f'must name at most {MAX_AXES} axes')
    for index, name in enumerate(names):
        where = f'axes[{index}]'
        if not AXIS_NAME.fullmatch(name):
            raise InvalidParameter(where, name, 'must be a joint name: letters, digits and _, '
                                   'not starting with a digit')
        if name in RESERVED_NAMES:
            raise InvalidParameter(where, name, 'is a parameter word of the cam format: name '
                                   'the axis otherwise')
        if name in names[:index]:
            raise InvalidParameter(where, name, 'must be given once')
    return names


def _parse_axis(name: str, flat: Mapping[str, Any]) -> CamConfig:
    """Parse one axis's flat values; errors about its own keys name them with its prefix."""
    try:
        config = parse_parameters(flat)
    except InvalidParameter as err:
        raise axis_error(name, err) from err
    scaling = config.parameters['master.scaling']
    cycles = 1.0 / scaling
    if round(cycles) < 1 or abs(cycles - round(cycles)) > WHOLE_TOLERANCE * cycles:
        raise InvalidParameter(f'{name}.master.scaling', scaling, 'must be 1 / n for a whole n '
                               '(the axis repeats n times per machine cycle)')
    if scaling == 1.0:
        return config
    # The axis's cam turns 1 / scaling times as fast as the machine: its forces, limits and
    # speeds are those of its own cam speed (the master's stays the machine's cam_speed).
    return parse_parameters({**flat, 'cam_speed': flat['cam_speed'] / scaling})


def axis_error(name: str, err: InvalidParameter) -> InvalidParameter:
    """Restate an error of axis name's config with the key as the machine file spells it."""
    first = re.split(r'[\[ ]', err.parameter, maxsplit=1)[0]
    if first in MACHINE_WIDE and first != 'length_unit':
        return err
    return InvalidParameter(f'{name}.{err.parameter}', err.value, err.rule)


def _pairs(wide: Mapping[str, Any], names: tuple[str, ...],
           axes: tuple[CamConfig, ...]) -> tuple[InterferencePair, ...]:
    """Return the interference pairs in SI after the rules that span their arrays."""
    count = len(wide['interference.axis_a'])
    for name in INTERFERENCE[1:]:
        if len(wide[name]) != count:
            raise InvalidParameter(name, list(wide[name]), f'must have {count} entries, one '
                                   'per entry of interference.axis_a')
    metre = UNITS[wide['length_unit']]
    pairs = []
    for index, row in enumerate(zip(*(wide[name] for name in INTERFERENCE))):
        fields = dict(zip((name.partition('.')[2] for name in INTERFERENCE), row))
        for side in ('axis_a', 'axis_b'):
            if fields[side] not in names:
                raise InvalidParameter(f'interference.{side}[{index}]', fields[side],
                                       'must be an axis of axes'
                                       f'{did_you_mean(fields[side], names)}')
        if fields['axis_a'] == fields['axis_b']:
            raise InvalidParameter(f'interference.axis_b[{index}]', fields['axis_b'],
                                   'must differ from interference.axis_a (a pair of two axes)')
        if fields['type'] not in PAIR_TYPES:
            raise InvalidParameter(f'interference.type[{index}]', fields['type'],
                                   f'must be one of {", ".join(PAIR_TYPES)}'
                                   f'{did_you_mean(fields["type"], PAIR_TYPES)}')
        unit_a, unit_b = (_position_unit(axes[names.index(fields[side])])
                          for side in ('axis_a', 'axis_b'))
        pairs.append(InterferencePair(
            fields['axis_a'], fields['axis_b'], fields['type'], fields['offset'] * metre,
            fields['gain_a'] * metre / unit_a, fields['gain_b'] * metre / unit_b,
            fields['min_clearance'] * metre, fields['zone_a'] * unit_a,
            fields['zone_b'] * unit_b, math.radians(fields['min_margin_deg'])))
    return tuple(pairs)


def _position_unit(config: CamConfig) -> float:
    """Return the SI value of one unit of an axis's file position (its length_unit, or deg)."""
    return 1.0 / config.file_position_unit[1]
