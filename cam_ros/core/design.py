"""A whole cam design: motion program + follower + speed + limits, built from a CamConfig.

This is what the node serves and the CLI reports on: one immutable object, built and validated
once, evaluated for any array of cam angles.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Callable, Mapping, cast

import numpy as np
import numpy.typing as npt

from .config.schema import LENGTH_UNITS, CamConfig, MotionConfig
from .dynamics.follower import DynamicsValues, FollowerDynamics
from .dynamics.polydyne import compensated_program
from .dynamics.report import DynamicsReport, dynamics_report
from .dynamics.vibration import RIGID_RATIO, vibration_report, VibrationReport
from .errors import InvalidParameter, quote
from .extremes import CHECK_SAMPLES
from .geometry.followers import (Follower, OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                 TranslatingRoller)
from .geometry.cam_geometry import CamGeometry, cam_geometry, contact_measures
from .geometry.check import GeometryCheck, check_geometry
from .motion.laws import MotionLaw, make_law
from .motion.program import Discontinuity, MotionProgram, Segment

TWO_PI = 2.0 * math.pi
#: Added to a velocity jump's warning: it fails the verdict unless the config allows it.
_VELOCITY_JUMP_NOTE = ('', ' (an infinite acceleration: set limits.allow_velocity_jumps: true '
                           'to accept it)')
#: Boundary conditions of the 3-4-5 law (u, derivative order, value) that a polynomial segment
#: with via points keeps: rest to rest with zero acceleration at both ends.
REST_TO_REST = ((0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0),
                (1.0, 0, 1.0), (1.0, 1, 0.0), (1.0, 2, 0.0))
SEGMENT_FIELDS = {'start': 'motion.start_deg', 'end': 'motion.end_deg',
                  's_start': 'motion.start_position', 's_end': 'motion.end_position',
                  'law': 'motion.laws'}
#: The config array that gives each law parameter (via points, SCCA fractions, table points).
LAW_FIELDS = {'u_via': 'motion.via_deg', 'y_via': 'motion.via_position',
              'conditions': 'motion.via_deg', 'b': 'motion.scca_fractions',
              'c': 'motion.scca_fractions', 'd': 'motion.scca_fractions',
              'b + c + d': 'motion.scca_fractions', 'u': 'motion.table_u', 'y': 'motion.table_y'}
#: A number as the core quotes it (repr, :g or pi), and one or a pair of them with an SI unit.
NUMBER = r'-?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|pi'
SI_QUANTITY = re.compile(
    rf'(?<![\w.])((?:{NUMBER})|\((?:{NUMBER}), (?:{NUMBER})\)) (m|rad)(?![\w/^])')


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

    @cached_property
    def surface(self) -> MotionProgram:
        """Return the motion the cam surface gives the follower's input.

        The program itself, or with dynamics.compensate the polydyne cam (see polydyne.py),
        whose elastic train outputs the program at cam_speed. Geometry is the surface's.
        """
        train = self.config.train
        if train is None or not train.compensate:
            return self.program
        return compensated_program(self.program, self.config.cam_speed, train)

    def evaluate(self, angles: npt.ArrayLike) -> CamState:
        """Evaluate follower motion and cam geometry at cam angles (rad, taken modulo 2 pi)."""
        theta = np.mod(np.asarray(angles, dtype=float), TWO_PI)
        motion = self.program.evaluate(theta)
        timed = motion.at_speed(self.config.cam_speed)
        cam = motion if self.surface is self.program else self.surface.evaluate(theta)
        pressure_angle, radius = contact_measures(self.follower, theta, cam.s, cam.ds,
                                                  cam.d2s, clockwise=self.clockwise)
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
        motion = self.surface.evaluate(theta)
        return cam_geometry(self.follower, theta, motion.s, motion.ds, motion.d2s,
                            clockwise=self.clockwise)

    @cached_property
    def check(self) -> GeometryCheck:
        """Check the design against its limits: extremes refined from a dense sampling."""
        return check_geometry(self.geometry(), max_pressure_angle=self.config.pressure_angle_limit,
                              min_radius=self.config.min_radius_of_curvature,
                              program=self.surface)

    @cached_property
    def dynamics_check(self) -> DynamicsReport | None:
        """Return the refined dynamics figures at the cam speed, None without dynamics."""
        if self.dynamics is None:
            return None
        return dynamics_report(self.dynamics, self.program, self.evaluate)

    @cached_property
    def vibration_check(self) -> VibrationReport | None:
        """Return the elastic train's figures at the cam speed, None for a rigid train."""
        train = self.config.train
        if train is None:
            return None
        return vibration_report(self.surface, self.config.cam_speed, train, self.dynamics,
                                output=self.program)

    @cached_property
    def velocity_jumps(self) -> tuple[Discontinuity, ...]:
        """Return the joints where ds/dtheta jumps (an infinite acceleration).

        They fail the verdict unless limits.allow_velocity_jumps is true.
        """
        return tuple(jump for jump in self.program.continuity_report() if jump.order == 1)

    @property
    def ok(self) -> bool:
        """Return True when the design meets its limits, is not undercut and does not jump.

        A velocity jump at a joint fails it too, unless limits.allow_velocity_jumps is true.
        """
        dynamics, vibration = self.dynamics_check, self.vibration_check
        return (self.check.ok and (dynamics is None or dynamics.ok)
                and (vibration is None or not vibration.leaves_cam)
                and (self.config.allow_velocity_jumps or not self.velocity_jumps))

    def warnings(self) -> list[str]:
        """Say, once, what a designer must know: limits broken, undercut, discontinuities, jump."""
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
                             f'{math.degrees(jump.angle):.2f} deg'
                             + _VELOCITY_JUMP_NOTE[jump.order == 1
                                                   and not self.config.allow_velocity_jumps])
        notes += self._vibration_warnings()
        dynamics = self.dynamics_check
        if dynamics is None:
            return notes
        for start, end in dynamics.jump_angles:
            notes.append(f'the follower leaves the cam between {cam_degrees(start, 1):.1f} and '
                         f'{cam_degrees(end, 1, end=True):.1f} deg at '
                         f'{self.config.cam_speed:.6g} rad/s')
        if dynamics.contact_stress_ok is False:
            at = cam_degrees(dynamics.contact_stress_max_at, 1)
            allowable = cast(float, dynamics.contact_stress_limit) / 1e6
            notes.append(f'contact stress is undefined (undercut) from {at:.1f} deg, so not '
                         f'within the allowable {allowable:.6g} MPa'
                         if math.isnan(dynamics.contact_stress_max) else
                         f'contact stress reaches {dynamics.contact_stress_max / 1e6:.6g} MPa at '
                         f'{at:.1f} deg, over the allowable {allowable:.6g} MPa')
        return notes

    def _vibration_warnings(self) -> list[str]:
        """Say when the rigid model does not hold (VDI 2149) and when the output lifts off."""
        vibration, notes = self.vibration_check, list[str]()
        if vibration is None:
            return notes
        if not vibration.rigid_ok:
            notes.append(f'the follower train\'s natural frequency '
                         f'{vibration.natural_frequency_hz:.6g} Hz is only '
                         f'{vibration.frequency_ratio:.3g} times the cam frequency: VDI 2149 '
                         f'asks for {RIGID_RATIO:g} or more for a rigid-body analysis (see the '
                         'vibration figures)')
        if vibration.leaves_cam:
            notes.append(f'with the elastic train the follower leaves the cam at '
                         f'{cam_degrees(cast(float, vibration.elastic_force_min_at), 1):.1f} deg '
                         f'({self.config.cam_speed:.6g} rad/s): the force falls to '
                         f'{vibration.elastic_force_min:.6g} '
                         + ('N m' if self.config.follower.type.startswith('oscillating')
                            else 'N'))
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


def cam_degrees(angle: float, digits: int = 9, end: bool = False) -> float:
    """Return a cam angle (rad) in degrees rounded to digits: in [0, 360), or (0, 360] for an end.

    A position just short of a full turn reads 0, never 360; the end of a span reaching the
    full turn reads 360.
    """
    degrees = round(math.degrees(angle), digits) % 360.0
    return 360.0 if end and degrees == 0.0 else degrees


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
        raise InvalidParameter(name, written, in_file_units(err.rule, config)) from err


def in_file_units(text: str, config: CamConfig) -> str:
    """Restate the lengths (m) and angles (rad) a core message quotes in the file's units."""
    metre, unit = LENGTH_UNITS[config.length_unit], config.length_unit

    def restate(match: re.Match) -> str:
        numbers = [math.pi if n == 'pi' else float(n) for n in re.findall(NUMBER, match.group(1))]
        angle = match.group(2) == 'rad'
        shown = ', '.join(f'{math.degrees(n) if angle else n / metre:g}' for n in numbers)
        if match.group(1).startswith('('):
            shown = f'({shown})'
        return f'{shown} {"deg" if angle else unit}'

    return SI_QUANTITY.sub(restate, text.replace('(m)', f'({unit})'))


def build_law(motion: MotionConfig, index: int, written: Mapping[str, Any]) -> MotionLaw:
    """Build segment index's law with the parameters the config gives for it.

    Errors name the config entry (motion.via_deg[i], motion.scca_fractions, ...) as written.
    """
    name = motion.laws[index]
    params: dict[str, object] = {}
    vias = [number for number, segment in enumerate(motion.via_segment) if segment == index]
    if vias and name not in ('via_point', 'polynomial'):
        raise InvalidParameter(f'motion.via_segment[{vias[0]}]', index,
                               f'law {name} takes no via points (via_point and polynomial do)')
    start, span = motion.start[index], motion.end[index] - motion.start[index]
    stroke = motion.end_position[index] - motion.start_position[index]
    for number in vias:
        if not 0.0 < motion.via_angle[number] - start < span:
            raise InvalidParameter(
                f'motion.via_deg[{number}]', written['motion.via_deg'][number],
                f'must lie strictly inside segment {index}, between motion.start_deg[{index}] = '
                f'{written["motion.start_deg"][index]!r} and motion.end_deg[{index}] = '
                f'{written["motion.end_deg"][index]!r}')
    if name == 'via_point':
        if len(vias) != 1:
            raise InvalidParameter(f'motion.laws[{index}]', name,
                                   f'needs exactly one via point (motion.via_segment has '
                                   f'{len(vias)} entries equal to {index})')
        lift = motion.via_position[vias[0]] - motion.start_position[index]
        rise = lift / stroke if stroke else math.nan  # nan: no rise to pass through
        if not 0.0 < rise < 1.0:
            raise InvalidParameter(
                f'motion.via_position[{vias[0]}]', written['motion.via_position'][vias[0]],
                f'must lie strictly between motion.start_position[{index}] = '
                f'{written["motion.start_position"][index]!r} and motion.end_position[{index}]'
                f' = {written["motion.end_position"][index]!r} (the via_point law rises '
                'through it without stopping)')
        params = {'u_via': (motion.via_angle[vias[0]] - start) / span, 'y_via': rise}
    elif name == 'polynomial':
        params = {'conditions': [*REST_TO_REST, *(
            ((motion.via_angle[number] - start) / span, 0,
             (motion.via_position[number] - motion.start_position[index]) / stroke)
            for number in vias if stroke)]}
    elif name == 'scca':
        if len(motion.scca_fractions) != 3:
            raise InvalidParameter('motion.scca_fractions', list(motion.scca_fractions),
                                   f'needs 3 entries b, c, d for the scca law of segment {index}')
        params = dict(zip('bcd', motion.scca_fractions))
    elif name == 'table':
        params = dict(zip('uy', table_points(motion, index)))
    return make_law(name, **params)


def table_points(motion: MotionConfig, index: int) -> tuple[tuple[float, ...], ...]:
    """Return the (u, y) points of the table segment index: its share of table_u/table_y.

    One table segment takes them all; with more, motion.table_counts says how many each takes,
    in segment order, so no two segments ever share a shape by accident.
    """
    tables = [number for number, law in enumerate(motion.laws) if law == 'table']
    counts, total = motion.table_counts, len(motion.table_u)
    if not counts and len(tables) == 1:
        return motion.table_u, motion.table_y
    if len(counts) != len(tables):
        raise InvalidParameter('motion.table_counts', list(counts),
                               f'needs one entry per table segment ({len(tables)}: segments '
                               f'{", ".join(map(str, tables))}) giving how many of the '
                               f'motion.table_u/table_y points each takes, in segment order')
    if any(count < 2 for count in counts) or sum(counts) != total:
        raise InvalidParameter('motion.table_counts', list(counts),
                               f'must be counts of at least 2 adding up to the {total} '
                               f'motion.table_u points')
    first = sum(counts[:tables.index(index)])
    end = first + counts[tables.index(index)]
    return motion.table_u[first:end], motion.table_y[first:end]


def build_program(motion: MotionConfig, written: Mapping[str, Any]) -> MotionProgram:
    """Build the motion program; errors name the motion.* parameter (as written) and index."""
    for index, segment in enumerate(motion.via_segment):
        if not 0 <= segment < len(motion.laws):
            raise InvalidParameter(f'motion.via_segment[{index}]', segment,
                                   f'must be a segment index in [0, {len(motion.laws) - 1}]')
    segments = []
    for index in range(len(motion.laws)):
        try:
            law = build_law(motion, index, written)
        except InvalidParameter as err:
            if err.parameter.startswith('motion.'):
                raise
            field = LAW_FIELDS.get(err.parameter)
            if field is None:
                raise InvalidParameter(f'motion.laws[{index}] ({motion.laws[index]}): '
                                       f'{err.parameter}', err.value, err.rule) from err
            what = '' if err.parameter in ('u', 'y', 'conditions') else (
                f'{err.parameter} = {quote(err.value)}: ')
            raise InvalidParameter(field, list(written.get(field, ())), f'{what}{err.rule} '
                                   f'({motion.laws[index]} law of segment {index})') from err
        segments.append(Segment(law, motion.start[index], motion.end[index],
                                motion.start_position[index], motion.end_position[index]))
    try:
        return MotionProgram(tuple(segments))
    except InvalidParameter as err:
        raise _in_config_terms(err, written) from err


def _in_config_terms(err: InvalidParameter, written: Mapping[str, Any]) -> InvalidParameter:
    """Restate a program error ('segments[2].end') with the config's names and written values.

    Values the rule quotes in SI (segments[1].end = 1.5707963267948966 rad) become the entries
    as the file gives them (motion.end_deg[1] = 90.0).
    """
    def entry(match: re.Match) -> str:
        field, number = SEGMENT_FIELDS.get(match.group(2)), int(match.group(1))
        if field is None:
            return match.group(0)
        values = written.get(field)
        value = values[number] if isinstance(values, (list, tuple)) else None
        quoted = f' = {value!r}' if match.group(3) and value is not None else match.group(3)
        return f'{field}[{number}]{quoted or ""}'

    match = re.fullmatch(r'segments\[(\d+)\]\.(\w+)', err.parameter)
    if not match or match.group(2) not in SEGMENT_FIELDS:
        return InvalidParameter(f'motion ({err.parameter})', err.value, err.rule)
    field, index = SEGMENT_FIELDS[match.group(2)], int(match.group(1))
    values = written.get(field)
    value = values[index] if isinstance(values, (list, tuple)) else err.value
    rule = re.sub(r'(?<![\w.])(s_start|start) = ', rf'segments[{index}].\1 = ', err.rule)
    rule = re.sub(r'segments\[(\d+)\]\.(\w+)( = [-+\w.]+(?: rad)?)?', entry, rule)
    return InvalidParameter(f'{field}[{index}]', value, rule)


def build_design(config: CamConfig) -> CamDesign:
    """Build and validate the whole design; raises InvalidParameter naming the parameter."""
    program = build_program(config.motion, config.parameters)
    follower = build_follower(config)
    design = CamDesign(config, program, follower)
    try:
        design.geometry()  # the follower must be able to follow the motion everywhere
    except InvalidParameter as err:
        raise _at_cam_angle(err, program, config) from err
    return design


def _at_cam_angle(err: InvalidParameter, program: MotionProgram,
                  config: CamConfig) -> InvalidParameter:
    """Restate a geometry error at a check sample ('s[2812]') as the segment and cam angle.

    A follower position s is quoted in the file's units (its length_unit, or deg of arm angle).
    """
    match = re.fullmatch(r'(\w+)\[(\d+)\]', err.parameter)
    if not match:
        return err
    angle = int(match.group(2)) * TWO_PI / CHECK_SAMPLES
    index = program.segment_at(angle)
    value = err.value
    if match.group(1) == 's' and isinstance(value, float):
        oscillating = config.follower.type.startswith('oscillating')
        value = math.degrees(value) if oscillating else value / LENGTH_UNITS[config.length_unit]
    return InvalidParameter(f'motion.laws[{index}] ({program.segments[index].law.name}): '
                            f'{match.group(1)} at {math.degrees(angle):.2f} deg', value,
                            in_file_units(err.rule, config))
