"""Check a cam geometry against its limits: pressure angle, curvature, undercut, face width.

The extremes of the geometry's measures are found on the samples and, given the motion program,
refined between them on the exact motion (:mod:`.extremes`), so the limits are checked between
the samples too; cusps are then roots of a smooth undercut margin. The base-radius sizing
(:mod:`.sizing`) solves on the same margins.

Rise and return: theta runs with the cam's rotation, so the follower is pushed away from the cam
(the rise, the working stroke) where ds/dtheta > 0 and comes back (the return, driven by the
spring) where ds/dtheta < 0, whatever the sense of rotation. Each side's |pressure angle| is
checked against its own limit; a dwell (ds/dtheta = 0) belongs to both sides, so the stricter
limit governs there (the safe side).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence

import numpy as np

from ..errors import InvalidParameter
from ..extremes import refine_extrema, refine_roots, TWO_PI
from .followers import checked_real, Follower, ROLLERS
from .cam_geometry import read_only, CamGeometry
from ..motion.program import MotionProgram

Array = np.ndarray

Measure = Callable[[Any], Array]  # of a CamGeometry or a Profile: the same attribute names


def turning_breaks(program: MotionProgram, theta: Array, ds: Array) -> Array:
    """Return the program's breaks and the angles where ds/dtheta changes sign.

    theta: increasing angles in [0, 2 pi), ds the motion's ds/dtheta there. A function of the
    side (rise or return) jumps or kinks where the follower turns, so those angles split an
    extreme's search like segment joints; a dwell's own zeros are left out.
    """
    breaks = np.asarray(program.breaks, dtype=float)
    moving = ds != 0.0
    if np.count_nonzero(moving) < 3:
        return breaks
    turns = refine_roots(lambda angles: program.evaluate(angles).ds, theta[moving], ds[moving],
                         breaks=breaks)
    return np.concatenate((breaks, turns))


class GeometryExtremes:
    """Extremes and zeros of a geometry's measures, refined on the exact motion when given.

    sampled holds the measures at the angles theta (a CamGeometry, or the raw Profile when the
    cam-frame coordinates are not needed). With a program, every extreme is refined from its
    grid bracket on the exact geometry (see extremes.py); without one, the grid's values are
    taken as they are.
    """

    def __init__(self, follower: Follower, clockwise: bool, theta: Array, sampled: Any,
                 program: Optional[MotionProgram]):
        self._follower, self._sigma = follower, -1 if clockwise else 1
        self._sampled, self._program = sampled, program
        theta = np.asarray(theta)
        if program is not None:
            theta = np.mod(theta, TWO_PI)
        order = np.argsort(theta, kind='stable')
        distinct = np.concatenate(([True], np.diff(theta[order]) > 0.0))
        self._order, self._theta = order[distinct], theta[order][distinct]
        self._breaks = None if program is None else program.breaks
        self._side_breaks: Optional[Array] = None

    def _function(self, measures: Sequence[Measure]) -> Callable[[Array], Array]:
        """Return the exact measures as a function of cam angles (one row per measure)."""
        follower, sigma, program = self._follower, self._sigma, self._program
        assert program is not None

        def func(angles: Array) -> Array:
            motion = program.evaluate(angles)
            profile = follower._geometry(angles, sigma, motion.s, motion.ds, motion.d2s)
            profile.ds = motion.ds
            return np.array([measure(profile) for measure in measures])
        return func

    def _breaks_between_sides(self) -> Optional[Array]:
        """Return the program's breaks and the angles where ds/dtheta changes sign (cached)."""
        if self._program is not None and self._side_breaks is None:
            ds = np.asarray(self._sampled.ds)[self._order]
            self._side_breaks = turning_breaks(self._program, self._theta, ds)
        return self._side_breaks

    def extremes(self, wanted: Sequence[tuple[Measure, str]]) -> list[tuple[float, float]]:
        """Return (value, angle) of each (measure, 'max' or 'min') wanted, refined together."""
        measures = [measure for measure, _ in wanted]
        values = np.array([measure(self._sampled) for measure in measures])[:, self._order]
        if self._program is None or self._theta.size < 3:
            found = []
            for row, (_, kind) in enumerate(wanted):
                index = int(np.argmax(values[row]) if kind == 'max' else np.argmin(values[row]))
                found.append((float(values[row, index]), float(self._theta[index])))
            return found
        sided = any(measure in SIDE_MEASURES for measure in measures)
        return refine_extrema(self._function(measures), self._theta, values,
                              [kind for _, kind in wanted],
                              breaks=self._breaks_between_sides() if sided else self._breaks)

    def zeros(self, measure: Measure, inside: Optional[float] = None) -> Array:
        """Return the angles where the measure changes sign (grid: interpolated).

        inside, an angle (rad) where the measure is known to be <= 0, joins the grid, so that a
        dip below zero between two samples is bracketed too.
        """
        values = np.asarray(measure(self._sampled))[self._order]
        if self._program is None or values.size < 3:
            return _zero_crossings(self._theta, values)
        exact = self._function([measure])
        theta = self._theta
        if inside is not None:
            at = float(np.mod(inside, TWO_PI))
            place = int(np.searchsorted(theta, at))
            if place == theta.size or theta[place] != at:
                theta = np.insert(theta, place, at)
                values = np.insert(values, place, exact(np.array([at]))[0, 0])
        return refine_roots(lambda angles: exact(angles)[0], theta, values, breaks=self._breaks)


def _pressure_angle_of(measures: Any) -> Array:
    return measures.pressure_angle


def abs_pressure_angle(measures: Any) -> Array:
    """Return |pressure angle| of sampled measures (a Measure of the checks and the sizing)."""
    return np.abs(measures.pressure_angle)


def rise_pressure_angle(measures: Any) -> Array:
    """|pressure angle| where the follower rises or dwells (ds/dtheta >= 0), else 0."""
    return np.where(measures.ds >= 0.0, np.abs(measures.pressure_angle), 0.0)


def return_pressure_angle(measures: Any) -> Array:
    """|pressure angle| where the follower returns or dwells (ds/dtheta <= 0), else 0."""
    return np.where(measures.ds <= 0.0, np.abs(measures.pressure_angle), 0.0)


SIDE_MEASURES = (rise_pressure_angle, return_pressure_angle)


def pitch_curvature_of(measures: Any) -> Array:
    """Return the pitch curve's curvature of sampled measures (a Measure)."""
    return measures.pitch_curvature


def _surface_radius(measures: Any) -> Array:
    return measures.surface_radius


def _contact_offset(measures: Any) -> Array:
    return measures.contact_offset


def _undercut_measure(follower: Follower) -> Measure:
    """Return a smooth margin that is <= 0 exactly where the surface is undercut or has a cusp.

    Roller: 1 - Rr * kappa_pitch (<= 0 where 0 < rho_pitch <= Rr); flat face: rho.
    """
    if isinstance(follower, ROLLERS):
        roller = follower.roller_radius
        return lambda measures: 1.0 - roller * measures.pitch_curvature
    return _surface_radius


def worst_curvature(follower: Follower) -> tuple[Measure, str]:
    """Return the measure and kind that bound the surface radius from below.

    The largest pitch curvature for rollers, the smallest surface radius for flat faces.
    """
    if isinstance(follower, ROLLERS):
        return pitch_curvature_of, 'max'
    return _surface_radius, 'min'


def radius_margin(follower: Follower, worst: float, min_radius: float) -> float:
    """Return a number >= 0 exactly when every convex part of the surface has rho >= min_radius.

    worst is worst_curvature's value.
    """
    if isinstance(follower, ROLLERS):
        return 1.0 / (min_radius + follower.roller_radius) - worst
    return worst - min_radius


def _zero_crossings(theta: Array, margin: Array) -> Array:
    """Return the angles where margin reaches zero, interpolated between neighbouring angles."""
    order = np.argsort(theta, kind='stable')
    theta, margin = theta[order], margin[order]
    exact = theta[margin == 0.0]
    a, b = margin[:-1], margin[1:]
    change = (a * b < 0.0)
    ta, tb = theta[:-1][change], theta[1:][change]
    between = ta + (tb - ta) * a[change] / (a[change] - b[change])
    return np.sort(np.concatenate((exact, between)))


def pressure_limit(value: object, name: str = 'max_pressure_angle') -> float:
    """Return a pressure-angle limit (rad) after checking it lies in (0, pi/2)."""
    return checked_real(name, value, lambda x: 0.0 < x < math.pi / 2, 'in (0, pi/2) rad')


@dataclass(frozen=True)
class PressureLimits:
    """The allowed |pressure angle| (rad) on the rise and on the return (see the module doc)."""

    rise: float
    ret: float

    @property
    def single(self) -> bool:
        """Return True when both sides share one limit (then it is named 'pressure_angle')."""
        return self.rise == self.ret

    def margins(self, rise_peak: float, return_peak: float) -> dict[str, float]:
        """Return each side's margin (>= 0 when met), keyed by the limit's name."""
        if self.single:
            return {'pressure_angle': self.rise - max(rise_peak, return_peak)}
        return {'pressure_angle_rise': self.rise - rise_peak,
                'pressure_angle_return': self.ret - return_peak}


def check_limits(max_pressure_angle: Optional[float], min_radius: Optional[float],
                 max_pressure_angle_return: Optional[float] = None,
                 ) -> tuple[Optional[PressureLimits], Optional[float]]:
    """Validate the optional pressure-angle (rad; return: default the rise's) and radius limits.

    A return limit needs a rise limit.
    """
    if max_pressure_angle is None:
        if max_pressure_angle_return is not None:
            raise InvalidParameter('max_pressure_angle', None,
                                   'give it with max_pressure_angle_return (the rise limit)')
        angles = None
    else:
        rise = pressure_limit(max_pressure_angle)
        angles = PressureLimits(rise, rise if max_pressure_angle_return is None else
                                pressure_limit(max_pressure_angle_return,
                                               'max_pressure_angle_return'))
    radius = None if min_radius is None else checked_real('min_radius', min_radius,
                                                          lambda x: x >= 0.0, '>= 0 (m)')
    return angles, radius


@dataclass(frozen=True, eq=False)
class GeometryCheck:
    """Engineering verdict on a cam geometry: undercut, pressure angle, curvature, face width.

    Extremes are refined on the exact motion when check_geometry was given the program, else
    they are the samples' (see check_geometry). undercut_angles are the sampled cam angles (rad)
    where the surface is undercut or has a cusp (convex surface radius <= 0: 0 < rho_pitch <= Rr
    for rollers, rho <= 0 for flat faces), with the refined worst angle added when only it is;
    cusp_angles are where that starts or ends. min_radius is the smallest radius of curvature of
    the convex parts of the surface (m; inf if none is convex). The *_ok fields are None when no
    limit was given. face_min/face_max (m) bound the contact offset on a flat face (None for
    rollers): the face must reach from face_min to face_max. pressure_angle_high/low are the
    signed extremes of the pressure angle (rad) and the angles where they occur;
    pressure_angle_rise/return are the largest |pressure angle| on each side (rise: ds/dtheta
    >= 0, return: <= 0; see the module doc) and where, each checked against its own limit
    (pressure_angle_limit for the rise, pressure_angle_return_limit for the return).
    pitch_convex_radius_min/pitch_concave_radius_min are the smallest radii of the convex and of
    the concave parts of a roller's pitch curve (m, inf if none; None for flat faces): a roller
    must stay below the first (undercut), a groove's roller below both.
    """

    undercut_angles: Array
    cusp_angles: Array
    max_pressure_angle: float
    max_pressure_angle_at: float
    pressure_angle_limit: Optional[float]
    pressure_angle_ok: Optional[bool]
    min_radius: float
    min_radius_at: float
    radius_limit: Optional[float]
    radius_ok: Optional[bool]
    face_min: Optional[float]
    face_max: Optional[float]
    pressure_angle_high: tuple[float, float] = (math.nan, math.nan)
    pressure_angle_low: tuple[float, float] = (math.nan, math.nan)
    pressure_angle_rise: tuple[float, float] = (math.nan, math.nan)
    pressure_angle_return: tuple[float, float] = (math.nan, math.nan)
    pressure_angle_return_limit: Optional[float] = None
    pitch_convex_radius_min: Optional[float] = None
    pitch_concave_radius_min: Optional[float] = None

    @property
    def undercut(self) -> bool:
        """Return True if any sample is undercut or on a cusp."""
        return bool(self.undercut_angles.size)

    @property
    def face_width(self) -> Optional[float]:
        """Return the smallest face length face_max - face_min (m), None for rollers."""
        if self.face_min is None or self.face_max is None:
            return None
        return self.face_max - self.face_min

    @property
    def ok(self) -> bool:
        """Return True if there is no undercut and every given limit is met."""
        return (not self.undercut and self.pressure_angle_ok is not False
                and self.radius_ok is not False)


def check_geometry(geometry: CamGeometry, *, max_pressure_angle: Optional[float] = None,
                   min_radius: Optional[float] = None,
                   program: Optional[MotionProgram] = None,
                   max_pressure_angle_return: Optional[float] = None) -> GeometryCheck:
    """Check a geometry for undercut and cusps and against optional limits.

    max_pressure_angle (rad) bounds |pressure angle| on the rise, max_pressure_angle_return on
    the return (default: the same; see the module doc for the sides); min_radius (m) bounds the
    radius of curvature of the convex parts of the surface (for a roller, a pitch-curve limit P
    is the surface limit P - Rr). With program (the motion the geometry was sampled from,
    densely over a whole revolution), every extreme is refined between the samples on the exact
    motion and cusps are roots; without it, the samples' values are used. The verdict is
    returned as data, never raised.
    """
    if not isinstance(geometry, CamGeometry):
        raise InvalidParameter('geometry', geometry, 'must be a CamGeometry')
    if program is not None and not isinstance(program, MotionProgram):
        raise InvalidParameter('program', program, 'must be a MotionProgram or None')
    angles, radius_limit = check_limits(max_pressure_angle, min_radius,
                                        max_pressure_angle_return)
    follower = geometry.follower
    roller = isinstance(follower, ROLLERS)
    wanted = [(_pressure_angle_of, 'max'), (_pressure_angle_of, 'min'),
              (rise_pressure_angle, 'max'), (return_pressure_angle, 'max'),
              worst_curvature(follower)]
    if roller:
        wanted.append((pitch_curvature_of, 'min'))
    if geometry.contact_offset is not None:
        wanted += [(_contact_offset, 'min'), (_contact_offset, 'max')]
    extremes = GeometryExtremes(follower, geometry.clockwise, geometry.theta, geometry, program)
    high, low, rise, ret, (worst, worst_at), *rest = extremes.extremes(wanted)
    peak, peak_at = max(high, (-low[0], low[1]))
    convex: Optional[float] = None
    concave: Optional[float] = None
    if isinstance(follower, ROLLERS):
        undercut_margin = 1.0 - follower.roller_radius * worst
        smallest = 1.0 / worst - follower.roller_radius if worst > 0.0 else math.inf
        concave = -1.0 / rest[0][0] if rest[0][0] < 0.0 else math.inf
        convex, face = smallest + follower.roller_radius, rest[1:]
    else:
        undercut_margin = smallest = worst
        face = rest
    undercut = _undercut_measure(follower)
    dip = worst_at if undercut_margin <= 0.0 else None
    at = np.asarray(geometry.theta)[np.asarray(undercut(geometry)) <= 0.0]
    if undercut_margin <= 0.0 and not at.size:
        at = np.array([worst_at])
    return GeometryCheck(
        undercut_angles=read_only(at),
        cusp_angles=read_only(extremes.zeros(undercut, dip)),
        max_pressure_angle=peak,
        max_pressure_angle_at=peak_at,
        pressure_angle_limit=None if angles is None else angles.rise,
        pressure_angle_ok=None if angles is None
        else min(angles.margins(rise[0], ret[0]).values()) >= 0.0,
        min_radius=smallest,
        min_radius_at=worst_at,
        radius_limit=radius_limit,
        radius_ok=None if radius_limit is None
        else radius_margin(follower, worst, radius_limit) >= 0.0,
        face_min=face[0][0] if face else None,
        face_max=face[1][0] if face else None,
        pressure_angle_high=high,
        pressure_angle_low=low,
        pressure_angle_rise=rise,
        pressure_angle_return=ret,
        pressure_angle_return_limit=None if angles is None else angles.ret,
        pitch_convex_radius_min=convex,
        pitch_concave_radius_min=concave,
    )
