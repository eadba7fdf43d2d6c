"""The cam config format: one ROS 2 parameters file shared by the node, the CLI and the core.

A file looks like::

    /**:                      # or the node name, cam
      ros__parameters:
        length_unit: cm       # m, cm, mm or in: every length below is in this unit
        follower:
          type: translating_roller
          base_radius: 4.0
          ...
        motion:
          laws: [dwell, cycloidal, dwell, simple_harmonic]
          start_deg: [0.0, 90.0, 180.0, 240.0]
          ...

Nested keys flatten to dotted ROS parameter names (``follower.base_radius``). Every parameter is
listed once in :data:`PARAMETERS` with its type, default, unit and rule; the node declares exactly
these, and :func:`parse_parameters` applies the same rules without ROS, so a file the CLI
accepts is a file the node accepts. Values come out in SI (m, rad, s); angles in the file are in
degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..dynamics.contact import STEEL_MODULUS, STEEL_POISSON
from ..dynamics.follower import DynamicsConfig, parse_dynamics
from ..dynamics.vibration import parse_train, TrainConfig
from ..errors import did_you_mean, InvalidParameter
# The file side of the format (safe YAML reading, node sections) lives in params_file; these
# names stay importable from here.
from .params_file import (MAX_ARRAY_LENGTH, MAX_STRING_LENGTH, NODE_NAMES, flatten,  # noqa: F401
                          read_parameters_file)

LENGTH_UNITS = {'m': 1.0, 'cm': 0.01, 'mm': 0.001, 'in': 0.0254}
#: Every unit length_unit may name, in SI: the lengths, and deg for a rotary slave (rad).
UNITS = {**LENGTH_UNITS, 'deg': math.pi / 180.0}
#: 'none': a motion-only design (an electronic cam, no disk): no geometry, sizing or forces.
FOLLOWER_TYPES = ('translating_roller', 'translating_flat', 'oscillating_roller',
                  'oscillating_flat', 'none')
ROTATIONS = ('clockwise', 'counterclockwise')
CLOSURES = ('force', 'groove', 'conjugate')
COMPRESSIONS = ('zstd', 'lz4', 'none')
REQUIRED = object()  # default of a parameter the file must give
#: The optional per-segment arrays of a motion task, one entry per segment when given.
TASK_ARRAYS = tuple(f'motion.{side}_{name}' for name in ('velocity', 'acceleration', 'jerk')
                    for side in ('start', 'end')) + ('motion.inflection',)
#: Largest length (m) a config may give: far beyond any cam, and small enough that products of
#: lengths stay finite in double precision.
MAX_LENGTH_M = 1e3
#: Most cam switch tracks: one bit each of ~/switches (std_msgs/UInt32).
MAX_SWITCH_TRACKS = 32
#: Largest arm angle (deg) of an oscillating follower's motion.
MAX_ARM_ANGLE_DEG = 180.0
#: Largest slave position (deg) of a rotary slave: a thousand turns.
MAX_ROTARY_DEG = 360e3
#: Prefixes of the parameters that describe a cam, its follower train or their limits: a
#: motion-only design (follower.type: none) leaves them at their defaults.
CAM_ONLY = ('follower.', 'limits.pressure_angle', 'limits.min_radius', 'limits.contact',
            'dynamics.', 'contact.')


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of the config format: ROS type, default, unit and rule."""

    name: str
    type: str  # double, integer, string, bool, or one of those with the suffix _array
    default: Any
    description: str
    unit: str = ''
    minimum: float | None = None
    maximum: float | None = None
    choices: tuple[str, ...] = ()
    read_only: bool = False
    automatic: bool = False  # entries may be .nan, meaning "automatic"

    @property
    def rule(self) -> str:
        """Say in words what a valid value is."""
        parts = [self.type.replace('_', ' ')]
        if self.choices:
            parts.append('one of ' + ', '.join(self.choices))
        if self.minimum is not None and self.maximum is not None:
            parts.append(f'in [{self.minimum:g}, {self.maximum:g}]')
        elif self.minimum is not None:
            parts.append(f'>= {self.minimum:g}')
        return ', '.join(parts)


def _p(name: str, type_: str, default: Any, description: str, **kw: Any) -> ParameterSpec:
    return ParameterSpec(name, type_, default, description, **kw)


PARAMETERS: tuple[ParameterSpec, ...] = (
    _p('length_unit', 'string', 'm', 'Unit of every length in this file (deg: a rotary slave, '
       'follower.type none only)', choices=tuple(UNITS)),
    _p('rotation', 'string', 'clockwise', 'Direction the cam turns, seen from +z',
       choices=ROTATIONS),
    _p('cam_speed', 'double', 2 * math.pi, 'Constant cam speed', unit='rad/s',
       minimum=1e-9, maximum=1e5),
    _p('follower.type', 'string', REQUIRED, 'Follower kind (none: motion only, no cam)',
       choices=FOLLOWER_TYPES),
    _p('follower.base_radius', 'double', REQUIRED, 'Base circle radius of the cam surface (not '
       'with follower.type none)', unit='length_unit', minimum=0.0),
    _p('follower.roller_radius', 'double', 0.0, 'Roller radius (roller followers)',
       unit='length_unit', minimum=0.0),
    _p('follower.offset', 'double', 0.0, 'Offset e of a translating follower\'s line of travel '
       'from the cam centre (+x side positive)', unit='length_unit'),
    _p('follower.pivot_distance', 'double', 0.0, 'Distance from cam centre to the arm pivot '
       '(oscillating followers)', unit='length_unit', minimum=0.0),
    _p('follower.arm_length', 'double', 0.0, 'Pivot to roller centre (oscillating roller)',
       unit='length_unit', minimum=0.0),
    _p('follower.face_offset', 'double', 0.0, 'Distance of the flat face from the arm pivot '
       '(oscillating flat-faced)', unit='length_unit'),
    _p('follower.arm_turns_with_cam', 'bool', False, 'Oscillating arm turns in the cam\'s sense '
       'while it rises'),
    _p('follower.closure', 'string', 'force', 'What keeps the roller on the cam: a spring '
       '(force), a groove both flanks of which guide it, or a second, conjugate cam',
       choices=CLOSURES),
    _p('follower.groove_clearance', 'double', 0.0, 'Groove width minus the roller diameter '
       '(closure: groove)', unit='length_unit', minimum=0.0),
    _p('follower.conjugate_angle_deg', 'double', 0.0, 'Angle between the two arms of an '
       'oscillating conjugate follower (closure: conjugate)', unit='deg', minimum=0.0,
       maximum=180.0),
    _p('motion.laws', 'string_array', REQUIRED, 'Motion law of each segment'),
    _p('motion.start_deg', 'double_array', REQUIRED, 'Cam angle where each segment starts',
       unit='deg'),
    _p('motion.end_deg', 'double_array', REQUIRED, 'Cam angle where each segment ends',
       unit='deg'),
    _p('motion.start_position', 'double_array', REQUIRED, 'Follower position at each segment '
       'start (length_unit; deg of arm angle for oscillating followers)', unit='length_unit|deg'),
    _p('motion.end_position', 'double_array', REQUIRED, 'Follower position at each segment end',
       unit='length_unit|deg'),
    _p('motion.via_segment', 'integer_array', [], 'Segment index of each via point'),
    _p('motion.via_deg', 'double_array', [], 'Cam angle of each via point', unit='deg'),
    _p('motion.via_position', 'double_array', [], 'Follower position at each via point',
       unit='length_unit|deg'),
    _p('motion.scca_fractions', 'double_array', [], 'SCCA fractions b, c, d (sum 1) for scca '
       'segments'),
    _p('motion.table_u', 'double_array', [], 'Normalised abscissae 0..1 of the table law'),
    _p('motion.table_y', 'double_array', [], 'Normalised rise 0..1 of the table law'),
    _p('motion.table_counts', 'integer_array', [], 'How many of the table_u/table_y points '
       'belong to each table segment, in segment order (needed with two or more)'),
    *(_p(f'motion.{side}_{name}', 'double_array', [], f'Given {name} of each segment at its '
         f'{side} (.nan: automatic; see Motion tasks)', unit=f'length_unit|deg per deg{power}',
         automatic=True)
      for name, power in (('velocity', ''), ('acceleration', '^2'), ('jerk', '^3'))
      for side in ('start', 'end')),
    _p('motion.inflection', 'double_array', [], 'Fraction of each segment where the '
       'acceleration of a symmetric law changes sign (default 0.5)', minimum=1e-3,
       maximum=1.0 - 1e-3),
    _p('limits.pressure_angle_deg', 'double', 30.0, 'Largest allowed |pressure angle| on the '
       'rise (ds/dtheta >= 0; on the return too unless pressure_angle_return_deg is given)',
       unit='deg', minimum=1.0, maximum=89.0),
    _p('limits.pressure_angle_return_deg', 'double', 0.0, 'Largest allowed |pressure angle| on '
       'the return (ds/dtheta <= 0; 0: pressure_angle_deg)', unit='deg', minimum=0.0,
       maximum=89.0),
    _p('limits.min_radius_of_curvature', 'double', 0.0, 'Smallest allowed radius of curvature '
       'of the cam surface where convex', unit='length_unit', minimum=0.0),
    _p('limits.contact_stress', 'double', 0.0, 'Allowable Hertz peak contact pressure p0 '
       '(0: not checked)', unit='Pa', minimum=0.0, maximum=1e12),
    _p('limits.allow_velocity_jumps', 'bool', False, 'Let a design whose ds/dtheta jumps at a '
       'joint (an infinite acceleration) pass the verdict'),
    _p('dynamics.mass', 'double', 0.0, 'Moving mass of a translating follower train (0: no '
       'dynamics)', unit='kg', minimum=0.0, maximum=1e6),
    _p('dynamics.arm_inertia', 'double', 0.0, 'Inertia of an oscillating arm about its pivot '
       '(0: no dynamics)', unit='kg m^2', minimum=0.0, maximum=1e6),
    _p('dynamics.spring_rate', 'double', 0.0, 'Return spring rate (N m/rad for oscillating '
       'followers)', unit='N/m|N m/rad', minimum=0.0, maximum=1e12),
    _p('dynamics.spring_preload', 'double', 0.0, 'Spring force at s = 0 (N m for oscillating '
       'followers)', unit='N|N m', minimum=0.0, maximum=1e9),
    _p('dynamics.damping_ratio', 'double', 0.0, 'Damping as a fraction of critical, '
       '2 sqrt(k m)', minimum=0.0, maximum=100.0),
    _p('dynamics.external_force', 'double', 0.0, 'Constant load on the follower, positive '
       'toward the cam (N m for oscillating followers)', unit='N|N m', minimum=-1e9,
       maximum=1e9),
    _p('dynamics.jump_safety_factor', 'double', 1.5, 'Factor on the separating force for the '
       'needed spring preload', minimum=1.0, maximum=100.0),
    _p('dynamics.train_natural_frequency', 'double', 0.0, 'Lowest natural frequency of the '
       'follower train, cam side held (0: rigid train)', unit='Hz', minimum=0.0, maximum=1e6),
    _p('dynamics.train_stiffness', 'double', 0.0, 'Stiffness of the follower train, instead of '
       'its natural frequency (with dynamics.mass or arm_inertia)', unit='N/m|N m/rad',
       minimum=0.0, maximum=1e15),
    _p('dynamics.train_damping_ratio', 'double', 0.05, 'Damping ratio of the follower train',
       minimum=0.0, maximum=10.0),
    _p('dynamics.compensate', 'bool', False, 'Shape the cam so that the elastic train outputs '
       'the designed motion at cam_speed (polydyne; needs laws continuous to the 4th '
       'derivative)'),
    _p('contact.face_width', 'double', 0.0, 'Contact length along the camshaft (the narrower '
       'face); needed with dynamics', unit='length_unit', minimum=0.0),
    _p('contact.cam_modulus', 'double', STEEL_MODULUS, 'Young\'s modulus of the cam', unit='Pa',
       minimum=0.0, maximum=1e13),
    _p('contact.cam_poisson', 'double', STEEL_POISSON, 'Poisson\'s ratio of the cam, < 0.5',
       minimum=0.0, maximum=0.5),
    _p('contact.follower_modulus', 'double', STEEL_MODULUS, 'Young\'s modulus of the roller '
       'or face', unit='Pa', minimum=0.0, maximum=1e13),
    _p('contact.follower_poisson', 'double', STEEL_POISSON, 'Poisson\'s ratio of the roller or '
       'face, < 0.5', minimum=0.0, maximum=0.5),
    _p('contact.friction', 'double', 0.0, 'Sliding friction coefficient of a flat face',
       minimum=0.0, maximum=2.0),
    _p('output.sample_count', 'integer', 360, 'Samples per revolution on the profile topics',
       minimum=8, maximum=100000),
    _p('output.state_rate_hz', 'double', 50.0, 'Rate of the live state topic', unit='Hz',
       minimum=0.1, maximum=1000.0),
    _p('output.max_batch', 'integer', 10000, 'Most angles one evaluate call may carry',
       minimum=1, maximum=10000000),
    _p('recording.enabled', 'bool', False, 'Record the node\'s topics to MCAP from start-up'),
    _p('recording.directory', 'string', 'recordings', 'Folder of the MCAP recordings'),
    _p('recording.compression', 'string', 'zstd', 'Chunk compression', choices=COMPRESSIONS),
    _p('master.source', 'string', 'clock', 'Cam angle from the node\'s clock at cam_speed, or '
       'from a master axis on master.topic (electronic cam)', choices=('clock', 'topic')),
    _p('master.topic', 'string', '~/master', 'sensor_msgs/JointState topic of the master axis'),
    _p('master.joint', 'string', 'cam', 'Name of the master joint in the master messages'),
    _p('master.offset_deg', 'double', 0.0, 'Master position where the cam angle is 0',
       unit='deg', minimum=-1e9, maximum=1e9),
    _p('master.scaling', 'double', 1.0, 'Master travel per unit of cam angle', minimum=1e-6,
       maximum=1e6),
    _p('master.timeout', 'double', 0.5, 'Master silence after which motion commands stop',
       unit='s', minimum=1e-3, maximum=3600.0),
    _p('master.max_speed', 'double', 0.0, 'Master speed above which the node warns (0: no '
       'check)', unit='rad/s', minimum=0.0, maximum=1e6),
    _p('master.engage_on_start', 'bool', True, 'Engage the slave on the cam at start-up (else '
       'it waits for ~/engage)'),
    _p('master.engage_mode', 'string', 'ramp', 'How the slave joins the cam (~/engage, start-up, '
       'master return): at once, on a blend over engage_distance_deg, or at the next cycle '
       'start', choices=('immediate', 'ramp', 'next_cycle')),
    _p('master.engage_distance_deg', 'double', 30.0, 'Master travel of an engage ramp and of an '
       'offset change\'s blend', unit='deg', minimum=1e-3, maximum=1e6),
    _p('master.periodic', 'bool', True, 'Repeat the cam every cycle (false: a one-shot cam that '
       'holds its end position one master cycle after it starts)'),
    _p('master.velocity_window', 'double', 0.02, 'Master positions the speed estimate fits (0: '
       'the last three)', unit='s', minimum=0.0, maximum=10.0),
    _p('slave.state_topic', 'string', '', 'sensor_msgs/JointState of the driven axis (joint '
       'follower): its position is where a first engagement starts ("": none)'),
    _p('slave.offset', 'double', 0.0, 'Added to the scaled follower position',
       unit='length_unit|deg'),
    _p('slave.scaling', 'double', 1.0, 'Factor on the follower position', minimum=-1e3,
       maximum=1e3),
    _p('switches.names', 'string_array', [], 'Cam switch tracks: bit i of ~/switches is track i'),
    _p('switches.on_deg', 'double_array', [], 'Cam angle where each track switches on',
       unit='deg', minimum=0.0, maximum=360.0),
    _p('switches.off_deg', 'double_array', [], 'Cam angle where each track switches off (below '
       'on_deg: on through 0)', unit='deg', minimum=0.0, maximum=360.0),
    _p('switches.lead_time', 'double_array', [], 'Dead time each track is switched ahead of its '
       'angles, at the master speed (default 0)', unit='s', minimum=0.0, maximum=10.0),
    _p('switches.hysteresis_deg', 'double', 0.1, 'Cam angle a track lags when the master '
       'reverses, so that it never chatters at an edge', unit='deg', minimum=0.0, maximum=90.0),
    _p('command.interface', 'string', 'position', 'Command interface of the follower joint on '
       '~/commands', choices=('position', 'velocity')),
    _p('command.trajectory_horizon', 'double', 0.0, 'Look-ahead of ~/joint_trajectory (0: not '
       'published)', unit='s', minimum=0.0, maximum=60.0),
    _p('command.trajectory_points', 'integer', 10, 'Points over the trajectory horizon',
       minimum=1, maximum=1000),
)
SPECS: dict[str, ParameterSpec] = {spec.name: spec for spec in PARAMETERS}
#: rclpy's own node parameters: a params file may set them for the node (launch files often give
#: use_sim_time); they are type-checked here and are no part of the design.
ROS_NODE_PARAMETERS: dict[str, ParameterSpec] = {spec.name: spec for spec in (
    _p('use_sim_time', 'bool', False, 'Take the time from /clock'),
    _p('start_type_description_service', 'bool', True, 'Serve the node\'s type descriptions'),
)}


@dataclass(frozen=True)
class FollowerConfig:
    """Follower parameters in SI (m); irrelevant fields of a kind stay at their defaults."""

    type: str
    base_radius: float
    roller_radius: float
    offset: float
    pivot_distance: float
    arm_length: float
    face_offset: float
    arm_turns_with_cam: bool
    closure: str = 'force'  # form-closed: 'groove' or 'conjugate' (rollers only)
    groove_clearance: float = 0.0  # m
    conjugate_angle: float = 0.0  # rad, oscillating conjugate followers


@dataclass(frozen=True)
class MotionConfig:
    """Motion segments in SI: angles in rad; positions in m (rad for oscillating followers)."""

    laws: tuple[str, ...]
    start: tuple[float, ...]
    end: tuple[float, ...]
    start_position: tuple[float, ...]
    end_position: tuple[float, ...]
    via_segment: tuple[int, ...]
    via_angle: tuple[float, ...]
    via_position: tuple[float, ...]
    scca_fractions: tuple[float, ...]
    table_u: tuple[float, ...]
    table_y: tuple[float, ...]
    table_counts: tuple[int, ...]
    #: Given end derivatives per segment, per rad (nan: automatic): (ds, d2s, d3s) at start, end.
    begin: tuple[tuple[float, float, float], ...]
    finish: tuple[tuple[float, float, float], ...]
    inflection: tuple[float, ...]


@dataclass(frozen=True)
class CamConfig:
    """A whole config file, type-checked and converted to SI; the design layer builds the cam."""

    length_unit: str
    clockwise: bool
    cam_speed: float
    follower: FollowerConfig
    motion: MotionConfig
    pressure_angle_limit: float  # rad, the rise's (and the return's unless given)
    pressure_angle_return_limit: float  # rad
    min_radius_of_curvature: float
    allow_velocity_jumps: bool
    sample_count: int
    state_rate_hz: float
    max_batch: int
    recording_enabled: bool
    recording_directory: str
    recording_compression: str
    dynamics: DynamicsConfig | None  # None: the file gives no dynamics.mass / arm_inertia
    train: TrainConfig | None  # None: a rigid follower train (no natural frequency given)
    parameters: Mapping[str, Any]  # the flat values as written, for reports and recordings

    @property
    def oscillating(self) -> bool:
        """True for an oscillating follower: positions are arm angles (rad), not lengths."""
        return self.follower.type.startswith('oscillating')

    @property
    def motion_only(self) -> bool:
        """True for follower.type none: a motion (an electronic cam) with no cam to shape."""
        return self.follower.type == 'none'

    @property
    def angular(self) -> bool:
        """True when positions are angles (rad): an oscillating arm or a rotary slave (deg)."""
        return self.oscillating or self.length_unit == 'deg'

    @property
    def position_unit(self) -> str:
        """Return the SI unit of the follower position: 'm', or 'rad' for an angle."""
        return 'rad' if self.angular else 'm'

    @property
    def file_position_unit(self) -> tuple[str, float]:
        """Return the unit the file writes follower positions in and its factor from SI.

        The file's length_unit for translating followers, deg of arm angle for oscillating ones
        (and for a rotary slave, whose length_unit is deg).
        """
        if self.angular:
            return 'deg', 180.0 / math.pi
        return self.length_unit, 1.0 / LENGTH_UNITS[self.length_unit]


def _check_type(spec: ParameterSpec, value: Any) -> Any:
    """Return value if it has the spec's ROS type (as rclpy judges it), else raise."""
    scalar = spec.type.removesuffix('_array')
    python_type = {'double': float, 'integer': int, 'string': str, 'bool': bool}[scalar]

    def ok(item: Any) -> bool:
        is_bool_for_int = python_type is int and isinstance(item, bool)
        return isinstance(item, python_type) and not is_bool_for_int

    if isinstance(value, (list, tuple)) and len(value) > MAX_ARRAY_LENGTH:
        raise InvalidParameter(spec.name, value, f'must have at most {MAX_ARRAY_LENGTH} entries')
    if isinstance(value, str) and len(value) > MAX_STRING_LENGTH:
        raise InvalidParameter(spec.name, value,
                               f'must have at most {MAX_STRING_LENGTH} characters')
    if spec.type.endswith('_array'):
        if not isinstance(value, (list, tuple)) or not all(ok(item) for item in value):
            hint = ' (write 1.0, not 1)' if scalar == 'double' else ''
            raise InvalidParameter(spec.name, value, f'must be a list of {scalar}s{hint}')
        return tuple(value)
    if not ok(value):
        hint = ' (write 1.0, not 1)' if scalar == 'double' and isinstance(value, int) else ''
        article = 'an' if scalar == 'integer' else 'a'
        raise InvalidParameter(spec.name, value, f'must be {article} {scalar}{hint}')
    return value


def _check_range(spec: ParameterSpec, value: Any) -> None:
    if spec.choices and value not in spec.choices:
        hint = did_you_mean(value, spec.choices) if isinstance(value, str) else ''
        raise InvalidParameter(spec.name, value,
                               'must be one of ' + ', '.join(spec.choices) + hint)
    items = value if isinstance(value, tuple) else (value,)
    written = list(value) if isinstance(value, tuple) else value  # quoted as the file gives it
    for item in items:
        if isinstance(item, float) and not math.isfinite(item) and not (
                spec.automatic and math.isnan(item)):
            raise InvalidParameter(spec.name, written, 'must be finite' + (
                ' (or .nan: automatic)' if spec.automatic else ''))
        if spec.minimum is not None and isinstance(item, (int, float)) and item < spec.minimum:
            raise InvalidParameter(spec.name, written, f'must be >= {spec.minimum:g}')
        if spec.maximum is not None and isinstance(item, (int, float)) and item > spec.maximum:
            raise InvalidParameter(spec.name, written, f'must be <= {spec.maximum:g}')


def check_parameter(name: str, value: Any) -> Any:
    """Type- and range-check one parameter value; return it (arrays as tuples)."""
    spec = SPECS.get(name)
    if spec is None:
        raise InvalidParameter(name, value, f'is not a cam parameter{did_you_mean(name, SPECS)}')
    checked = _check_type(spec, value)
    _check_range(spec, checked)
    return checked


def parse_parameters(flat: Mapping[str, Any]) -> CamConfig:
    """Check flat parameter values against :data:`PARAMETERS` and convert them to SI."""
    values: dict[str, Any] = {}
    for name, value in flat.items():
        if name in ROS_NODE_PARAMETERS:
            _check_type(ROS_NODE_PARAMETERS[name], value)
        else:
            values[name] = check_parameter(name, value)
    for spec in PARAMETERS:
        if spec.name not in values:
            if spec.default is REQUIRED and not (spec.name.startswith(CAM_ONLY)
                                                 and values.get('follower.type') == 'none'):
                raise InvalidParameter(spec.name, None, f'is required ({spec.rule})')
            values[spec.name] = check_parameter(spec.name, _default(spec))
    _check_motion_only(values)
    metre = UNITS[values['length_unit']]
    oscillating = values['follower.type'].startswith('oscillating')
    _check_magnitudes(values, metre, oscillating)
    position_scale = math.radians(1.0) if oscillating else metre

    def scaled(name: str, scale: float) -> tuple[float, ...]:
        return tuple(item * scale for item in values[name])

    def length(name: str) -> float:
        return float(values[f'follower.{name}'] * metre)

    follower = FollowerConfig(
        type=values['follower.type'], base_radius=length('base_radius'),
        roller_radius=length('roller_radius'), offset=length('offset'),
        pivot_distance=length('pivot_distance'), arm_length=length('arm_length'),
        face_offset=length('face_offset'),
        arm_turns_with_cam=values['follower.arm_turns_with_cam'],
        **_closure(values, metre))
    radian = math.radians(1.0)
    motion = MotionConfig(
        laws=values['motion.laws'],
        start=scaled('motion.start_deg', radian),
        end=scaled('motion.end_deg', radian),
        start_position=scaled('motion.start_position', position_scale),
        end_position=scaled('motion.end_position', position_scale),
        via_segment=values['motion.via_segment'],
        via_angle=scaled('motion.via_deg', radian),
        via_position=scaled('motion.via_position', position_scale),
        scca_fractions=values['motion.scca_fractions'],
        table_u=values['motion.table_u'],
        table_y=values['motion.table_y'],
        table_counts=values['motion.table_counts'],
        begin=_end_derivatives(values, 'start', position_scale),
        finish=_end_derivatives(values, 'end', position_scale),
        inflection=values['motion.inflection'] or (0.5,) * len(values['motion.laws']),
    )
    _check_parallel(values, ('motion.laws', 'motion.start_deg', 'motion.end_deg',
                             'motion.start_position', 'motion.end_position'))
    _check_parallel(values, ('motion.laws', *(name for name in TASK_ARRAYS if values[name])))
    _check_parallel(values, ('motion.via_segment', 'motion.via_deg', 'motion.via_position'))
    _check_parallel(values, ('motion.table_u', 'motion.table_y'))
    _check_switches(values)
    return CamConfig(
        length_unit=values['length_unit'],
        clockwise=values['rotation'] == 'clockwise',
        cam_speed=values['cam_speed'],
        follower=follower,
        motion=motion,
        pressure_angle_limit=math.radians(values['limits.pressure_angle_deg']),
        pressure_angle_return_limit=math.radians(values['limits.pressure_angle_return_deg']
                                                 or values['limits.pressure_angle_deg']),
        min_radius_of_curvature=values['limits.min_radius_of_curvature'] * metre,
        allow_velocity_jumps=values['limits.allow_velocity_jumps'],
        sample_count=values['output.sample_count'],
        state_rate_hz=values['output.state_rate_hz'],
        max_batch=values['output.max_batch'],
        recording_enabled=values['recording.enabled'],
        recording_directory=values['recording.directory'],
        recording_compression=values['recording.compression'],
        dynamics=parse_dynamics(values, metre, values['follower.type']),
        train=parse_train(values, *((values['dynamics.arm_inertia'], 'dynamics.arm_inertia')
                                    if oscillating else (values['dynamics.mass'],
                                                         'dynamics.mass'))),
        parameters=dict(values),
    )


def _default(spec: ParameterSpec) -> Any:
    """Return a parameter's default; 0.0 for a required one a motion-only design leaves out."""
    return 0.0 if spec.default is REQUIRED else spec.default


def _check_motion_only(values: Mapping[str, Any]) -> None:
    """Refuse cam parameters in a motion-only design, and deg as a length unit elsewhere."""
    if values['follower.type'] != 'none':
        if values['length_unit'] == 'deg':
            raise InvalidParameter('length_unit', 'deg', 'a rotary slave in deg is a motion-only '
                                   'design: needs follower.type none')
        return
    for spec in PARAMETERS:
        if spec.name.startswith(CAM_ONLY) and spec.name != 'follower.type' \
                and values[spec.name] != _default(spec):
            raise InvalidParameter(spec.name, values[spec.name], 'follower.type none is a '
                                   'motion-only design (no cam, no follower train): leave it '
                                   'out')


def _end_derivatives(values: Mapping[str, Any], side: str,
                     position_scale: float) -> tuple[tuple[float, float, float], ...]:
    """Return (ds, d2s, d3s) per rad at each segment's side from the per-deg arrays (nan kept)."""
    per_degree = 180.0 / math.pi
    columns = [values[f'motion.{side}_{name}'] or (math.nan,) * len(values['motion.laws'])
               for name in ('velocity', 'acceleration', 'jerk')]
    return tuple(tuple(value * position_scale * per_degree ** order
                       for order, value in enumerate(row, 1))  # type: ignore[misc]
                 for row in zip(*columns))


def _closure(values: Mapping[str, Any], metre: float) -> dict[str, Any]:
    """Return the follower's closure fields after the rules that span parameters.

    A form-closed cam guides a roller from both sides, so it takes no return spring.
    """
    closure = values['follower.closure']
    if closure != 'force':
        if not values['follower.type'].endswith('roller'):
            raise InvalidParameter('follower.closure', closure,
                                   f'needs a roller follower, not {values["follower.type"]}')
        for spring in ('dynamics.spring_rate', 'dynamics.spring_preload'):
            if values[spring]:
                raise InvalidParameter(spring, values[spring], f'a {closure} cam needs no '
                                       'return spring (the other flank or cam closes it): '
                                       'use 0.0')
    if values['follower.groove_clearance'] and closure != 'groove':
        raise InvalidParameter('follower.groove_clearance', values['follower.groove_clearance'],
                               'applies to follower.closure: groove only')
    if values['follower.conjugate_angle_deg'] and not (
            closure == 'conjugate' and values['follower.type'] == 'oscillating_roller'):
        raise InvalidParameter('follower.conjugate_angle_deg',
                               values['follower.conjugate_angle_deg'],
                               'applies to an oscillating_roller with follower.closure: '
                               'conjugate only')
    return {'closure': closure,
            'groove_clearance': values['follower.groove_clearance'] * metre,
            'conjugate_angle': math.radians(values['follower.conjugate_angle_deg'])}


def _check_magnitudes(values: Mapping[str, Any], metre: float, oscillating: bool) -> None:
    """Bound every length and follower position (the specs cannot: their unit varies)."""
    length_bound = (MAX_LENGTH_M / metre, f'{MAX_LENGTH_M / metre:g} {values["length_unit"]}')
    if values['length_unit'] == 'deg':
        length_bound = (MAX_ROTARY_DEG, f'{MAX_ROTARY_DEG:g} deg')
    bounds = {'length_unit': length_bound,
              'length_unit|deg': ((MAX_ARM_ANGLE_DEG, f'{MAX_ARM_ANGLE_DEG:g} deg') if oscillating
                                  else length_bound)}
    for spec in PARAMETERS:
        if spec.unit in bounds:
            value, (limit, text) = values[spec.name], bounds[spec.unit]
            items = value if isinstance(value, tuple) else (value,)
            if any(abs(item) > limit for item in items):
                raise InvalidParameter(spec.name, list(items) if items is value else value,
                                       f'must not exceed {text} in magnitude')


def _check_parallel(values: Mapping[str, Any], names: tuple[str, ...]) -> None:
    """Raise unless the parallel arrays named have one length."""
    length = len(values[names[0]])
    for name in names[1:]:
        if len(values[name]) != length:
            raise InvalidParameter(name, list(values[name]),
                                   f'must have {length} entries, one per entry of {names[0]}')


def _check_switches(values: Mapping[str, Any]) -> None:
    """Check the cam switch tracks: one entry each, at most 32, named once, on != off."""
    names = values['switches.names']
    _check_parallel(values, ('switches.names', 'switches.on_deg', 'switches.off_deg',
                             *(('switches.lead_time',) if values['switches.lead_time'] else ())))
    if len(names) > MAX_SWITCH_TRACKS:
        raise InvalidParameter('switches.names', list(names),
                               f'must have at most {MAX_SWITCH_TRACKS} tracks (one bit each)')
    for index, name in enumerate(names):
        if not name.strip() or name in names[:index]:
            raise InvalidParameter(f'switches.names[{index}]', name,
                                   'must be a name, given once')
    for index, (on, off) in enumerate(zip(values['switches.on_deg'], values['switches.off_deg'])):
        if math.isclose(math.fmod(on, 360.0), math.fmod(off, 360.0), abs_tol=1e-12):
            raise InvalidParameter(f'switches.off_deg[{index}]', off,
                                   f'must differ from switches.on_deg[{index}] ({on:g} deg)')


def load_config(path: str | Path) -> CamConfig:
    """Read and check a cam parameters file (the CLI's and the core's entry point)."""
    return parse_parameters(read_parameters_file(path))
