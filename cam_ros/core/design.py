"""A whole cam design: motion program + follower + speed + limits, built from a CamConfig.

This is what the node serves and the CLI reports on: one immutable object, built and validated
once, evaluated for any array of cam angles.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Callable, Mapping

import numpy as np
import numpy.typing as npt

from .config import CamConfig, MotionConfig
from .dynamics import DynamicsValues, FollowerDynamics
from .errors import InvalidParameter
from .geometry import (CamGeometry, Follower, GeometryCheck, OscillatingFlat, OscillatingRoller,
                       TranslatingFlat, TranslatingRoller, cam_geometry, check_geometry,
                       contact_measures)
from .laws import MotionLaw, make_law
from .program import MotionProgram, Segment

TWO_PI = 2.0 * math.pi
#: Samples per revolution for the design checks (pressure angle, curvature, undercut).
CHECK_SAMPLES = 7200
#: Boundary conditions of the 3-4-5 law (u, derivative order, value) that a polynomial segment
#: with via points keeps: rest to rest with zero acceleration at both ends.
REST_TO_REST = ((0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0),
                (1.0, 0, 1.0), (1.0, 1, 0.0), (1.0, 2, 0.0))
SEGMENT_FIELDS = {'start': 'motion.start_deg', 'end': 'motion.end_deg',
                  's_start': 'motion.start_position', 's_end': 'motion.end_position',
                  'law': 'motion.laws'}


@dataclass(frozen=True, eq=False)
class CamState:
    """The cam evaluated at an array of angles (SI; derivatives per rad and per s)."""

    angle: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray
    d3s: np.ndarray
    pressure_angle: np.ndarray
    radius_of_curvature: np.ndarray
    dynamics: DynamicsValues | None = None  # None: the design has no dynamics


@dataclass(frozen=True, eq=False)
class CamDesign:
    """One validated cam: evaluate it anywhere, sample its profile, check it against limits."""

    config: CamConfig
    program: MotionProgram
    follower: Follower

    @property
    def clockwise(self) -> bool:
        """True for a cam turning clockwise seen from +z."""
        return self.config.clockwise

    def evaluate(self, angles: npt.ArrayLike) -> CamState:
        """Evaluate follower motion and cam geometry at cam angles (rad, taken modulo 2 pi)."""
        theta = np.mod(np.asarray(angles, dtype=float), TWO_PI)
        motion = self.program.evaluate(theta)
        timed = motion.at_speed(self.config.cam_speed)
        pressure_angle, radius = contact_measures(self.follower, theta, motion.s, motion.ds,
                                                  motion.d2s, clockwise=self.clockwise)
        forces = None if self.dynamics is None else self.dynamics.values(
            motion.s, motion.ds, motion.d2s, pressure_angle, radius)
        return CamState(theta, timed.position, timed.velocity, timed.acceleration, timed.jerk,
                        motion.ds, motion.d2s, motion.d3s, pressure_angle, radius, forces)

    @cached_property
    def dynamics(self) -> FollowerDynamics | None:
        """Return the follower-train model at the cam speed, None without dynamics."""
        config = self.config.dynamics
        return None if config is None else FollowerDynamics(config, self.follower,
                                                            self.config.cam_speed)

    def profile(self, count: int) -> CamState:
        """Evaluate the cam at count equally spaced angles over one revolution from 0."""
        return self.evaluate(np.linspace(0.0, TWO_PI, count, endpoint=False))

    def geometry(self, count: int = CHECK_SAMPLES) -> CamGeometry:
        """Return the cam's geometry (pitch curve, surface, ...) at count angles from 0."""
        theta = np.linspace(0.0, TWO_PI, count, endpoint=False)
        motion = self.program.evaluate(theta)
        return cam_geometry(self.follower, theta, motion.s, motion.ds, motion.d2s,
                            clockwise=self.clockwise)

    @cached_property
    def check(self) -> GeometryCheck:
        """Check the design against its limits: extremes refined from a dense sampling."""
        return check_geometry(self.geometry(), max_pressure_angle=self.config.pressure_angle_limit,
                              min_radius=self.config.min_radius_of_curvature,
                              program=self.program)

    def warnings(self) -> list[str]:
        """Say, once, what a designer must know: limits broken, undercut, discontinuities."""
        check, notes = self.check, []
        if check.pressure_angle_ok is False:
            notes.append(f'pressure angle reaches {math.degrees(check.max_pressure_angle):.2f} deg'
                         f' at {math.degrees(check.max_pressure_angle_at):.1f} deg, over the '
                         f'limit of {math.degrees(self.config.pressure_angle_limit):.1f} deg')
        if check.radius_ok is False:
            notes.append(f'radius of curvature falls to {check.min_radius:.6g} m at '
                         f'{math.degrees(check.min_radius_at):.1f} deg, under the limit of '
                         f'{self.config.min_radius_of_curvature:.6g} m')
        if check.undercut:
            where = np.degrees(check.undercut_angles)
            notes.append(f'the cam surface is undercut between {where.min():.1f} and '
                         f'{where.max():.1f} deg')
        unit = 'rad' if self.config.follower.type.startswith('oscillating') else 'm'
        for jump in self.program.continuity_report():
            if jump.order <= 2:
                name = ('s', 'ds/dtheta', 'd2s/dtheta2')[jump.order]
                notes.append(f'{name} jumps by {jump.jump:.6g} {unit}/rad^{jump.order} at '
                             f'{math.degrees(jump.angle):.2f} deg')
        return notes

    def summary(self) -> str:
        """Describe the design in one line for logs."""
        laws = ', '.join(f'{s.law.name} {math.degrees(s.start):g}-{math.degrees(s.end):g} deg'
                         for s in self.program.segments)
        check = self.check
        return (f'{self.config.follower.type} follower, '
                f'{"clockwise" if self.clockwise else "counter-clockwise"} cam at '
                f'{self.config.cam_speed:g} rad/s: {laws}; max |pressure angle| '
                f'{math.degrees(check.max_pressure_angle):.2f} deg, min radius of curvature '
                f'{check.min_radius:.6g} m')


def check_angles(angles: np.ndarray, max_batch: int) -> str | None:
    """Return why a batch of requested angles cannot be evaluated, or None if it can."""
    if angles.size == 0:
        return 'angles is empty: give at least one cam angle (rad)'
    if angles.size > max_batch:
        return (f'angles has {angles.size} entries: more than output.max_batch = {max_batch}; '
                'split the request')
    finite = np.isfinite(angles)
    if not finite.all():
        index = int(np.argmin(finite))
        return f'angles[{index}] = {float(angles[index])!r}: must be a finite angle (rad)'
    return None


def build_follower(config: CamConfig) -> Follower:
    """Build the configured follower; errors name the follower.* parameter."""
    f = config.follower
    builders: dict[str, Callable[[], Follower]] = {
        'translating_roller': lambda: TranslatingRoller(f.base_radius, f.roller_radius, f.offset),
        'translating_flat': lambda: TranslatingFlat(f.base_radius),
        'oscillating_roller': lambda: OscillatingRoller(f.base_radius, f.roller_radius,
                                                        f.pivot_distance, f.arm_length,
                                                        f.arm_turns_with_cam),
        'oscillating_flat': lambda: OscillatingFlat(f.base_radius, f.pivot_distance,
                                                    f.face_offset, f.arm_turns_with_cam),
    }
    try:
        return builders[f.type]()
    except InvalidParameter as err:
        name = f'follower.{err.parameter}'
        written = config.parameters.get(name, err.value)
        raise InvalidParameter(name, written, f'{err.rule} (the file gives {config.length_unit}; '
                                              f'{err.value!r} m in SI)') from err


def build_law(motion: MotionConfig, index: int) -> MotionLaw:
    """Build segment index's law with the parameters the config gives for it."""
    name = motion.laws[index]
    params: dict[str, object] = {}
    vias = [(angle, position) for segment, angle, position
            in zip(motion.via_segment, motion.via_angle, motion.via_position) if segment == index]
    start, span = motion.start[index], motion.end[index] - motion.start[index]
    stroke = motion.end_position[index] - motion.start_position[index]
    normalised = [((angle - start) / span, (position - motion.start_position[index]) / stroke)
                  for angle, position in vias] if span and stroke else []
    if vias and name not in ('via_point', 'polynomial'):
        raise InvalidParameter(f'motion.via_segment[{index}]', index,
                               f'law {name} takes no via points (via_point and polynomial do)')
    if name == 'via_point':
        if len(normalised) != 1:
            raise InvalidParameter(f'motion.laws[{index}]', name,
                                   f'needs exactly one via point (motion.via_segment has '
                                   f'{len(vias)} entries equal to {index})')
        params = {'u_via': normalised[0][0], 'y_via': normalised[0][1]}
    elif name == 'polynomial':
        params = {'conditions': [*REST_TO_REST, *((u, 0, y) for u, y in normalised)]}
    elif name == 'scca':
        b, c, d = (motion.scca_fractions + (math.nan,) * 3)[:3]
        params = {'b': b, 'c': c, 'd': d}
    elif name == 'table':
        params = {'u': motion.table_u, 'y': motion.table_y}
    return make_law(name, **params)


def build_program(motion: MotionConfig, written: Mapping[str, Any]) -> MotionProgram:
    """Build the motion program; errors name the motion.* parameter (as written) and index."""
    for index, segment in enumerate(motion.via_segment):
        if not 0 <= segment < len(motion.laws):
            raise InvalidParameter(f'motion.via_segment[{index}]', segment,
                                   f'must be a segment index in [0, {len(motion.laws) - 1}]')
    segments = []
    for index in range(len(motion.laws)):
        try:
            law = build_law(motion, index)
        except InvalidParameter as err:
            if err.parameter.startswith('motion.'):
                raise
            raise InvalidParameter(f'motion.laws[{index}] ({motion.laws[index]}): '
                                   f'{err.parameter}', err.value, err.rule) from err
        segments.append(Segment(law, motion.start[index], motion.end[index],
                                motion.start_position[index], motion.end_position[index]))
    try:
        return MotionProgram(tuple(segments))
    except InvalidParameter as err:
        raise _in_config_terms(err, written) from err


def _in_config_terms(err: InvalidParameter, written: Mapping[str, Any]) -> InvalidParameter:
    """Restate a program error ('segments[2].end') with the config's names and values."""
    def rename(match: re.Match) -> str:
        field = SEGMENT_FIELDS.get(match.group(2))
        return f'{field}[{match.group(1)}]' if field else match.group(0)

    pattern = r'segments\[(\d+)\]\.(\w+)'
    match = re.fullmatch(pattern, err.parameter)
    if not match or match.group(2) not in SEGMENT_FIELDS:
        return InvalidParameter(f'motion ({err.parameter})', err.value, err.rule)
    field, index = SEGMENT_FIELDS[match.group(2)], int(match.group(1))
    values = written.get(field)
    value = values[index] if isinstance(values, (list, tuple)) else err.value
    return InvalidParameter(f'{field}[{index}]', value,
                            f'{re.sub(pattern, rename, err.rule)} [in SI: {err.value!r}]')


def build_design(config: CamConfig) -> CamDesign:
    """Build and validate the whole design; raises InvalidParameter naming the parameter."""
    program = build_program(config.motion, config.parameters)
    follower = build_follower(config)
    design = CamDesign(config, program, follower)
    try:
        design.geometry()  # the follower must be able to follow the motion everywhere
    except InvalidParameter as err:
        raise _at_cam_angle(err, program) from err
    return design


def _at_cam_angle(err: InvalidParameter, program: MotionProgram) -> InvalidParameter:
    """Restate a geometry error at a check sample ('s[2812]') as the segment and cam angle."""
    match = re.fullmatch(r'(\w+)\[(\d+)\]', err.parameter)
    if not match:
        return err
    angle = int(match.group(2)) * TWO_PI / CHECK_SAMPLES
    index = program.segment_at(angle)
    return InvalidParameter(f'motion.laws[{index}] ({program.segments[index].law.name}): '
                            f'{match.group(1)} at {math.degrees(angle):.2f} deg', err.value,
                            err.rule)
