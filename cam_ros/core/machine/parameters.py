"""The parameters a machine file adds to the cam format: its axes and the interference pairs.

A machine file names its axes in ``axes``; every key of a single-cam file is then either
machine-wide (:data:`MACHINE_WIDE`, at the top, shared by every axis) or per axis (under
``<axis>.``). The interference section is parallel arrays, one entry per checked pair.
"""
from __future__ import annotations

from ..config.parameters import (LENGTH_UNITS, PARAMETERS, ParameterSpec, REQUIRED,
                                 ROS_NODE_PARAMETERS)

#: Most axes of one machine (a PLC runs up to 255 or 256).
MAX_AXES = 256
#: Machine-wide parameters of the single-cam format: exact names, and prefixes ending in '.'.
MACHINE_WIDE_NAMES = ('cam_speed', 'length_unit', 'master.source', 'master.topic',
                      'master.joint', 'master.timeout', 'master.velocity_window',
                      'master.max_speed', 'master.periodic', 'command.trajectory_horizon',
                      'command.trajectory_points')
MACHINE_WIDE_PREFIXES = ('master.engage_', 'output.', 'recording.', 'switches.')


def machine_wide(name: str) -> bool:
    """Say whether a single-cam parameter is machine-wide in a machine file."""
    return name in MACHINE_WIDE_NAMES or name.startswith(MACHINE_WIDE_PREFIXES)


#: The machine-wide parameters, and those each axis gives under its prefix (length_unit is both:
#: the machine's for the interference section, and each axis's own).
MACHINE_WIDE = tuple(spec.name for spec in PARAMETERS if machine_wide(spec.name))
PER_AXIS = tuple(spec.name for spec in PARAMETERS
                 if not machine_wide(spec.name) or spec.name == 'length_unit')


def _pair_array(name: str, type_: str, description: str, **kw: object) -> ParameterSpec:
    """Return the spec of one parallel interference array (one entry per pair)."""
    return ParameterSpec(f'interference.{name}', type_, [], description, **kw)  # type: ignore


#: The machine's own parameters: its axes, its length unit (a length) and the interference pairs.
MACHINE_PARAMETERS: tuple[ParameterSpec, ...] = (
    ParameterSpec('axes', 'string_array', REQUIRED, 'Axis names: each is the axis\'s joint name '
                  'and the prefix of its parameters'),
    ParameterSpec('length_unit', 'string', REQUIRED, 'Unit of the lengths of the interference '
                  'section', choices=tuple(LENGTH_UNITS)),
    _pair_array('axis_a', 'string_array', 'First axis of each checked pair'),
    _pair_array('axis_b', 'string_array', 'Second axis of each checked pair'),
    _pair_array('type', 'string_array', 'Check of each pair: clearance (a gap that must stay '
                'open) or zones (a shared space never occupied by both)'),
    _pair_array('offset', 'double_array', 'Gap at y_a = y_b = 0 (clearance)',
                unit='length_unit', minimum=-1e9, maximum=1e9),
    _pair_array('gain_a', 'double_array', 'Gap change per unit of axis a\'s position '
                '(clearance; machine length_unit per the axis\'s own file unit)',
                minimum=-1e9, maximum=1e9),
    _pair_array('gain_b', 'double_array', 'Gap change per unit of axis b\'s position '
                '(clearance)', minimum=-1e9, maximum=1e9),
    _pair_array('min_clearance', 'double_array', 'Smallest gap allowed (clearance)',
                unit='length_unit', minimum=-1e9, maximum=1e9),
    _pair_array('zone_a', 'double_array', 'Axis a is in the shared zone above this position '
                '(zones; the axis\'s own file unit)', unit='axis unit', minimum=-1e9,
                maximum=1e9),
    _pair_array('zone_b', 'double_array', 'Axis b is in the shared zone above this position '
                '(zones)', unit='axis unit', minimum=-1e9, maximum=1e9),
    _pair_array('min_margin_deg', 'double_array', 'Smallest machine angle allowed between one '
                'axis leaving the zone and the other entering (zones)', unit='deg',
                minimum=0.0, maximum=360.0),
)
MACHINE_SPECS: dict[str, ParameterSpec] = {spec.name: spec for spec in MACHINE_PARAMETERS}
INTERFERENCE = tuple(name for name in MACHINE_SPECS if name.startswith('interference.'))
PAIR_TYPES = ('clearance', 'zones')
#: Words an axis may not be named: the first part of any machine-wide or single-cam parameter.
RESERVED_NAMES = frozenset(name.split('.')[0] for name in (
    *(spec.name for spec in PARAMETERS), *MACHINE_SPECS, *ROS_NODE_PARAMETERS))
