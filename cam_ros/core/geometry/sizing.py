"""Base-radius sizing: an exact root find on the motion and the quick textbook estimate.

Given the motion program, the sizing refines every extreme of pressure angle and curvature
between the samples on the exact motion, so the limits hold at the returned radius. Without it,
it works on the samples alone and the extremes between them are not seen: then pass densely
sampled arrays (DENSE_SAMPLES = 3600 per revolution or more; a table every 10 degrees can miss
the worst angle by a wide margin).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ..errors import InvalidParameter
from .followers import check_follower, checked_real, Follower
from .cam_geometry import check_motion
from .check import (abs_pressure_angle, check_limits, GeometryExtremes, Measure, pressure_limit,
                    PressureLimits, radius_margin, return_pressure_angle, rise_pressure_angle,
                    worst_curvature)
from ..motion.program import MotionProgram

DENSE_SAMPLES = 3600  # samples per revolution recommended for sizing
SIZING_TOLERANCE = 1e-16  # m: the returned radius is within this (plus 4 ulp) of the exact one
SAFETY_ULPS = 4  # ulps added on the safe side of the boundary for the margins' rounding
SIZING_GRID = 256  # candidate radii scanned for the first feasible one (bounded followers)
DOUBLINGS = 40  # unbounded followers: scan Rb_min + scale * 2**k for k in [-DOUBLINGS, DOUBLINGS]
BIG_CAM_SIZE_INDEX = 5.0  # R/h above this is a big cam (seed 002)
_RTOL = 4.0 * float(np.finfo(float).eps)  # brentq's smallest relative tolerance
_INVALID = -1.0  # margin of a radius at which the follower cannot follow the motion

Margins = Callable[[float, bool], dict[str, float]]


@dataclass(frozen=True)
class BaseRadiusSizing:
    """Smallest base radius meeting the limits, found on the sampled (or exact) motion.

    follower is the input follower with base_radius replaced (None if infeasible). governing
    names what sets the radius: 'pressure_angle', 'radius' (curvature), 'geometry' (the follower
    cannot follow the motion below it) or 'search_bound' (the limits hold down to the smallest
    radius scanned); 'infeasible' when no scanned radius meets them. max_base_radius is the
    upper end of the feasible interval that starts at base_radius when the follower's base
    radius is bounded (oscillating followers), set by max_governing; None for translating
    followers (the limits only ease as the cam grows).
    """

    follower: Optional[Follower]
    base_radius: Optional[float]
    governing: str
    tolerance: float
    max_base_radius: Optional[float] = None
    max_governing: str = ''

    @property
    def feasible(self) -> bool:
        """Return True if a radius meeting the limits was found."""
        return self.base_radius is not None


def _margins(follower: Follower, motion: tuple[np.ndarray, ...], clockwise: bool,
             angles: Optional[PressureLimits], radius: Optional[float],
             program: Optional[MotionProgram]) -> dict[str, float]:
    """Return each limit's margin (>= 0 when met) for one follower, or the invalid sentinel.

    With a program the extremes are refined on the exact motion, else the samples' are taken.
    Two pressure-angle limits give a margin per side (check.py's rise and return).
    """
    theta, s, ds, d2s = motion
    if follower._motion_problem(s, ds) is not None:
        return {'geometry': _INVALID}
    wanted: dict[str, tuple[Measure, str]] = {}
    if angles is not None and angles.single:
        wanted['pressure_angle'] = (abs_pressure_angle, 'max')
    elif angles is not None:
        wanted['rise'] = (rise_pressure_angle, 'max')
        wanted['return'] = (return_pressure_angle, 'max')
    if radius is not None:
        wanted['radius'] = worst_curvature(follower)
    sampled = follower._geometry(theta, -1 if clockwise else 1, s, ds, d2s)
    sampled.ds = ds
    extremes = GeometryExtremes(follower, clockwise, theta, sampled, program)
    found = {name: value for name, (value, _) in zip(wanted, extremes.extremes(
        list(wanted.values())))}
    margins = {}
    if angles is not None:
        margins = angles.margins(found.get('rise', found.get('pressure_angle', 0.0)),
                                 found.get('return', found.get('pressure_angle', 0.0)))
    if radius is not None:
        margins['radius'] = radius_margin(follower, found['radius'], radius)
    return margins


def _candidates(follower: Follower, s: np.ndarray) -> np.ndarray:
    """Return increasing candidate base radii strictly inside the follower's valid range."""
    low, high = follower._base_radius_bounds()
    if math.isinf(high):
        scale = max(float(np.ptp(s)), getattr(follower, 'roller_radius', 0.0),
                    abs(getattr(follower, 'offset', 0.0))) or 1.0
        return low + scale * 2.0 ** np.arange(-DOUBLINGS, DOUBLINGS + 1)
    return np.linspace(low, high, SIZING_GRID + 2)[1:-1]


def _boundary(margins: Margins, bad: float, good: float, tol: float) -> tuple[float, str]:
    """Return the radius nearest the boundary between bad and good where the limits hold.

    The limits fail at bad and hold at good (exact margins); the result lies on good's side,
    within tol (+ 4 ulp) of the boundary and SAFETY_ULPS past the first radius whose computed
    margins hold; the limit that fails just beyond it is named.
    """
    from scipy.optimize import brentq  # here: scipy costs the node 0.5 s start-up

    def worst(base_radius: float, exact: bool = True) -> float:
        return min(margins(base_radius, exact).values())

    def solve(func: Callable[[float], float], low: float, high: float) -> float:
        return float(brentq(func, min(low, high), max(low, high), xtol=tol, rtol=_RTOL))

    toward = math.copysign(1.0, good - bad)
    if worst(bad, False) < 0.0:  # narrow the bracket on the cheap sampled margins first
        near = solve(lambda radius: worst(radius, False), bad, good)
        if worst(near) < 0.0:  # sampled margins are never below exact ones
            bad = near
            for widen in (1e-7, 1e-5, 1e-3):
                trial = near + toward * widen * abs(near)
                if (trial - good) * toward >= 0.0:
                    break
                if worst(trial) >= 0.0:
                    good = trial
                    break
                bad = trial
    root = solve(worst, bad, good)
    step = tol + _RTOL * abs(root)
    found = good
    for shift in (0.0, 1.0, 2.0, 4.0, 8.0):
        trial = root + toward * shift * step
        if (trial - good) * toward >= 0.0:
            break
        if worst(trial) >= 0.0:  # then SAFETY_ULPS more, for the rounding of the margins
            found = trial + toward * SAFETY_ULPS * math.ulp(trial)
            found = found if (found - good) * toward < 0.0 else good
            break
    beyond = margins(found - toward * 2.0 * step, True)
    return found, min(beyond, key=beyond.__getitem__)


def _lowest_feasible(margins: Margins, candidates: np.ndarray) -> Optional[int]:
    """Return the first candidate index whose exact margins all hold.

    Sampled margins are never below exact ones, so candidates failing on the samples are
    skipped with the cheap test.
    """
    for index in range(candidates.size):
        radius = float(candidates[index])
        if all(min(margins(radius, exact).values()) >= 0.0 for exact in (False, True)):
            return index
    return None


def size_base_radius(follower: Follower, theta: object, s: object, ds: object, d2s: object, *,
                     clockwise: bool = False, max_pressure_angle: Optional[float] = None,
                     min_radius: Optional[float] = None, tolerance: float = SIZING_TOLERANCE,
                     program: Optional[MotionProgram] = None,
                     max_pressure_angle_return: Optional[float] = None) -> BaseRadiusSizing:
    """Find the smallest base radius (m) that meets the limits on the sampled motion.

    The limits: max |pressure angle| <= max_pressure_angle (rad) on the rise and
    max_pressure_angle_return on the return (default: the same; sides as in check.py), and
    radius of curvature of the convex parts of the surface >= min_radius (m); give a
    pressure-angle limit, min_radius or both. The other follower parameters
    stay fixed. Candidate radii are scanned upwards and the first feasible one is refined with
    brentq against its infeasible predecessor; the result meets the limits and lies within
    tolerance (m) of the exact boundary. If the margins are not monotone in the radius, a feasible
    window narrower than the scan spacing can be missed. Given program (the motion the samples
    come from), every extreme is refined between the samples on the exact motion, so the limits
    hold exactly at the returned radius; without it pass dense samples (see DENSE_SAMPLES).
    For followers with a bounded base radius the feasible interval's upper end is found too.
    """
    check_follower(follower)
    motion = check_motion(theta, s, ds, d2s)
    angle, radius = check_limits(max_pressure_angle, min_radius, max_pressure_angle_return)
    if angle is None and radius is None:
        raise InvalidParameter('max_pressure_angle', None,
                               'give max_pressure_angle and/or min_radius to size for')
    if program is not None and not isinstance(program, MotionProgram):
        raise InvalidParameter('program', program, 'must be a MotionProgram or None')
    tol = checked_real('tolerance', tolerance, lambda x: x > 0.0, '> 0 (m)')

    def margins(base_radius: float, exact: bool) -> dict[str, float]:
        trial = dataclasses.replace(follower, base_radius=base_radius)
        return _margins(trial, motion, bool(clockwise), angle, radius,
                        program if exact else None)

    candidates = _candidates(follower, motion[1])
    index = _lowest_feasible(margins, candidates)
    if index is None:
        return BaseRadiusSizing(None, None, 'infeasible', tol)
    if index == 0:
        found, governing = float(candidates[0]), 'search_bound'
    else:
        found, governing = _boundary(margins, float(candidates[index - 1]),
                                     float(candidates[index]), tol)
    top, top_governing = _upper_end(margins, follower, candidates, index, tol)
    return BaseRadiusSizing(dataclasses.replace(follower, base_radius=found), found, governing,
                            tol, top, top_governing)


def _upper_end(margins: Margins, follower: Follower, candidates: np.ndarray, index: int,
               tol: float) -> tuple[Optional[float], str]:
    """Return the upper end of the feasible interval holding candidates[index] (bounded only).

    (None, '') for followers whose base radius is unbounded above.
    """
    if math.isinf(follower._base_radius_bounds()[1]):
        return None, ''
    beyond = next((j for j in range(index + 1, candidates.size)
                   if min(margins(float(candidates[j]), False).values()) < 0.0), None)
    if beyond is None:
        last = candidates.size - 1
        while min(margins(float(candidates[last]), True).values()) < 0.0:
            last -= 1  # stops at index, which holds
        if last == candidates.size - 1:
            return float(candidates[last]), 'search_bound'
        beyond = last + 1
    good = beyond - 1
    while min(margins(float(candidates[good]), True).values()) < 0.0:
        good -= 1
    return _boundary(margins, float(candidates[good + 1]), float(candidates[good]), tol)


@dataclass(frozen=True)
class BaseRadiusEstimate:
    """Quick base-radius estimate for a translating roller (seed 002), all lengths in m.

    mean_radius R is the distance of the roller centre from the cam centre at mid-rise;
    prime_radius = R - h/2 is the prime circle (cam base radius + roller radius; may come out <= 0
    when the limit is lax); offset = sigma R sin(eccentricity_angle) is signed for the rotation so
    that it lowers the rise pressure angle; size_index = R/h.
    """

    mean_radius: float
    prime_radius: float
    offset: float
    size_index: float

    @property
    def big_cam(self) -> bool:
        """Return True if the size index R/h exceeds BIG_CAM_SIZE_INDEX."""
        return self.size_index > BIG_CAM_SIZE_INDEX


def _positive(name: str, value: float, rule: str = '> 0') -> float:
    return checked_real(name, value, lambda x: x > 0.0, rule)


def estimate_base_radius(rise: float, rise_angle: float, velocity_coefficient: float,
                         max_pressure_angle: float, *, eccentricity_angle: float = 0.0,
                         clockwise: bool = False) -> BaseRadiusEstimate:
    """Estimate the prime radius from the peak rise velocity (seed 002's quick method).

    With ds/dtheta peaking at Cv h / beta near mid-rise, where the roller centre is at distance R:
    R = Cv h / (beta cos(eps) (tan(phi_max) + tan(eps))), prime radius R - h/2, offset R sin(eps).
    rise h (m) > 0, rise_angle beta (rad) in (0, 2 pi], velocity_coefficient Cv > 0,
    max_pressure_angle phi_max (rad) in (0, pi/2), eccentricity_angle eps (rad) in [0, pi/2).
    """
    h = _positive('rise', rise, '> 0 (m)')
    beta = checked_real('rise_angle', rise_angle, lambda x: 0.0 < x <= 2 * math.pi,
                        'in (0, 2 pi] rad')
    cv = _positive('velocity_coefficient', velocity_coefficient)
    phi = pressure_limit(max_pressure_angle)
    eps = checked_real('eccentricity_angle', eccentricity_angle, lambda x: 0.0 <= x < math.pi / 2,
                       'in [0, pi/2) rad')
    mean = cv * h / (beta * math.cos(eps) * (math.tan(phi) + math.tan(eps)))
    sigma = -1.0 if clockwise else 1.0
    return BaseRadiusEstimate(mean, mean - h / 2.0, sigma * mean * math.sin(eps), mean / h)
