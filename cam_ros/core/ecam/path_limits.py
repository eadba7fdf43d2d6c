"""
How fast and how hard the master of a machine may move so that every axis stays within its limits:
the limit curves of time-optimal path parameterization (the phase-plane method), per design.

Axis i follows y_i(theta) of the master position theta. At master speed w and acceleration a it
moves at v_i = y_i' w and accelerates at acc_i = y_i'' w^2 + y_i' a. With s = w^2, the limits
|v_i| <= V_i and |acc_i| <= A_i are linear in (s, a):

- speed: s <= V_i^2 / y_i'^2 and, where y_i' = 0, s <= A_i / |y_i''|;
- acceleration: -A_i - y_i'' s <= y_i' a <= A_i - y_i'' s, a band of a whose ends are linear in s.

So at each theta the admissible accelerations are an interval [lower(s), upper(s)] (lower convex,
upper concave in s) and the admissible speeds an interval s <= s_max(theta): the maximum velocity
curve, where the bands of two axes stop overlapping. Both are computed exactly at any theta from
the cams (admissible, speed_limit).

A stop must be possible from every state the master is let into: the braking curve
stoppable(theta) is the largest speed from which decelerating as hard as the limits allow
(a = lower(s)) reaches rest without crossing the maximum velocity curve. It is integrated backward
over GRID points per machine cycle and every segment joint (both sides: a jump of y'' is a break),
once per design, with the collocation of TOPP-RA (ds/dtheta = 2 a, the constraints at the grid
points), around the cycle until it repeats; online it is read, the lower of the two neighbouring
grid values (the safe side). Every limit is taken MARGIN below its value: the grid's
collocation and a controller stepping in time both stay inside.

Without any acceleration limit a stop would take one message; then a stop of the master is
limited to the deceleration that stops its speed as the stop begins (at least the speed at
cam_speed) over master.engage_distance_deg of travel, the travel of an engagement ramp, and a
catch-up likewise at the faster of the master and the virtual master (master_limit); a master
followed is not limited.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..cam_angles import TWO_PI
from .master import ElectronicCam
from .slave_limits import SlaveLimits

#: Grid points of the braking curve per machine cycle (more at every segment joint).
GRID = 4096
#: Every limit is applied this fraction below its value (see the module docstring).
MARGIN = 0.01
#: How far either side of a segment joint its one-sided values are taken (rad of master).
SIDE = 1e-9
#: The braking curve holds for steps over up to WINDOW - 2 grid cells (line_shaft's substeps).
WINDOW = 4
#: A slope below this fraction of the axis's steepest counts as none (see bands).
RESTING = 1e-12
#: Backward passes around the cycle at most; the braking curve repeats after two for any cam
#: whose stop takes less than a cycle, and only ever falls.
PASSES = 8


@dataclass(frozen=True)
class Bands:
    """The admissible accelerations of every axis at some master positions, linear in s = w^2.

    Axis i (rows) at point k (columns) allows lower0 + lower1 s <= a <= upper0 + upper1 s and
    s <= cap; an axis whose velocity y' is 0 there bounds only s.
    """

    lower0: np.ndarray
    lower1: np.ndarray
    upper0: np.ndarray
    upper1: np.ndarray
    cap: np.ndarray  # s bound of each point, over every axis

    def lower(self, s: npt.ArrayLike) -> np.ndarray:
        """Return the least admissible acceleration at each point for speeds squared s."""
        return np.max(self.lower0 + self.lower1 * s, axis=0)

    def upper(self, s: npt.ArrayLike) -> np.ndarray:
        """Return the largest admissible acceleration at each point for speeds squared s."""
        return np.min(self.upper0 + self.upper1 * s, axis=0)

    def speed_cap(self) -> np.ndarray:
        """Return the maximum velocity curve s_max at each point: lower(s) <= upper(s) and the
        speed bounds hold exactly for s <= s_max (the constraints are linear in s)."""
        # lower_i(s) <= upper_j(s) for every pair: (lower0_i - upper0_j) + (lower1_i - upper1_j)
        # s <= 0, with lower0 <= 0 <= upper0: a bound on s where the slope is positive.
        slope = self.lower1[:, np.newaxis] - self.upper1[np.newaxis]
        room = self.upper0[np.newaxis] - self.lower0[:, np.newaxis]
        with np.errstate(divide='ignore', invalid='ignore'):
            bound = np.where(slope > 0.0, room / slope, np.inf)
        return np.minimum(self.cap, bound.min(axis=(0, 1)))


def bands(slope: np.ndarray, curvature: np.ndarray, max_velocity: np.ndarray,
          max_acceleration: np.ndarray) -> Bands:
    """
    Return the bands of axes (rows) at points (columns) from y' and y'' per rad of master.

    max_velocity, max_acceleration: per axis (inf: none), already less the margin.
    """
    v, acc = max_velocity[:, np.newaxis], max_acceleration[:, np.newaxis]
    # A slope this small (relative to the axis's steepest) moves nothing however hard the
    # master accelerates: the axis bounds only the speed there (1 / y' would overflow).
    moving = np.abs(slope) > RESTING * np.abs(slope).max(axis=-1, keepdims=True)
    with np.errstate(divide='ignore', invalid='ignore'):
        inverse = np.where(moving, 1.0 / np.where(moving, slope, 1.0), 0.0)
        speed = np.where(moving, (v * inverse) ** 2, np.inf)
        still = np.where(moving | (curvature == 0.0), np.inf, acc / np.abs(curvature))
        # slope a in [-A - y'' s, A - y'' s]: divided by slope, ends swapped where negative.
        finite = np.isfinite(acc) & moving
        one = np.where(finite, -np.abs(acc * inverse), -np.inf)
    slope_s = np.where(moving, -curvature * inverse, 0.0)
    return Bands(one, np.where(finite, slope_s, 0.0), -one, np.where(finite, slope_s, 0.0),
                 np.minimum(speed, still).min(axis=0))


@dataclass(frozen=True, eq=False)
class PathLimits:
    """
    A machine's master limits over one machine cycle (rad of master), from its axes' cams.

    theta: the grid (one cycle from 0, both sides of every joint); forward and backward: the
    braking curve as a speed (rad/s) at each grid point for a master moving forward or backward.
    master_acceleration: the master's own limit (inf unless no axis limits acceleration).
    """

    cams: tuple[ElectronicCam, ...]
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    cycle: float
    theta: np.ndarray
    forward: np.ndarray
    backward: np.ndarray
    master_acceleration: float  # master_limit at the speed at cam_speed (inf: axes limit it)
    engage_distance: float
    nominal_speed: float  # the master speed at cam_speed (rad/s)
    bands: Bands  # the axes' (not the master's own) at the grid points (the first again last)

    @classmethod
    def of(cls, cams: Sequence[ElectronicCam], limits: Sequence[SlaveLimits],
           nominal_speed: float, engage_distance: float) -> 'PathLimits':
        """Compute the limits of axes on cams with their limits (the braking curve: once)."""
        keep = 1.0 - MARGIN
        velocity = np.array([lim.max_velocity * keep if lim.max_velocity else np.inf
                             for lim in limits])  # 0: none; any positive limit is one
        acceleration = np.array([lim.max_acceleration * keep if lim.max_acceleration else np.inf
                                 for lim in limits])
        master = np.inf
        if not np.isfinite(acceleration).any():
            master = nominal_speed * nominal_speed / (2.0 * engage_distance) * keep
        cycle = TWO_PI * max(cam.mapping.master_scaling for cam in cams)
        joints = np.concatenate([cam.breaks(0.0, cycle) for cam in cams])
        theta = np.unique(np.concatenate([
            np.linspace(0.0, cycle, GRID, endpoint=False),
            np.clip(joints - SIDE, 0.0, cycle), np.clip(joints + SIDE, 0.0, cycle)]))
        theta = theta[theta < cycle]
        slope, curvature = _derivatives(cams, theta)
        ahead = _machine_bands(slope, curvature, velocity, acceleration, master)
        behind = _machine_bands(-slope[:, ::-1], curvature[:, ::-1], velocity, acceleration,
                                master)
        forward = _braking(_window(ahead), np.diff(np.append(theta, cycle)))
        backward = _braking(_window(behind), np.append(
            -np.diff(theta[::-1]), theta[0] + cycle - theta[-1]))[::-1]
        axes = bands(slope, curvature, velocity, acceleration)
        wrapped = Bands(*(np.concatenate([part, part[..., :1]], axis=-1) for part in (
            axes.lower0, axes.lower1, axes.upper0, axes.upper1, axes.cap)))
        return cls(tuple(cams), velocity, acceleration, cycle, theta, forward, backward, master,
                   engage_distance, nominal_speed, wrapped)

    def master_limit(self, omega: float) -> float:
        """Return the master's own acceleration limit in a stop or a catch-up at speed omega:
        inf when an axis limits acceleration, else the stop over the engage distance from
        omega (at least the speed at cam_speed)."""
        if math.isinf(self.master_acceleration):
            return math.inf
        return max(self.master_acceleration, omega * omega / (2.0 * self.engage_distance)
                   * (1.0 - MARGIN))

    def _bands_at(self, theta: npt.ArrayLike) -> Bands:
        """Return the machine's bands exactly at master positions theta."""
        slope, curvature = _derivatives(self.cams, theta)
        return _machine_bands(slope, curvature, self.max_velocity, self.max_acceleration,
                              self.master_acceleration)

    def admissible(self, theta: float, omega: float) -> tuple[float, float, float]:
        """
        Return, exactly at a master position and speed, the largest admissible speed (rad/s,
        the maximum velocity curve) and the admissible master accelerations (least, largest).
        """
        found = self._bands_at(theta)
        s = omega * omega
        return (math.sqrt(float(found.speed_cap()[0])), float(found.lower(s)[0]),
                float(found.upper(s)[0]))

    def band(self, theta: float, omega: float, travel: float = 0.0) -> tuple[float, float]:
        """Return the master accelerations (least, largest) the axes admit at a master speed
        from the grid, on the safe side over the grid points around theta and travel (rad) on
        (the master's own limit is not in it: it bounds stops, not a master followed)."""
        found, s = self.bands, omega * omega
        span, count = self._span(theta, travel), len(self.theta)
        cells: slice | np.ndarray = span
        if span.stop - span.start > count:  # a cycle or more: every point
            cells = slice(None)
        elif span.stop > count + 1:
            cells = np.arange(span.start, span.stop) % count
        lower = found.lower0[:, cells] + found.lower1[:, cells] * s
        upper = found.upper0[:, cells] + found.upper1[:, cells] * s
        return float(lower.max()), float(upper.min())

    def _span(self, theta: float, travel: float) -> slice:
        """Return the grid points from the one at or before theta to the one at or after
        theta + travel (indexes may pass the grid's end: they wrap)."""
        grid, cycle, count = self.theta, self.cycle, len(self.theta)
        low, high = sorted((theta, theta + travel))
        turn_low, turn_high = math.floor(low / cycle), math.floor(high / cycle)
        first = int(np.searchsorted(grid, low - turn_low * cycle, side='right')) - 1
        last = int(np.searchsorted(grid, high - turn_high * cycle, side='left')) + \
            (turn_high - turn_low) * count
        return slice(first, max(last, first + 1) + 1)

    def speed_limit(self, theta: npt.ArrayLike) -> np.ndarray:
        """Return the maximum velocity curve (rad/s) at master positions theta, exactly."""
        return np.sqrt(self._bands_at(theta).speed_cap())

    def stoppable(self, theta: float, direction: float, travel: float = 0.0) -> float:
        """
        Return the fastest speed (rad/s) at theta, moving in direction (+1 or -1), from which a
        stop within every limit exists: the braking curve, its least over the grid points
        around theta and the travel ahead (rad, in the direction; safe side of the grid).
        """
        curve = self.forward if direction >= 0.0 else self.backward
        cells = self._span(theta, math.copysign(travel, direction))
        if cells.stop - cells.start > len(curve):
            return float(curve.min())
        return float(curve.take(range(cells.start, cells.stop), mode='wrap').min())


def _derivatives(cams: Sequence[ElectronicCam], theta: npt.ArrayLike
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Return rows y' and y'' of every cam at master positions theta."""
    at = np.atleast_1d(np.asarray(theta, dtype=float))
    parts = [cam.derivatives(at) for cam in cams]
    return (np.array([np.asarray(part.dy, dtype=float) for part in parts]),
            np.array([np.asarray(part.d2y, dtype=float) for part in parts]))


def _machine_bands(slope: np.ndarray, curvature: np.ndarray, max_velocity: np.ndarray,
                   max_acceleration: np.ndarray, master: float) -> Bands:
    """Return the axes' bands, with the master's own acceleration limit as one more axis."""
    found = bands(slope, curvature, max_velocity, max_acceleration)
    if not math.isfinite(master):
        return found
    own = np.full((1, slope.shape[1]), master)
    zero = np.zeros_like(own)
    return Bands(np.vstack([found.lower0, -own]), np.vstack([found.lower1, zero]),
                 np.vstack([found.upper0, own]), np.vstack([found.upper1, zero]), found.cap)


def _window(found: Bands) -> Bands:
    """Return at each point the bands of it and the WINDOW - 1 points after it together: what
    a step over up to WINDOW - 2 cells from there must keep (its speed cap included)."""
    def stacked(part: np.ndarray) -> np.ndarray:
        return np.concatenate([np.roll(part, -shift, axis=1) for shift in range(WINDOW)])

    cap = np.min([np.roll(found.cap, -shift) for shift in range(WINDOW)], axis=0)
    return Bands(stacked(found.lower0), stacked(found.lower1), stacked(found.upper0),
                 stacked(found.upper1), cap)


def _braking(found: Bands, steps: np.ndarray) -> np.ndarray:
    """
    Return the braking curve (speed) at the bands' points, for a master moving toward higher
    indexes with steps[k] of travel from point k to k + 1 (the last back to the first).

    From point k, decelerating as hard as allowed, s_{k+1} = s_k + 2 steps_k lower_k(s_k) must
    be at most the curve at k + 1; lower_k is the max of lines l0 + l1 s, so s_k is bounded by
    (K_{k+1} - 2 h l0) / (1 + 2 h l1) for every line with 1 + 2 h l1 > 0 (TOPP-RA's backward
    pass, in closed form).
    """
    cap = found.speed_cap()
    count = len(cap)
    l0, l1 = found.lower0.T.tolist(), found.lower1.T.tolist()
    caps, hs = cap.tolist(), steps.tolist()
    curve = list(caps)
    for _ in range(PASSES):
        before = curve[0]
        following = curve[0]
        for k in range(count - 1, -1, -1):
            best, h2 = caps[k], 2.0 * hs[k]
            for c0, c1 in zip(l0[k], l1[k]):
                gain = 1.0 + h2 * c1
                if gain > 0.0 and c0 != -math.inf:
                    best = min(best, (following - h2 * c0) / gain)
            best = max(best, 0.0)
            curve[k], following = best, best
        if curve[0] == before:
            break
    return np.sqrt(np.array(curve))
