"""Base-radius sizing: an exact root find on sampled motion and the quick textbook estimate.

The exact sizing works on the motion samples it is given: the extremes of pressure angle and
curvature between samples are not seen, so pass densely sampled arrays (DENSE_SAMPLES = 3600 per
revolution or more; a table every 10 degrees can miss the worst angle by a wide margin).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .errors import InvalidParameter
from .geometry import (
    _check_follower, _check_limits, _check_motion, _geometry, _pressure_limit, _pressure_margin,
    _radius_margin, _real, Follower,
)

DENSE_SAMPLES = 3600  # samples per revolution recommended for sizing
SIZING_TOLERANCE = 1e-9  # m: the returned radius is within this (plus 4 ulp) of the exact one
SIZING_GRID = 256  # candidate radii scanned for the first feasible one (bounded followers)
DOUBLINGS = 40  # unbounded followers: scan Rb_min + scale * 2**k for k in [-DOUBLINGS, DOUBLINGS]
BIG_CAM_SIZE_INDEX = 5.0  # R/h above this is a big cam (seed 002)
_RTOL = 4.0 * float(np.finfo(float).eps)  # brentq's smallest relative tolerance
_INVALID = -1.0  # margin of a radius at which the follower cannot follow the motion


@dataclass(frozen=True)
class BaseRadiusSizing:
    """Smallest base radius meeting the limits, found on the sampled motion.

    follower is the input follower with base_radius replaced (None if infeasible). governing
    names what sets the radius: 'pressure_angle', 'radius' (curvature), 'geometry' (the follower
    cannot follow the motion below it) or 'search_bound' (the limits hold down to the smallest
    radius scanned); 'infeasible' when no scanned radius meets them.
    """

    follower: Optional[Follower]
    base_radius: Optional[float]
    governing: str
    tolerance: float

    @property
    def feasible(self) -> bool:
        """Return True if a radius meeting the limits was found."""
        return self.base_radius is not None


def _margins(follower: Follower, motion: tuple[np.ndarray, ...], clockwise: bool,
             angle: Optional[float], radius: Optional[float]) -> dict[str, float]:
    """Return each limit's margin (>= 0 when met) for one follower, or the invalid sentinel."""
    theta, s, ds, d2s = motion
    if follower._motion_problem(s, ds) is not None:
        return {'geometry': _INVALID}
    geometry = _geometry(follower, theta, s, ds, d2s, clockwise)
    margins = {}
    if angle is not None:
        margins['pressure_angle'] = _pressure_margin(geometry, angle)
    if radius is not None:
        margins['radius'] = _radius_margin(geometry, radius)
    return margins


def _candidates(follower: Follower, s: np.ndarray) -> np.ndarray:
    """Return increasing candidate base radii strictly inside the follower's valid range."""
    low, high = follower._base_radius_bounds()
    if math.isinf(high):
        scale = max(float(np.ptp(s)), getattr(follower, 'roller_radius', 0.0),
                    abs(getattr(follower, 'offset', 0.0))) or 1.0
        return low + scale * 2.0 ** np.arange(-DOUBLINGS, DOUBLINGS + 1)
    return np.linspace(low, high, SIZING_GRID + 2)[1:-1]


def size_base_radius(follower: Follower, theta: object, s: object, ds: object, d2s: object, *,
                     clockwise: bool = False, max_pressure_angle: Optional[float] = None,
                     min_radius: Optional[float] = None,
                     tolerance: float = SIZING_TOLERANCE) -> BaseRadiusSizing:
    """Find the smallest base radius (m) that meets the limits on the sampled motion.

    The limits: max |pressure angle| <= max_pressure_angle (rad) and radius of curvature of the
    convex parts of the surface >= min_radius (m); give one or both. The other follower parameters
    stay fixed. Candidate radii are scanned upwards and the first feasible one is refined with
    brentq against its infeasible predecessor; the result meets the limits and lies within
    tolerance (m) of the exact boundary. If the margins are not monotone in the radius, a feasible
    window narrower than the scan spacing can be missed. Pass dense samples (see DENSE_SAMPLES).
    """
    _check_follower(follower)
    motion = _check_motion(theta, s, ds, d2s)
    angle, radius = _check_limits(max_pressure_angle, min_radius)
    if angle is None and radius is None:
        raise InvalidParameter('max_pressure_angle', None,
                               'give max_pressure_angle and/or min_radius to size for')
    tol = _real('tolerance', tolerance, lambda x: x > 0.0, '> 0 (m)')

    def margins(base_radius: float) -> dict[str, float]:
        trial = dataclasses.replace(follower, base_radius=base_radius)
        return _margins(trial, motion, bool(clockwise), angle, radius)

    def worst(base_radius: float) -> float:
        return min(margins(base_radius).values())

    candidates = _candidates(follower, motion[1])
    index = next((i for i, r in enumerate(candidates) if worst(float(r)) >= 0.0), None)
    if index is None:
        return BaseRadiusSizing(None, None, 'infeasible', tol)
    if index == 0:
        found = float(candidates[0])
        return BaseRadiusSizing(dataclasses.replace(follower, base_radius=found), found,
                                'search_bound', tol)
    from scipy.optimize import brentq  # here: scipy costs the node 0.5 s start-up

    low, high = float(candidates[index - 1]), float(candidates[index])
    root = float(brentq(worst, low, high, xtol=tol, rtol=_RTOL))
    found = root if worst(root) >= 0.0 else min(high, root + tol + _RTOL * root)
    below = margins(max(low, found - 2.0 * (tol + _RTOL * found)))
    return BaseRadiusSizing(dataclasses.replace(follower, base_radius=found), found,
                            min(below, key=below.__getitem__), tol)


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
    return _real(name, value, lambda x: x > 0.0, rule)


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
    beta = _real('rise_angle', rise_angle, lambda x: 0.0 < x <= 2 * math.pi, 'in (0, 2 pi] rad')
    cv = _positive('velocity_coefficient', velocity_coefficient)
    phi = _pressure_limit(max_pressure_angle)
    eps = _real('eccentricity_angle', eccentricity_angle, lambda x: 0.0 <= x < math.pi / 2,
                'in [0, pi/2) rad')
    mean = cv * h / (beta * math.cos(eps) * (math.tan(phi) + math.tan(eps)))
    sigma = -1.0 if clockwise else 1.0
    return BaseRadiusEstimate(mean, mean - h / 2.0, sigma * mean * math.sin(eps), mean / h)
