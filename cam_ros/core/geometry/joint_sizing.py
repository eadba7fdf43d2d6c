"""The smallest cam of a translating roller: base radius and offset chosen together.

With the roller centre at (e, d + s), d = sqrt(Rp^2 - e^2), the pressure angle obeys
tan phi = (v - x) / (d + s) with v = ds/dtheta and x = sigma e (followers.py). A limit L on a
side (rise: v >= 0, return: v <= 0, dwells on both; check.py) asks -tan L <= tan phi <= tan L,
which for each angle is a pair of half-planes for the cam centre in the (x, d) plane:

    d >= -(s - v cot L) - x cot L        and        d >= -(s + v cot L) + x cot L.

Over a side only the least of s - v cot L and of s + v cot L matters, so four lines (two per
side; the kinematics note's wedge is the rise's first and the return's second) and d >= 0 bound
the feasible centres: the region above F(x) = max_i (a_i + b_i x). The smallest prime radius
sqrt(x^2 + d^2) is at the foot of the perpendicular from the origin on one line, or where two
lines meet (the wedge's apex): every candidate is evaluated on F and the least is kept. The four
least values are extremes of the exact motion, refined with extremes.refine_extrema; the centre
is then raised (d grows, every margin with it) until the refined check of both limits holds,
so the result is on the safe side of each.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..errors import InvalidParameter
from ..extremes import CHECK_SAMPLES, refine_extrema, TWO_PI
from ..motion.program import MotionProgram
from .check import check_limits, GeometryExtremes, return_pressure_angle, rise_pressure_angle
from .check import PressureLimits, turning_breaks
from .followers import TranslatingRoller

#: Relative step by which the centre is raised when the refined check misses a limit (it grows
#: fourfold until both hold).
RAISE_STEP = 1e-13
RAISE_TRIES = 24


@dataclass(frozen=True)
class SmallestCam:
    """Smallest translating-roller cam meeting both pressure-angle limits (m).

    offset is signed as follower.offset (it lowers the rise's pressure angle: sigma e > 0);
    base_radius = prime_radius - roller_radius, None when the limits need a prime circle no
    larger than the roller (no positive base radius is bounded by them). governing names the
    limits met with equality: 'pressure_angle' (one limit for both sides), 'pressure_angle_rise',
    'pressure_angle_return' or 'pressure_angle_rise_and_return' (the wedge's apex).
    """

    base_radius: Optional[float]
    offset: float
    prime_radius: float
    governing: str
    rise_peak: float  # rad: largest |pressure angle| on the rise at the result (refined)
    return_peak: float  # rad: the same on the return


def _lines(program: MotionProgram, limits: PressureLimits,
           samples: int) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Return the intercepts a_i, slopes b_i and sides of the lines d >= a_i + b_i x."""
    theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    cot_rise, cot_ret = 1.0 / math.tan(limits.rise), 1.0 / math.tan(limits.ret)

    def rows(angles: np.ndarray) -> np.ndarray:
        motion = program.evaluate(angles)
        up, down = np.maximum(motion.ds, 0.0), np.minimum(motion.ds, 0.0)
        return np.array((motion.s - up * cot_rise, motion.s + up * cot_rise,
                         motion.s - down * cot_ret, motion.s + down * cot_ret))

    breaks = turning_breaks(program, theta, program.evaluate(theta).ds)
    least = [value for value, _ in refine_extrema(rows, theta, rows(theta), ('min',) * 4,
                                                  breaks=breaks)]
    intercepts = -np.array(least + [0.0])
    slopes = np.array((-cot_rise, cot_rise, -cot_ret, cot_ret, 0.0))
    return intercepts, slopes, ['rise', 'rise', 'return', 'return', 'geometry']


def _lowest_point(a: np.ndarray, b: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Return (x, d) nearest the origin with d >= max(a + b x), and which lines it lies on."""
    feet = -a * b / (1.0 + b * b)
    i, j = np.triu_indices(a.size, 1)
    crossing = b[i] != b[j]
    meets = (a[j] - a[i])[crossing] / (b[i] - b[j])[crossing]
    x = np.concatenate((feet, meets))
    height = np.max(a[:, np.newaxis] + b[:, np.newaxis] * x, axis=0)
    best = int(np.argmin(x * x + height * height))
    x_best, d_best = float(x[best]), float(height[best])
    scale = max(abs(x_best), abs(d_best), float(np.max(np.abs(a))), 1e-300)
    active = np.abs(a + b * x_best - d_best) <= 1e-9 * scale
    return x_best, d_best, active


def _governing(limits: PressureLimits, sides: list[str], active: np.ndarray) -> str:
    """Name what the optimum meets with equality (see SmallestCam)."""
    met = {side for side, on in zip(sides, active) if on}
    if 'geometry' in met:
        return 'geometry'
    if limits.single:
        return 'pressure_angle'
    return 'pressure_angle_' + '_and_'.join(side for side in ('rise', 'return') if side in met)


def _peaks(program: MotionProgram, x: float, d: float, sigma: int,
           samples: int) -> tuple[float, float]:
    """Return the refined largest |pressure angle| on the rise and on the return of a centre."""
    prime = math.hypot(x, d)
    follower = TranslatingRoller(0.5 * prime, 0.5 * prime, sigma * x)
    theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    motion = program.evaluate(theta)
    sampled = follower._geometry(theta, sigma, motion.s, motion.ds, motion.d2s)
    sampled.ds = motion.ds
    found = GeometryExtremes(follower, sigma < 0, theta, sampled, program).extremes(
        [(rise_pressure_angle, 'max'), (return_pressure_angle, 'max')])
    return found[0][0], found[1][0]


def smallest_cam(roller_radius: float, program: MotionProgram, *, max_pressure_angle: float,
                 max_pressure_angle_return: Optional[float] = None, clockwise: bool = False,
                 samples: int = CHECK_SAMPLES) -> Optional[SmallestCam]:
    """Return the smallest cam (prime radius) meeting both pressure-angle limits (rad).

    The motion is the cam surface's program (m); max_pressure_angle_return defaults to
    max_pressure_angle. None when no positive prime radius satisfies the limits (a program that
    never moves). samples locate the extremes before they are refined.
    """
    if not isinstance(program, MotionProgram):
        raise InvalidParameter('program', program, 'must be a MotionProgram')
    limits, _ = check_limits(max_pressure_angle, None, max_pressure_angle_return)
    assert limits is not None
    sigma = -1 if clockwise else 1
    a, b, sides = _lines(program, limits, samples)
    x, d, active = _lowest_point(a, b)
    raise_by = 0.0
    for _ in range(RAISE_TRIES):
        lifted = d + raise_by
        if lifted > 0.0:
            rise, ret = _peaks(program, x, lifted, sigma, samples)
            if min(limits.margins(rise, ret).values()) >= 0.0:
                prime = math.hypot(x, lifted)
                base = prime - roller_radius
                return SmallestCam(base if base > 0.0 else None, sigma * x, prime,
                                   _governing(limits, sides, active), rise, ret)
        raise_by = max(4.0 * raise_by, RAISE_STEP * max(math.hypot(x, d), float(np.ptp(a))))
    return None
