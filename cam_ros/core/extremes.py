"""Refine extremes and roots of a function of the cam angle from a dense sampling.

A dense grid (e.g. 7200 samples per revolution) locates where a quantity peaks or changes sign;
the grid value itself can be off by the curvature times the spacing squared. These functions take
the grid as a map and refine on the exact function, evaluated at any angles:

* ``refine_extremum(func, theta, values, kind)`` -> ``(value, angle)``: the global maximum
  (kind='max') or minimum (kind='min'). Every grid local extreme whose value could reach the grid
  extreme (it is within twice its own drop to a neighbour) is refined over its two neighbouring
  intervals, all brackets at once: golden section to POLISH_WIDTH rad, then one parabolic step;
  the value is then exact to rounding for a smooth extreme and exact at a break.
* ``refine_extrema(func, theta, values, kinds)`` -> ``[(value, angle), ...]``: the same for
  several functions computed together (func returns one row per function), in one search.
* ``refine_roots(func, theta, values)`` -> sorted angles where func changes sign, each found by
  bisection to a few ulps of the angle; a sign change across a jump at a break is reported at
  the break.

func maps a 1-D float array of angles (rad) to an array of values of the same shape, and must
accept any real angle (periodic functions are evaluated at angles outside [0, period) near the
wrap, e.g. -1e-4). theta is strictly increasing (one period [t0, t0 + period) when periodic) and
values = func(theta) (or the same quantity computed another way). breaks are the angles where
func or a derivative jumps (segment joints and law breakpoints, any order): a bracket holding a
break, or ending at one (a joint on a sample), is split there and each side is searched up to
BREAK_GAP of the break, never at it (the angle of a joint belongs to the segment after it). At a
side's end next to a break the one-sided limit is the candidate: extrapolated from two values a
gap apart, it is exact to rounding (the value at the gap itself falls short by the slope times
the gap, on the lenient side of a limit), so both one-sided limits at every break count and a
jump is never mistaken for a smooth peak. period=None treats theta as an open range.

Pure NumPy; vectorised over brackets (one call of func per iteration).
"""
from __future__ import annotations

import math
from typing import Callable, Optional, Sequence

import numpy as np
import numpy.typing as npt

from .cam_angles import TWO_PI

Array = npt.NDArray[np.float64]
Func = Callable[[Array], npt.ArrayLike]

#: Samples per revolution of the design checks (pressure angle, curvature, undercut, dynamics)
#: from which extremes are refined.
CHECK_SAMPLES = 7200
#: Bracket width (rad) at which golden section hands over to a final parabolic step.
POLISH_WIDTH = 1e-4
#: Distance (in units of eps times the period or the angle range) kept from a break.
BREAK_GAP = 8.0
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_EPS = float(np.finfo(float).eps)


def _call(func: Func, angles: Array) -> Array:
    """Return func at angles as a float array (the angles' shape, or rows of it)."""
    return np.asarray(func(angles), dtype=float)


def _grid(theta: npt.ArrayLike, values: npt.ArrayLike, rows: int = 0) -> tuple[Array, Array]:
    """Return theta (1-D) and values (1-D, or (rows, N) when rows) after checking they match."""
    t = np.asarray(theta, dtype=float).reshape(-1)
    v = np.asarray(values, dtype=float)
    v = v.reshape(rows, -1) if rows else v.reshape(-1)
    if v.shape[-1] != t.size or t.size < 3:
        raise ValueError(f'theta ({t.size}) and values ({v.shape[-1]}) must have the same size '
                         '>= 3')
    if not np.all(np.diff(t) > 0.0):
        raise ValueError('theta must be strictly increasing')
    return t, v


def _neighbours(t: Array, v: Array, period: Optional[float]) -> tuple[Array, ...]:
    """Return (left angle, left value, right angle, right value) of every sample.

    Periodic grids wrap (the neighbours of the ends are shifted by a period); open grids repeat
    the end sample as its own outer neighbour.
    """
    if period is None:
        return (np.concatenate((t[:1], t[:-1])), np.concatenate((v[:1], v[:-1])),
                np.concatenate((t[1:], t[-1:])), np.concatenate((v[1:], v[-1:])))
    return (np.concatenate((t[-1:] - period, t[:-1])), np.roll(v, 1),
            np.concatenate((t[1:], t[:1] + period)), np.roll(v, -1))


def _pieces(low: Array, high: Array, breaks: Array,
            gap: float) -> tuple[Array, Array, Array, Array]:
    """Split the brackets [low, high] at the breaks in them; keep gap away from each break.

    Overlapping brackets are merged into their union. A break at a bracket's end counts too:
    a bracket ending at a joint is searched up to gap before it, on the segment that ends
    there, not at the joint (which the next segment owns). Returns the pieces' ends a, b and
    the breaks they were moved off (nan where an end is no break's).
    """
    inner = breaks[(breaks >= low.min()) & (breaks <= high.max())]
    edges = np.unique(np.concatenate((low, high, inner)))
    a, b = edges[:-1], edges[1:]
    middle = 0.5 * (a + b)
    covered = (np.searchsorted(np.sort(low), middle, side='right')
               - np.searchsorted(np.sort(high), middle, side='left')) > 0
    a, b = a[covered], b[covered]
    is_break = np.isin(edges, inner)
    from_a = np.where(is_break[:-1][covered], a, np.nan)
    from_b = np.where(is_break[1:][covered], b, np.nan)
    a = np.where(is_break[:-1][covered], a + gap, a)
    b = np.where(is_break[1:][covered], b - gap, b)
    keep = b >= a
    return a[keep], b[keep], from_a[keep], from_b[keep]


def _nearest(cuts: Array, angles: Array) -> Array:
    """Return the break (of the sorted cuts, at least one) nearest to each angle."""
    padded = np.concatenate(([-np.inf], cuts, [np.inf]))
    right = np.searchsorted(padded, angles)
    low, high = padded[right - 1], padded[right]
    return np.where(angles - low <= high - angles, low, high)


def _extended_breaks(breaks: Optional[Sequence[float] | Array],
                     period: Optional[float]) -> Array:
    """Return the breaks (and, when periodic, their copies a period below and above)."""
    found = np.asarray(() if breaks is None else breaks, dtype=float).reshape(-1)
    if period is None:
        return np.sort(found)
    found = np.mod(found, period)
    return np.sort(np.concatenate((found - period, found, found + period)))


def _gap(t: Array, period: Optional[float]) -> float:
    """Return the distance kept from breaks: a few ulps of the largest angle met."""
    scale = period if period is not None else float(np.max(np.abs(t)))
    return BREAK_GAP * _EPS * max(scale, 1.0)


def _one_sided(f_end: Array, f_near: Array, end: Array, near: Array, cut: Array) -> Array:
    """Return the limit at the break cut of a score sampled at end and near (further in).

    Linear extrapolation over the gap: exact to rounding for a smooth score, where the value at
    end alone falls short by the slope times the gap. f_end where cut is nan or near left the
    piece (near == end).
    """
    with np.errstate(invalid='ignore', divide='ignore'):
        limit = f_end + (f_end - f_near) * (end - cut) / (near - end)
    return np.where(np.isfinite(cut) & (near != end), limit, f_end)


def _golden(score: Callable[[Array], Array], a: Array, b: Array, from_a: Array,
            from_b: Array) -> tuple[Array, Array]:
    """Return (best score, its angle) of every bracket [a, b], maximising score.

    score maps angles of shape (k, brackets) to scores of that shape. Golden section narrows
    each bracket to POLISH_WIDTH, then one parabolic step through the best three points lands on
    a smooth peak. The ends count as candidates; an end moved off a break (from_a, from_b; nan
    for none) scores the one-sided limit there, so an extreme at a break is found exactly.
    """
    width = float(np.max(b - a)) if a.size else 0.0
    steps = (math.ceil(math.log(POLISH_WIDTH / width) / math.log(_GOLDEN))
             if width > POLISH_WIDTH else 0)
    ends = np.stack((a, b))
    c, d = b - _GOLDEN * (b - a), a + _GOLDEN * (b - a)
    near_a = np.where(np.isfinite(from_a) & (2.0 * a - from_a <= b), 2.0 * a - from_a, a)
    near_b = np.where(np.isfinite(from_b) & (2.0 * b - from_b >= a), 2.0 * b - from_b, b)
    fc, fd, fa, fb, f_near_a, f_near_b = score(np.stack((c, d, a, b, near_a, near_b)))
    f_ends = np.stack((_one_sided(fa, f_near_a, a, near_a, from_a),
                       _one_sided(fb, f_near_b, b, near_b, from_b)))
    for _ in range(steps):
        left = fc >= fd  # the peak is in [a, d]: d becomes the right end
        a, fa = np.where(left, a, c), np.where(left, fa, fc)
        b, fb = np.where(left, d, b), np.where(left, fd, fb)
        fresh = np.where(left, b - _GOLDEN * (b - a), a + _GOLDEN * (b - a))
        f_fresh = score(fresh[np.newaxis])[0]
        c, d = np.where(left, fresh, d), np.where(left, c, fresh)
        fc, fd = np.where(left, f_fresh, fd), np.where(left, fc, f_fresh)
    left = fc >= fd  # parabola through (a, c, d) or (c, d, b) around the better inner point
    x0, x1, x2 = np.where(left, a, c), np.where(left, c, d), np.where(left, d, b)
    f0, f1, f2 = np.where(left, fa, fc), np.where(left, fc, fd), np.where(left, fd, fb)
    numerator = (x1 - x0) ** 2 * (f1 - f2) - (x1 - x2) ** 2 * (f1 - f0)
    denominator = (x1 - x0) * (f1 - f2) - (x1 - x2) * (f1 - f0)
    with np.errstate(divide='ignore', invalid='ignore'):
        vertex = x1 - 0.5 * numerator / denominator
    vertex = np.clip(np.where(np.isfinite(vertex), vertex, x1), x0, x2)
    angles = np.concatenate((vertex[np.newaxis], x1[np.newaxis], ends))
    scores = np.concatenate((score(vertex[np.newaxis]), f1[np.newaxis], f_ends))
    pick = np.argmax(scores, axis=0)
    columns = np.arange(pick.size)
    return scores[pick, columns], angles[pick, columns]


def _wrapped(angle: float, period: Optional[float]) -> float:
    """Return angle in [0, period) when periodic, else unchanged."""
    return angle if period is None else float(np.mod(angle, period))


def _sign(kind: str) -> float:
    """Return +1 for 'max', -1 for 'min'."""
    if kind not in ('max', 'min'):
        raise ValueError(f"kind = {kind!r}: must be 'max' or 'min'")
    return 1.0 if kind == 'max' else -1.0


def _brackets(t: Array, g: Array, period: Optional[float]) -> tuple[Array, Array, int]:
    """Return the brackets around every grid peak of g that could reach the top, and the top.

    A local peak qualifies when its value plus twice its larger drop to a neighbour reaches the
    grid's top (a parabola overshoots its samples by at most a quarter of that drop).
    """
    left_t, left_v, right_t, right_v = _neighbours(t, g, period)
    top = int(np.argmax(g))
    local = (g >= left_v) & (g >= right_v) & ((g > left_v) | (g > right_v))
    drop = np.maximum(g - left_v, g - right_v)
    chosen = local & (g + 2.0 * drop >= g[top])
    chosen[top] = True
    return left_t[chosen], right_t[chosen], top


def refine_extrema(func: Func, theta: npt.ArrayLike, values: npt.ArrayLike,
                   kinds: Sequence[str], *, breaks: Optional[Sequence[float] | Array] = None,
                   period: Optional[float] = TWO_PI) -> list[tuple[float, float]]:
    """Return (value, angle) of the extreme of each of several functions, refined together.

    func maps angles of shape (n,) to values of shape (m, n), one row per function; values (m, N)
    holds them on theta; kinds[i] is 'max' or 'min' for row i. One call of func per iteration
    serves every row, which is what makes this cheaper than m calls of refine_extremum.
    """
    signs = np.array([_sign(kind) for kind in kinds])
    rows = signs.size
    t, v = _grid(theta, values, rows)
    cuts, gap = _extended_breaks(breaks, period), _gap(t, period)
    found: list[tuple[Array, ...]] = []
    owners, tops = [], []
    for row in range(rows):  # one pass per function (a few), vectorised over the samples
        low, high, top = _brackets(t, signs[row] * v[row], period)
        found.append(_pieces(low, high, cuts, gap))
        owners.append(np.full(found[-1][0].size, row))
        tops.append(top)
    owner = np.concatenate(owners)
    columns = np.arange(owner.size)

    def score(points: Array) -> Array:
        found = _call(func, points.reshape(-1)).reshape(rows, points.shape[0], -1)
        return signs[owner] * found[owner, :, columns].T

    scores, angles = _golden(score, *(np.concatenate(ends) for ends in zip(*found)))
    results = []
    for row, top in enumerate(tops):
        mine = owner == row
        best = int(np.argmax(np.where(mine, scores, -np.inf)))
        grid_top = signs[row] * v[row][top]
        if scores[best] < grid_top:  # cannot happen for a func matching values; keep the grid's
            results.append((float(v[row][top]), float(t[top])))
        else:
            results.append((float(signs[row] * scores[best]),
                            _wrapped(float(angles[best]), period)))
    return results


def refine_extremum(func: Func, theta: npt.ArrayLike, values: npt.ArrayLike, kind: str = 'max',
                    *, breaks: Optional[Sequence[float] | Array] = None,
                    period: Optional[float] = TWO_PI) -> tuple[float, float]:
    """Return (value, angle) of the largest (kind='max') or smallest ('min') value of func.

    theta, values: the dense sampling (values = func(theta)); breaks: where func or a derivative
    jumps; see the module docstring. The angle is in [0, period) when periodic.
    """
    def rows(angles: Array) -> Array:
        return _call(func, angles)[np.newaxis]

    return refine_extrema(rows, theta, np.asarray(values, dtype=float)[np.newaxis], (kind,),
                          breaks=breaks, period=period)[0]


def refine_roots(func: Func, theta: npt.ArrayLike, values: npt.ArrayLike, *,
                 breaks: Optional[Sequence[float] | Array] = None,
                 period: Optional[float] = TWO_PI) -> Array:
    """Return the sorted angles where func changes sign (or is zero at a sample).

    Each grid interval whose end values differ in sign is split at the breaks inside it; a piece
    whose ends differ in sign is bisected to a few ulps, a sign change across a break (a jump)
    is reported at the break. Angles are in [0, period) when periodic.
    """
    t, v = _grid(theta, values)
    _, _, right_t, right_v = _neighbours(t, v, period)
    change = v * right_v < 0.0
    if period is None:
        change[-1] = False
    exact = t[v == 0.0]
    if not change.any():
        return np.sort(exact)
    cuts = _extended_breaks(breaks, period)
    gap = _gap(t, period)
    a, b, _, _ = _pieces(t[change], right_t[change], cuts, gap)
    ends = np.unique(np.concatenate((t[change], right_t[change])))
    if a.size:  # keep the samples outside every piece: at (or a gap from) a break, its side
        piece = np.maximum(np.searchsorted(a, ends, side='right') - 1, 0)
        ends = ends[(ends < a[piece]) | (ends >= b[piece])]
    order = np.argsort(np.concatenate((a, ends)), kind='stable')
    a, b = np.concatenate((a, ends))[order], np.concatenate((b, ends))[order]
    f_ends = _call(func, np.concatenate((a, b)))
    fa, fb = f_ends[:a.size], f_ends[a.size:]
    inside = fa * fb < 0.0
    across = (fb[:-1] * fa[1:] < 0.0) & (  # the two sides of one break, each a gap off it
        a[1:] - b[:-1] <= 2.0 * gap * (1.0 + 1e-9) + 4.0 * np.spacing(np.abs(b[:-1])) + _EPS)
    jumps = _nearest(cuts, 0.5 * (b[:-1] + a[1:])[across])
    low, high, f_low = a[inside], b[inside], fa[inside]
    width = float(np.max(high - low)) if low.size else 0.0
    floor = 2.0 * _EPS * float(np.max(np.abs(t)))
    steps = math.ceil(math.log2(width / floor)) if width > floor else 0
    for _ in range(steps):
        middle = 0.5 * (low + high)
        f_middle = _call(func, middle)
        same = f_middle * f_low > 0.0
        low, f_low = np.where(same, middle, low), np.where(same, f_middle, f_low)
        high = np.where(same, high, middle)
    roots = np.concatenate((exact, 0.5 * (low + high), jumps))
    if period is not None:
        roots = np.mod(roots, period)
    return np.unique(roots)
