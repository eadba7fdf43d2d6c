"""
Cam tables: the follower position at knots of the cam (master) angle, for a PLC to interpolate.

A table holds knots 0 = theta_0 < ... < theta_n = 360 deg and the exact s, ds/dtheta and
d2s/dtheta2 of the motion program there (SI: m, or rad for an oscillating follower; derivatives
per rad).  A PLC or drive interpolates between the knots, linearly (positions only), by cubic
Hermite pieces (positions and slopes) or by quintic Hermite pieces (positions, slopes and
curvatures at both ends: CODESYS SoftMotion's XYVA cams, one fifth-degree polynomial per
interval).  The worst deviation of that interpolant p from the exact law s is found on every
interval by dense sampling, refined by Newton steps on e' = s' - p' = 0 (an extreme of the error
e = s - p lies where the slopes agree).

- `equidistant_table`: n equal steps of 360/n deg.
- `tolerance_table`: knots placed greedily: from each knot the next is as far as the interval
  stays within the tolerance, searched in rounds of CANDIDATES ends (the first end over the
  tolerance and the one before it bracket the next round), each checked as above.  Every boundary
  of the program's segments, where derivatives may jump, is a knot.  Greedy placement from a
  fixed start is not the fewest knots in general; the table states the tolerance it meets.

Every interval's error is also evaluated at the program's breaks inside it: where the slope
jumps (a dwell next to constant velocity) the worst error sits at the kink, where e' changes sign
without passing through zero.  A knot carries one slope and one curvature, the segment's that
starts there; where either jumps, a placed table keeps the other side too by a knot just before
the joint (as close as the tolerance needs).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Optional

import numpy as np

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ..errors import InvalidParameter
from ..motion.program import MotionProgram

INTERPOLATIONS = ('linear', 'cubic', 'quintic')
#: Most knots a table may have (equidistant or placed).
MAX_POINTS = 1_000_000
#: Samples per interval in the final check of a table (then refined by Newton steps).
CHECK_SAMPLES = 64
#: Samples per candidate interval while knots are placed (then refined by Newton steps).
SEARCH_SAMPLES = 24
NEWTON_STEPS = 3
#: Candidate ends checked at once in each round of the search for the next knot.
CANDIDATES = 31
#: The search for the next knot stops when its bracket is below this fraction of the piece.
SEARCH_RESOLUTION = 1e-7
#: Knots are placed for this fraction of the tolerance, so that the check stays within it.
SEARCH_MARGIN = 1.0 - 1e-6
#: Smallest tolerance, relative to the stroke (below it the table would need ~1e5+ knots).
MIN_RELATIVE_TOLERANCE = 1e-7
#: Segment boundaries closer than this (rad) count as one knot.
BOUNDARY_MERGE = 1e-9


class _Knots(NamedTuple):
    """Exact values at the ends of intervals (rad; SI per rad)."""

    s: FloatArray
    ds: FloatArray
    d2s: FloatArray


@dataclass(frozen=True, eq=False)
class CamTable:
    """
    Knots in master degrees and the exact follower values there, with the worst error.

    position, slope and curvature are s, ds/dtheta, d2s/dtheta2 (SI, per rad) at
    radians(master_deg).  max_error is the largest |interpolated - exact| over the revolution
    for the table's interpolation; tolerance is what the knots were placed for (None for an
    equidistant table).  The last knot is 360 deg and repeats the first knot's values.
    """

    master_deg: FloatArray
    position: FloatArray
    slope: FloatArray
    curvature: FloatArray
    interpolation: str
    max_error: float
    tolerance: Optional[float] = None

    @property
    def angle(self) -> FloatArray:
        """Knots in rad."""
        return np.radians(self.master_deg)


def stroke(program: MotionProgram) -> float:
    """Return the follower's travel: highest minus lowest segment end position (m, or rad)."""
    ends = [value for segment in program.segments for value in (segment.s_start, segment.s_end)]
    return max(ends) - min(ends)


def equidistant_table(program: MotionProgram, points: int,
                      interpolation: str = 'linear') -> CamTable:
    """Return a table of points equal steps over one revolution (points + 1 knots with 360)."""
    if isinstance(points, bool) or not isinstance(points, int) or not 2 <= points <= MAX_POINTS:
        raise InvalidParameter('points', points, f'must be an integer in [2, {MAX_POINTS}]')
    _check_interpolation(interpolation)
    return _table(program, 360.0 * np.arange(points + 1) / points, interpolation, None)


def tolerance_table(program: MotionProgram, tolerance: float, interpolation: str = 'linear',
                    *, unit: tuple[str, float] = ('m or rad', 1.0)) -> CamTable:
    """Return a table of knots placed greedily whose interpolation stays within tolerance.

    unit (name, factor from SI) is how error messages state the allowed range.
    """
    _check_interpolation(interpolation)
    check_tolerance(program, tolerance, unit)
    pieces = piece_bounds(program)
    knots = [0.0]
    for start, end in zip(pieces[:-1], pieces[1:]):
        knots += place_knots(program, start, end, float(tolerance), interpolation)
        if len(knots) > MAX_POINTS:
            raise InvalidParameter('tolerance', tolerance,
                                   f'needs more than {MAX_POINTS} points: choose a larger one')
    return _table(program, np.degrees(knots), interpolation, float(tolerance))


def interpolate(table: CamTable, theta: FloatArray) -> FloatArray:
    """Return the table's interpolant at angles theta (rad, in [0, 2 pi])."""
    angle = table.angle
    index = np.clip(np.searchsorted(angle, theta, side='right') - 1, 0, angle.size - 2)
    start, span = angle[index], np.diff(angle)[index]
    left, right = (_Knots(table.position[at], table.slope[at], table.curvature[at])
                   for at in (index, index + 1))
    coefficients = _coefficients(span, left, right, table.interpolation)
    return _polynomial(coefficients, (theta - start) / span, span)[0]


def check_tolerance(program: MotionProgram, tolerance: float,
                    unit: tuple[str, float] = ('m or rad', 1.0)) -> None:
    """Raise unless tolerance lies between MIN_RELATIVE_TOLERANCE of the stroke and the stroke."""
    travel = stroke(program)
    low = MIN_RELATIVE_TOLERANCE * travel
    if not (isinstance(tolerance, (int, float)) and low <= tolerance <= travel):
        name, factor = unit
        raise InvalidParameter('tolerance', tolerance,
                               f'must be in [{low * factor:.6g}, {travel * factor:.6g}] {name}: '
                               f'from {MIN_RELATIVE_TOLERANCE:g} of the stroke to the stroke')


def interval_errors(program: MotionProgram, start: FloatArray, end: FloatArray,
                    interpolation: str) -> FloatArray:
    """Return the refined worst |s - p| on each interval [start, end] (rad) of an interpolant p."""
    return _errors(program, start, end, interpolation, CHECK_SAMPLES)


def _check_interpolation(interpolation: str) -> None:
    if interpolation not in INTERPOLATIONS:
        raise InvalidParameter('interpolation', interpolation,
                               'must be one of ' + ', '.join(INTERPOLATIONS))


def _table(program: MotionProgram, master_deg: FloatArray, interpolation: str,
           tolerance: Optional[float]) -> CamTable:
    """Evaluate the program at the knots and check the interpolation on every interval."""
    angle = np.radians(master_deg)
    values = program.evaluate(angle)
    errors = interval_errors(program, angle[:-1], angle[1:], interpolation)
    return CamTable(master_deg, values.s, values.ds, values.d2s, interpolation,
                    float(errors.max()), tolerance)


def piece_bounds(program: MotionProgram) -> FloatArray:
    """Return 0, the segment boundaries in (0, 2 pi) and 2 pi: the knots every table keeps."""
    starts = np.sort(np.mod([segment.start for segment in program.segments], TWO_PI))
    inner = starts[(starts > BOUNDARY_MERGE) & (starts < TWO_PI - BOUNDARY_MERGE)]
    if inner.size:
        inner = inner[np.concatenate(([True], np.diff(inner) > BOUNDARY_MERGE))]
    return np.concatenate(([0.0], inner, [TWO_PI]))


def place_knots(program: MotionProgram, start: float, end: float, tolerance: float,
                interpolation: str) -> list[float]:
    """Return the knots after start up to end: each the farthest whose interval meets tolerance.

    Placed for SEARCH_MARGIN of the tolerance, so that the final check stays within it.
    """
    target = SEARCH_MARGIN * tolerance
    knots: list[float] = []
    here = start
    resolution = SEARCH_RESOLUTION * (end - start)
    while not _errors(program, np.array([here]), np.array([end]), interpolation,
                      SEARCH_SAMPLES)[0] <= target:
        low, high = here, end
        while high - low > resolution:
            ends = np.linspace(low, high, CANDIDATES + 2)[1:-1]
            bad = _errors(program, np.full(CANDIDATES, here), ends, interpolation,
                          SEARCH_SAMPLES) > target
            first = int(np.argmax(bad)) if bad.any() else CANDIDATES
            high = ends[first] if first < CANDIDATES else high
            low = ends[first - 1] if first else low
        if low <= here:
            raise InvalidParameter('tolerance', target / SEARCH_MARGIN,
                                   f'cannot be met near {math.degrees(here):.6g} deg')
        knots.append(float(low))
        here = low
        if len(knots) > MAX_POINTS:
            raise InvalidParameter('tolerance', target / SEARCH_MARGIN,
                                   f'needs more than {MAX_POINTS} points: choose a larger one')
    knots.append(end)
    return knots


def _coefficients(span: FloatArray, left: _Knots, right: _Knots,
                  interpolation: str) -> FloatArray:
    """Return c (degree + 1, n) of p(t) = sum c_k t^k on each interval, t in [0, 1].

    Hermite pieces in t: the slopes and curvatures per rad times span and span^2.
    """
    rise = right.s - left.s
    if interpolation == 'linear':
        return np.array([left.s, rise])
    m0, m1 = span * left.ds, span * right.ds
    if interpolation == 'cubic':
        return np.array([left.s, m0, 3.0 * rise - 2.0 * m0 - m1, m0 + m1 - 2.0 * rise])
    q0, q1 = span ** 2 * left.d2s, span ** 2 * right.d2s
    return np.array([left.s, m0, 0.5 * q0,
                     10.0 * rise - 6.0 * m0 - 4.0 * m1 - 0.5 * (3.0 * q0 - q1),
                     -15.0 * rise + 8.0 * m0 + 7.0 * m1 + 0.5 * (3.0 * q0 - 2.0 * q1),
                     6.0 * rise - 3.0 * (m0 + m1) - 0.5 * (q0 - q1)])


def _horner(c: FloatArray, t: FloatArray) -> FloatArray:
    """Return sum c_k t^k (c's rows broadcast against t)."""
    value = c[-1] + 0.0 * t
    for row in c[-2::-1]:
        value = row + t * value
    return value


def _polynomial(c: FloatArray, t: FloatArray,
                span: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return p, dp/dtheta, d2p/dtheta2 of the pieces c at t (broadcast against c[k])."""
    power = np.arange(1.0, len(c)).reshape((-1,) + (1,) * (c.ndim - 1))
    first = c[1:] * power
    second = first[1:] * power[:-1] if len(c) > 2 else np.zeros_like(c[:1])
    return _horner(c, t), _horner(first, t) / span, _horner(second, t) / span ** 2


def _errors(program: MotionProgram, start: FloatArray, end: FloatArray, interpolation: str,
            samples: int) -> FloatArray:
    """Return the largest |s - p| on each interval [start, end] (rad) of an interpolant p."""
    ends = program.evaluate(np.concatenate((start, end)))
    count = start.size
    left = _Knots(ends.s[:count], ends.ds[:count], ends.d2s[:count])
    right = _Knots(ends.s[count:], ends.ds[count:], ends.d2s[count:])
    span = (end - start)[:, None]
    c = _coefficients(span[:, 0], left, right, interpolation)[:, :, None]

    def error(t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        exact = program.evaluate(start[:, None] + span * t)
        value, slope, curvature = _polynomial(c, t, span)
        return exact.s - value, exact.ds - slope, exact.d2s - curvature

    grid = np.linspace(0.0, 1.0, samples + 2)
    size = np.abs(error(grid[None, 1:-1])[0])
    worst = size.max(axis=1)
    peak = size.argmax(axis=1) + 1
    low, high = grid[peak - 1][:, None], grid[peak + 1][:, None]
    t = grid[peak][:, None]
    for _ in range(NEWTON_STEPS):  # refine each sampled peak: Newton on e'(theta) = 0
        _, slope, curvature = error(t)
        step = np.divide(slope, curvature, out=np.zeros_like(slope), where=curvature != 0.0)
        t = np.clip(t - step / span, low, high)
    refined = np.maximum(worst, np.abs(error(t)[0][:, 0]))
    return np.maximum(refined, _errors_at_breaks(program, start, end, c))


def _errors_at_breaks(program: MotionProgram, start: FloatArray, end: FloatArray,
                      c: FloatArray) -> FloatArray:
    """Return the largest |s - p| at the program's breaks strictly inside each interval (or 0).

    Where a slope jumps (a dwell next to constant velocity) the error peaks at the kink itself,
    where e' changes sign without passing through 0, so no sampled peak's Newton step lands there.
    """
    breaks = np.unique(np.mod(program.breaks, TWO_PI))
    breaks = np.concatenate((breaks, breaks + TWO_PI))  # intervals may end at 2 pi
    first = np.searchsorted(breaks, start, side='right')
    count = np.searchsorted(breaks, end, side='left') - first
    result = np.zeros(start.size)
    if not count.sum():
        return result
    interval = np.repeat(np.arange(start.size), count)
    at = breaks[np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
                + np.repeat(first, count)]
    span = end[interval] - start[interval]
    value = _polynomial(c[:, interval, 0], (at - start[interval]) / span, span)[0]
    np.maximum.at(result, interval, np.abs(program.evaluate(at).s - value))
    return result
