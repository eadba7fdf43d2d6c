"""Cutter paths of a cam: the surface offset by the cutter, points placed by a chordal tolerance.

A contour is a closed curve given exactly as a function of the cam angle theta (cam frame, m):
its points, outward unit normals (from the cam to the follower) and signed curvature (convex
> 0). The cam surface is one (cam_contour); the cutter-location path of a cutter of radius Rc
cutting the outside is its offset by Rc along the normal, of curvature k / (1 + Rc k). A concave
part of radius under Rc would be gouged: check_cutter refuses the cutter and says where.

place_points puts points on a contour so that every chord stays within a tolerance of it: the
chords are split until each one's sampled deviation (sagitta ~ L^2 / (8 rho)) is within a
margin of the tolerance, with the points rounded to the output's resolution; then the worst
deviation of the rounded polyline from the exact curve (the distance of each curve point to its
chord) is refined with extremes.refine_extrema, so the stated worst deviation is the true one
(never below it), and any chord found beyond the tolerance is split again.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ..errors import InvalidParameter
from ..extremes import CHECK_SAMPLES, refine_extrema, TWO_PI
from ..motion.program import MotionProgram
from .followers import check_follower, Follower

Array = np.ndarray
#: Points, outward unit normals ((2, n) each, m) and signed curvature (n, 1/m) at angles (n,).
Evaluate = Callable[[Array], tuple[Array, Array, Array]]

INITIAL_CHORDS = 64  # chords of the first, equally spaced placement (plus the breaks)
CHORD_SAMPLES = 8  # interior samples of each chord for its deviation
PLACEMENT_MARGIN = 0.8  # chords are placed within this share of what the rounding leaves
MAX_POINTS = 1_000_000
MAX_ROUNDS = 60


@dataclass(frozen=True, eq=False)
class Contour:
    """A closed contour as an exact function of the cam angle (see the module doc).

    breaks: angles (rad) where the curvature may jump (the motion's joints).
    """

    evaluate: Evaluate
    breaks: Array

    def offset(self, distance: float) -> Contour:
        """Return the contour moved by distance (m) along its outward normal."""
        inner = self.evaluate

        def evaluate(theta: Array) -> tuple[Array, Array, Array]:
            points, normals, curvature = inner(theta)
            return points + distance * normals, normals, curvature / (1.0 + distance * curvature)
        return Contour(evaluate, self.breaks)

    def flipped(self) -> Contour:
        """Return the same curve with its normals (and so its curvature's sign) turned over.

        The outer flank of a groove is cut from inside the groove: its outward side is there.
        """
        inner = self.evaluate

        def evaluate(theta: Array) -> tuple[Array, Array, Array]:
            points, normals, curvature = inner(theta)
            return points, -normals, -curvature
        return Contour(evaluate, self.breaks)


def cam_contour(follower: Follower, program: MotionProgram, clockwise: bool) -> Contour:
    """Return the cam surface of a follower driven by program as a Contour (cam frame)."""
    check_follower(follower)
    sigma = -1 if clockwise else 1

    def evaluate(theta: Array) -> tuple[Array, Array, Array]:
        motion = program.evaluate(theta)
        profile = follower._geometry(theta, sigma, motion.s, motion.ds, motion.d2s)
        with np.errstate(divide='ignore'):
            curvature = 1.0 / profile.surface_radius
        return profile.surface, profile.surface_normal, curvature
    return Contour(evaluate, np.asarray(program.breaks, dtype=float))


def smallest_concave_radius(contour: Contour,
                            samples: int = CHECK_SAMPLES) -> tuple[float, float]:
    """Return (radius m, angle rad) of the contour's most curved concave part (inf if none)."""
    theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)

    def bend(angles: Array) -> Array:
        return -contour.evaluate(angles)[2]

    value, at = refine_extrema(lambda angles: bend(angles)[np.newaxis], theta,
                               bend(theta)[np.newaxis], ('max',), breaks=contour.breaks)[0]
    return (1.0 / value if value > 0.0 else math.inf), at


def check_cutter(contour: Contour, cutter_radius: float, name: str = 'cutter_radius') -> None:
    """Raise InvalidParameter (naming name) if a cutter of this radius (m) gouges the contour.

    Cutting the outside, a concave part of radius below the cutter's cannot be reached.
    """
    if not (math.isfinite(cutter_radius) and cutter_radius > 0.0):
        raise InvalidParameter(name, cutter_radius, 'must be a finite length > 0 (m)')
    radius, at = smallest_concave_radius(contour)
    if cutter_radius > radius:
        raise InvalidParameter(name, cutter_radius,
                               f'is larger than the smallest concave radius of the cam surface, '
                               f'{radius:.6g} m at cam angle {at:.6g} rad: the cutter would '
                               'gouge it there (use a smaller cutter)')


#: A cutter within this share of a groove's half width cuts it in one pass on the pitch curve.
GROOVE_FIT = 1e-9


def cutter_contours(contours: dict[str, Contour], cutter_radius: Optional[float], nominal: bool,
                    groove_half_width: Optional[float] = None,
                    name: str = 'cutter_radius') -> tuple[dict[str, Contour], float]:
    """Return the contours a cutter follows and how far it leads in along the first normal (m).

    contours are a cam's working curves (normals on the cutter's side). nominal: the curves
    themselves (for a CMM, or for the control's cutter compensation); else each offset by the
    cutter radius, a gouging cutter refused (check_cutter). A groove (its half width w given)
    is cut from inside: a cutter of radius w runs once along the pitch curve, a narrower one
    along each flank, a wider one is refused. The lead-in starts clear of the cam (2 Rc for
    compensation, Rc for a path) or in the middle of the groove.
    """
    if cutter_radius is not None:
        if groove_half_width is not None and cutter_radius > groove_half_width * (1 + GROOVE_FIT):
            raise InvalidParameter(name, cutter_radius, f'is wider than the groove: at most half '
                                   f'its width, {groove_half_width:.6g} m')
        for contour in contours.values():
            check_cutter(contour, cutter_radius, name)
    cutter = cutter_radius or 0.0
    if nominal:
        return contours, (2.0 * cutter if groove_half_width is None else groove_half_width)
    if groove_half_width is None:
        return {key: contour.offset(cutter) for key, contour in contours.items()}, cutter
    if abs(cutter - groove_half_width) <= GROOVE_FIT * groove_half_width:
        return {'pitch': contours['inner'].offset(groove_half_width)}, 0.0
    return ({key: contour.offset(cutter) for key, contour in contours.items()},
            groove_half_width - cutter)


@dataclass(frozen=True, eq=False)
class ToolPath:
    """Points on a contour, in increasing cam angle, the closing chord back to the first implied.

    points are rounded to the resolution asked for; normals are the exact contour's there.
    worst_deviation (m) is the largest distance from the exact contour to its chord, refined
    (never below the truth), reached at cam angle worst_at (rad).
    """

    theta: Array
    points: Array  # (n, 2) m
    normals: Array  # (n, 2)
    tolerance: float
    worst_deviation: float
    worst_at: float


def _chord_distance(points: Array, start: Array, end: Array) -> Array:
    """Return the distance of points (2, n) to the segments start-end ((2, n) each)."""
    chord = end - start
    length2 = chord[0] ** 2 + chord[1] ** 2
    rel = points - start
    along = np.clip((rel[0] * chord[0] + rel[1] * chord[1]) / np.where(length2 > 0, length2, 1),
                    0.0, 1.0)
    return np.hypot(rel[0] - along * chord[0], rel[1] - along * chord[1])


class _Polyline:
    """The rounded points at knots and the deviation of the exact contour from their chords."""

    def __init__(self, contour: Contour, knots: Array, resolution: float):
        self.contour, self.knots = contour, knots
        points, self.normals, _ = contour.evaluate(knots)
        self.points = np.round(points / resolution) * resolution if resolution else points

    def deviation(self, angles: Array) -> Array:
        """Return the distance of the contour at angles (any real) to its chord."""
        wrapped = np.mod(angles, TWO_PI)
        index = np.clip(np.searchsorted(self.knots, wrapped, side='right') - 1, 0, None)
        following = (index + 1) % self.knots.size
        curve = self.contour.evaluate(wrapped)[0]
        return _chord_distance(curve, self.points[:, index], self.points[:, following])

    def interior(self) -> Array:
        """Return CHORD_SAMPLES angles inside each chord, shape (chords, CHORD_SAMPLES)."""
        ends = np.append(self.knots[1:], self.knots[0] + TWO_PI)
        share = np.arange(1, CHORD_SAMPLES + 1) / (CHORD_SAMPLES + 1)
        return self.knots[:, np.newaxis] + share * (ends - self.knots)[:, np.newaxis]


def _split(knots: Array, chords: Array, pieces: Array) -> Array:
    """Return knots with chord i cut into pieces[i] equal parts (in angle)."""
    ends = np.append(knots[1:], knots[0] + TWO_PI)
    cuts = pieces - 1  # new knots per chord
    first = np.repeat(np.cumsum(cuts) - cuts, cuts)  # where each chord's new knots begin
    step = np.arange(cuts.sum()) - first + 1  # 1 .. k-1 within each chord
    start, width = knots[chords], ends[chords] - knots[chords]
    new = np.repeat(start, cuts) + np.repeat(width, cuts) * step / np.repeat(pieces, cuts)
    return np.sort(np.mod(np.concatenate((knots, new)), TWO_PI))


def place_points(contour: Contour, tolerance: float, resolution: float = 0.0) -> ToolPath:
    """Place points on the contour so that every chord is within tolerance (m) of it.

    resolution (m): the points are rounded to this grid, as an output file writes them; the
    rounding is counted in the deviation. Raises InvalidParameter naming tolerance when it is
    not above 10 x the resolution or would take more than MAX_POINTS points.
    """
    if not (math.isfinite(tolerance) and tolerance > 10.0 * resolution):
        raise InvalidParameter('tolerance', tolerance,
                               f'must be a finite length > 10 x the output resolution '
                               f'{resolution:g} m')
    room = PLACEMENT_MARGIN * (tolerance - resolution / math.sqrt(2.0))
    breaks = np.mod(contour.breaks, TWO_PI)
    knots = np.unique(np.concatenate((breaks, np.linspace(0.0, TWO_PI, INITIAL_CHORDS,
                                                          endpoint=False))))
    for _ in range(MAX_ROUNDS):
        if knots.size > MAX_POINTS:
            raise InvalidParameter('tolerance', tolerance, f'needs more than {MAX_POINTS} '
                                                           'points: give a larger one')
        line = _Polyline(contour, knots, resolution)
        inside = line.interior()
        sampled = line.deviation(inside.reshape(-1)).reshape(inside.shape)
        worst_sampled = sampled.max(axis=1)
        over = worst_sampled > room
        if over.any():
            pieces = np.ceil(np.sqrt(worst_sampled[over] / room) * 1.05).astype(int)
            knots = _split(knots, np.flatnonzero(over), pieces)
            continue
        grid = np.concatenate((knots, inside.reshape(-1)))
        order = np.argsort(grid)
        worst, at = refine_extrema(lambda angles: line.deviation(angles)[np.newaxis],
                                   grid[order], line.deviation(grid[order])[np.newaxis],
                                   ('max',), breaks=knots)[0]
        if worst <= tolerance:
            return ToolPath(knots, line.points.T.copy(), line.normals.T.copy(), tolerance,
                            worst, at)
        chord = np.clip(np.searchsorted(knots, at, side='right') - 1, 0, None)
        knots = _split(knots, np.array([chord]), np.array([2]))
    raise InvalidParameter('tolerance', tolerance, 'could not be met by the point placement')
