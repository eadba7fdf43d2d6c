"""Every parameter of the cam config format, once: ROS type, default, unit and rule.

The node declares exactly these and the core checks each value against its spec here
(:func:`check_parameter`); the rules that span parameters are the schema's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from ..dynamics.contact import STEEL_MODULUS, STEEL_POISSON
from ..errors import did_you_mean, InvalidParameter
from .params_file import MAX_ARRAY_LENGTH, MAX_STRING_LENGTH

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
#: Smallest positive size (m) of a length that must not be negative: a micrometre, below any
#: meaning for a cam (0 still means none where a parameter allows it).
LEAST_LENGTH_M = 1e-6
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
    #: Smallest meaningful positive value (m for a length): one in (0, least) is refused, as
    #: below any physical meaning and a source of overflow.
    least: float | None = None

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
        if self.least is not None:
            metres = ' m' if self.unit == 'length_unit' else ''
            parts.append(f'0 or at least {self.least:g}{metres}')
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
       'with follower.type none)', unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('follower.roller_radius', 'double', 0.0, 'Roller radius (roller followers)',
       unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('follower.offset', 'double', 0.0, 'Offset e of a translating follower\'s line of travel '
       'from the cam centre (+x side positive)', unit='length_unit'),
    _p('follower.pivot_distance', 'double', 0.0, 'Distance from cam centre to the arm pivot '
       '(oscillating followers)', unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('follower.arm_length', 'double', 0.0, 'Pivot to roller centre (oscillating roller)',
       unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('follower.face_offset', 'double', 0.0, 'Distance of the flat face from the arm pivot '
       '(oscillating flat-faced)', unit='length_unit'),
    _p('follower.arm_turns_with_cam', 'bool', False, 'Oscillating arm turns in the cam\'s sense '
       'while it rises'),
    _p('follower.closure', 'string', 'force', 'What keeps the roller on the cam: a spring '
       '(force), a groove both flanks of which guide it, or a second, conjugate cam',
       choices=CLOSURES),
    _p('follower.groove_clearance', 'double', 0.0, 'Groove width minus the roller diameter '
       '(closure: groove)', unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
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
       maximum=89.0, least=1.0),
    _p('limits.min_radius_of_curvature', 'double', 0.0, 'Smallest allowed radius of curvature '
       'of the cam surface where convex', unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('limits.contact_stress', 'double', 0.0, 'Allowable Hertz peak contact pressure p0 '
       '(0: not checked)', unit='Pa', minimum=0.0, maximum=1e12),
    _p('limits.allow_velocity_jumps', 'bool', False, 'Let a design whose ds/dtheta jumps at a '
       'joint (an infinite acceleration) pass the verdict'),
    _p('dynamics.mass', 'double', 0.0, 'Moving mass of a translating follower train (0: no '
       'dynamics)', unit='kg', minimum=0.0, maximum=1e6, least=1e-6),
    _p('dynamics.arm_inertia', 'double', 0.0, 'Inertia of an oscillating arm about its pivot '
       '(0: no dynamics)', unit='kg m^2', minimum=0.0, maximum=1e6, least=1e-9),
    _p('dynamics.spring_rate', 'double', 0.0, 'Return spring rate (N m/rad for oscillating '
       'followers)', unit='N/m|N m/rad', minimum=0.0, maximum=1e12),
    _p('dynamics.spring_preload', 'double', 0.0, 'Spring force at s = 0 (N m for oscillating '
       'followers)', unit='N|N m', minimum=0.0, maximum=1e9),
    _p('dynamics.damping_ratio', 'double', 0.0, 'Damping as a fraction of critical, '
       '2 sqrt(k m)', minimum=0.0, maximum=100.0, least=1e-6),
    _p('dynamics.external_force', 'double', 0.0, 'Constant load on the follower, positive '
       'toward the cam (N m for oscillating followers)', unit='N|N m', minimum=-1e9,
       maximum=1e9),
    _p('dynamics.jump_safety_factor', 'double', 1.5, 'Factor on the separating force for the '
       'needed spring preload', minimum=1.0, maximum=100.0),
    _p('dynamics.train_natural_frequency', 'double', 0.0, 'Lowest natural frequency of the '
       'follower train, cam side held (0: rigid train)', unit='Hz', minimum=0.0, maximum=1e6,
       least=1e-3),
    _p('dynamics.train_stiffness', 'double', 0.0, 'Stiffness of the follower train, instead of '
       'its natural frequency (with dynamics.mass or arm_inertia)', unit='N/m|N m/rad',
       minimum=0.0, maximum=1e15),
    _p('dynamics.train_damping_ratio', 'double', 0.05, 'Damping ratio of the follower train',
       minimum=0.0, maximum=10.0),
    _p('dynamics.compensate', 'bool', False, 'Shape the cam so that the elastic train outputs '
       'the designed motion at cam_speed (polydyne; needs laws continuous to the 4th '
       'derivative)'),
    _p('contact.face_width', 'double', 0.0, 'Contact length along the camshaft (the narrower '
       'face); needed with dynamics', unit='length_unit', minimum=0.0, least=LEAST_LENGTH_M),
    _p('contact.cam_modulus', 'double', STEEL_MODULUS, 'Young\'s modulus of the cam', unit='Pa',
       minimum=0.0, maximum=1e13, least=1e5),
    _p('contact.cam_poisson', 'double', STEEL_POISSON, 'Poisson\'s ratio of the cam, < 0.5',
       minimum=0.0, maximum=0.5),
    _p('contact.follower_modulus', 'double', STEEL_MODULUS, 'Young\'s modulus of the roller '
       'or face', unit='Pa', minimum=0.0, maximum=1e13, least=1e5),
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
    _p('master.engage_mode', 'string', 'ramp', 'How the slave joins the cam (~/engage, '
       'start-up): at once, by a move in time within its limits, or at the next cycle start',
       choices=('immediate', 'ramp', 'next_cycle')),
    _p('master.engage_distance_deg', 'double', 30.0, 'Master travel of the line shaft\'s stop '
       'for an axis without limits', unit='deg',
       minimum=1e-3, maximum=1e6),
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
    _p('slave.max_velocity', 'double', 0.0, 'Fastest the axis may be commanded: moves, stops '
       'and catch-ups stay within it (0: not limited)',
       unit='length_unit|deg per s', minimum=0.0, maximum=1e9),
    _p('slave.max_acceleration', 'double', 0.0, 'Largest acceleration the axis may be commanded '
       '(0: not limited)', unit='length_unit|deg per s^2', minimum=0.0, maximum=1e12),
    _p('slave.max_jerk', 'double', 0.0, 'Largest jerk of a move off the cam (engagement, '
       'return after a fault; 0: not limited)', unit='length_unit|deg per s^3', minimum=0.0,
       maximum=1e15),
    _p('slave.following_error_limit', 'double', 0.0, 'Largest |command - reported position| '
       'on slave.state_topic before the machine holds (0: not checked)',
       unit='length_unit|deg', minimum=0.0, maximum=1e9),
    _p('slave.following_error_time', 'double', 0.0, 'How long the following error may stay over '
       'its limit before the machine holds (0: at once)', unit='s', minimum=0.0, maximum=3600.0),
    _p('slave.direction', 'string', 'any', 'Way the axis may move: any, or only positive or '
       'negative (a knife or feed roll that must not turn back)',
       choices=('any', 'positive', 'negative')),
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
    _p('autostart', 'bool', True, 'cam_node: configure and activate the managed node at '
       'start-up (false: it waits unconfigured for ~/change_state)'),
)}


def check_type(spec: ParameterSpec, value: Any) -> Any:
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
        if spec.least is not None and spec.unit != 'length_unit' and 0.0 < item < spec.least:
            raise InvalidParameter(spec.name, written, least_rule(f'{spec.least:g}'))


def least_rule(bound: str) -> str:
    """Say the rule of a value below its smallest meaningful positive value."""
    return f'must be 0 or at least {bound} (smaller is below any physical meaning)'


def check_parameter(name: str, value: Any, specs: Mapping[str, ParameterSpec] = SPECS) -> Any:
    """Type- and range-check one parameter value (of specs); return it (arrays as tuples)."""
    spec = specs.get(name)
    if spec is None:
        raise InvalidParameter(name, value, f'is not a cam parameter{did_you_mean(name, specs)}')
    checked = check_type(spec, value)
    _check_range(spec, checked)
    return checked
