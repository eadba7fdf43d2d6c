"""Circular arcs (G2/G3) fitted to a cutter path within its chordal tolerance.

A run of the path's points P_i .. P_j becomes one arc when the circle through P_i, the middle
point P_m and P_j, its centre rounded to the output's resolution as a file writes it, keeps the
exact contour within the tolerance over the run: |(|C(theta) - c| - r_i)| + |r_j - r_i| <= T,
the first term refined with extremes.refine_extrema (never below the truth), the second the
radius mismatch the rounded end points leave. Runs grow greedily from each kept point (doubling,
then bisection on the run's length); a run of one chord stays a line. Whether a run fits is not
monotone in its length, so a run found is one that fits next to one that does not, not always
the longest that would (every arc still keeps the tolerance). An arc turns through at
most MAX_SWEEP.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..extremes import refine_extrema, TWO_PI
from .machining import Contour, ToolPath

Array = np.ndarray
MAX_SWEEP = 2.0 * math.pi / 3.0  # rad: an arc turns through at most this
RUN_SAMPLES = 8  # samples per chord of a run for its deviation


@dataclass(frozen=True)
class Move:
    """One move of a path from point start to point end (indices into ToolPath.points; end 0
    closes the loop): a line when centre is None, else an arc about centre (m, rounded)."""

    start: int
    end: int
    centre: Optional[tuple[float, float]] = None


@dataclass(frozen=True)
class ArcPath:
    """A path's moves and its worst deviation from the exact contour (m), arcs included."""

    path: ToolPath
    moves: tuple[Move, ...]
    worst_deviation: float


def _circle(a: Array, b: Array, c: Array) -> Optional[Array]:
    """Return the centre of the circle through three points, None when they are collinear."""
    ab, ac = b - a, c - a
    det = 2.0 * (ab[0] * ac[1] - ab[1] * ac[0])
    scale = float(np.dot(ab, ab) + np.dot(ac, ac))
    if abs(det) <= 1e-12 * scale:
        return None
    shift = np.array((ac[1] * np.dot(ab, ab) - ab[1] * np.dot(ac, ac),
                      ab[0] * np.dot(ac, ac) - ac[0] * np.dot(ab, ab))) / det
    return a + shift


def _sweep(start: Array, middle: Array, end: Array, centre: Array) -> float:
    """Return the angle (rad) the arc from start through middle to end turns through."""
    def turn(p: Array, q: Array) -> float:
        u, v = p - centre, q - centre
        return abs(math.atan2(u[0] * v[1] - u[1] * v[0], float(np.dot(u, v))))
    return turn(start, middle) + turn(middle, end)


class _Fitter:
    """Tries runs of a path as arcs against the exact contour."""

    def __init__(self, contour: Contour, path: ToolPath, resolution: float):
        self.contour, self.path, self.resolution = contour, path, resolution
        self.knots = np.append(path.theta, path.theta[0] + TWO_PI)
        self.points = np.vstack((path.points, path.points[:1]))

    def arc(self, i: int, j: int) -> Optional[tuple[Array, float]]:
        """Return (rounded centre, deviation) of run i..j as an arc, None if it does not fit."""
        start, middle, end = self.points[i], self.points[(i + j) // 2], self.points[j]
        centre = _circle(start, middle, end)
        if centre is None or _sweep(start, middle, end, centre) > MAX_SWEEP:
            return None
        if self.resolution:
            centre = np.round(centre / self.resolution) * self.resolution
        radius = float(np.hypot(*(start - centre)))
        mismatch = abs(float(np.hypot(*(end - centre))) - radius)
        if mismatch > self.path.tolerance:
            return None

        def gap(angles: Array) -> Array:
            curve = self.contour.evaluate(np.mod(angles, TWO_PI))[0]
            return np.abs(np.hypot(curve[0] - centre[0], curve[1] - centre[1]) - radius)

        knots = self.knots[i:j + 1]
        share = np.arange(RUN_SAMPLES) / RUN_SAMPLES
        grid = np.append((knots[:-1, np.newaxis] + share * np.diff(knots)[:, np.newaxis]).ravel(),
                         knots[-1])
        worst, _ = refine_extrema(lambda angles: gap(angles)[np.newaxis], grid,
                                  gap(grid)[np.newaxis], ('max',), breaks=self.contour.breaks,
                                  period=None)[0]
        deviation = worst + mismatch
        return (centre, deviation) if deviation <= self.path.tolerance else None


def fit_arcs(contour: Contour, path: ToolPath, resolution: float = 0.0) -> ArcPath:
    """Return the path's moves with arcs where they fit (see the module doc).

    contour is the exact curve path was placed on; resolution (m) as for place_points.
    """
    fitter = _Fitter(contour, path, resolution)
    count = len(path.points)
    moves, worst, i = [], path.worst_deviation, 0
    while i < count:
        best: Optional[tuple[int, Array, float]] = None
        span = 2
        while i + span <= count and (found := fitter.arc(i, i + span)) is not None:
            best = (i + span, *found)
            span *= 2
        low, high = (best[0] - i if best else 1), min(span, count - i + 1)
        while high - low > 1:  # a fitting length next to a failing one
            middle = (low + high) // 2
            found = fitter.arc(i, i + middle)
            if found is None:
                high = middle
            else:
                low, best = middle, (i + middle, *found)
        if best is None:
            moves.append(Move(i, (i + 1) % count))
            i += 1
            continue
        end, centre, deviation = best
        moves.append(Move(i, end % count, (float(centre[0]), float(centre[1]))))
        worst = max(worst, deviation)
        i = end
    return ArcPath(path, tuple(moves), worst)


def lines_only(path: ToolPath) -> ArcPath:
    """Return the path as chords only: one line move per point."""
    count = len(path.points)
    return ArcPath(path, tuple(Move(i, (i + 1) % count) for i in range(count)),
                   path.worst_deviation)
