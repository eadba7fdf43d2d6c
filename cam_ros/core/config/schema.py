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

from ..dynamics.follower import DynamicsConfig, parse_dynamics
from ..dynamics.train import parse_train, TrainConfig
from ..errors import InvalidParameter
from ..motion.laws import make_law
# The parameters one by one live in parameters, the file side of the format (safe YAML reading,
# node sections) in params_file; the rules across the dynamics.* parameters in dynamics_rules.
from .dynamics_rules import check_dynamics
from .parameters import (CAM_ONLY, check_parameter, check_type, least_rule, LENGTH_UNITS,
                         MAX_ARM_ANGLE_DEG, MAX_LENGTH_M, MAX_ROTARY_DEG, MAX_SWITCH_TRACKS,
                         PARAMETERS, ParameterSpec, REQUIRED, ROS_NODE_PARAMETERS, TASK_ARRAYS,
                         UNITS)
from .params_file import read_parameters_file


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
        return angular_positions(self.follower.type, self.length_unit)

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


def parse_parameters(flat: Mapping[str, Any]) -> CamConfig:
    """Check flat parameter values against :data:`PARAMETERS` and convert them to SI."""
    values: dict[str, Any] = {}
    for name, value in flat.items():
        if name in ROS_NODE_PARAMETERS:
            check_type(ROS_NODE_PARAMETERS[name], value)
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
    inertia_name = check_dynamics(values, oscillating)
    _check_scca(values)
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
    check_switches(values)
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
        train=parse_train(values, values[inertia_name]),
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
    """Bound every length and follower position (the specs cannot: their unit varies).

    A length with a smallest meaningful size (spec.least, m) is 0 or at least that.
    """
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
        if spec.least is not None and spec.unit == 'length_unit' \
                and 0.0 < values[spec.name] < spec.least / metre:
            raise InvalidParameter(spec.name, values[spec.name], least_rule(
                f'{spec.least / metre:g} {values["length_unit"]}'))


def _check_scca(values: Mapping[str, Any]) -> None:
    """Check motion.scca_fractions given with no scca segment as the scca law would: three
    fractions b, c, d in [0, 1] adding up to 1 (an scca segment's law checks them, naming it)."""
    fractions = values['motion.scca_fractions']
    if not fractions or 'scca' in values['motion.laws']:
        return
    rule = 'must be 3 fractions b, c, d in [0, 1] that add up to 1'
    if len(fractions) != 3:
        raise InvalidParameter('motion.scca_fractions', list(fractions), rule)
    try:
        make_law('scca', **dict(zip('bcd', fractions)))
    except InvalidParameter as err:
        raise InvalidParameter('motion.scca_fractions', list(fractions),
                               f'{rule} ({err.parameter} = {err.value!r}: {err.rule})') from err


def _check_parallel(values: Mapping[str, Any], names: tuple[str, ...]) -> None:
    """Raise unless the parallel arrays named have one length."""
    length = len(values[names[0]])
    for name in names[1:]:
        if len(values[name]) != length:
            raise InvalidParameter(name, list(values[name]),
                                   f'must have {length} entries, one per entry of {names[0]}')


def check_switches(values: Mapping[str, Any]) -> None:
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


def angular_positions(follower_type: str, length_unit: str) -> bool:
    """Say whether a follower's positions are angles: an oscillating arm or a rotary slave."""
    return follower_type.startswith('oscillating') or length_unit == 'deg'


def load_config(path: str | Path) -> CamConfig:
    """Read and check a cam parameters file (the CLI's and the core's entry point)."""
    return parse_parameters(read_parameters_file(path))
