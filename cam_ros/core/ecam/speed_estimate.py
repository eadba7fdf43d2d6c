"""
Master speed and acceleration from stamped positions: a least-squares quadratic over a window.

The quadratic q(t) = c0 + c1 (t - t_n) + c2 (t - t_n)^2 that fits the positions of a window best
(least squares) gives omega = c1 and alpha = 2 c2 at the newest stamp t_n. Through three samples
it is the interpolating quadratic (the classic three-point estimate); over more it averages stamp
jitter. Either way it is exact for a master at constant acceleration, at any stamp spacing.

Stamps that jitter on a master sampled on a fixed cycle: the CycleClock counts the samples' cycles
and estimates the period. Once it has followed every sample of a window of more than three, the
window is fitted against the stamps and against the cycles (times: cycle x period, one straight
line), and the one whose positions fit better (mean square residual, which does not depend on the
period, averaged over MISFIT_SAMPLES) gives the estimate. Exact stamps of irregular samples keep
the stamps (their fit is exact); jittered stamps of regular samples take the cycles, and the speed
then errs by the period's relative error alone: the least-squares line's through all samples so
far while the clock starts, the loop's after (250 Hz, ±0.2 ms, 0.05 s window, 200 seeds: worst
speed error 0.54 % from the first full window on, 0.03 % once settled).

Delay: for a master whose acceleration changes (jerk j), a window of length T (samples spread
evenly over it) estimates alpha as it was T/2 ago (alpha - j T / 2) and omega with an error of
about -j T^2 / 10; after a step of the acceleration both settle within one window.
"""
from __future__ import annotations

from bisect import bisect_right
from typing import NamedTuple, Sequence

from .cycle_clock import CycleClock

#: Fewest samples the quadratic needs; fewer give the mean speed (two) or none (one).
QUADRATIC = 3
#: Normal equations whose determinant is below this fraction of n s2 s4 (samples bunched at one
#: end of the window, e.g. after a pause) give a line instead: the mean speed, no acceleration.
SINGULAR = 1e-10
#: Samples over which the residuals of the two time bases are averaged before they are compared.
MISFIT_SAMPLES = 16


class Fit(NamedTuple):
    """omega (rad/s) and alpha (rad/s^2) at the newest sample, the mean square residual."""

    omega: float
    alpha: float
    misfit: float  # rad^2


def fit_speed(times: Sequence[int], positions: Sequence[float], unit_s: float = 1e-9) -> Fit:
    """
    Return the Fit at the last of times (ascending; in unit_s, ns by default) of positions (rad).

    Two samples give their mean speed and no acceleration, one sample neither. The normal
    equations are summed in plain floats: a window is a few dozen samples, where NumPy's cost per
    call is more than the arithmetic (3.4 against 8 us for 20 samples).
    """
    count = len(times)
    if count < 2:
        return Fit(0.0, 0.0, 0.0)
    newest, last = times[-1], positions[-1]
    span = (newest - times[0]) * unit_s
    if count < QUADRATIC:
        return Fit((last - positions[0]) / span, 0.0, 0.0)
    scale = 1.0 / (newest - times[0])  # u in [-1, 0]: well-conditioned normal equations
    s1 = s2 = s3 = s4 = b0 = b1 = b2 = yy = 0.0
    for t, q in zip(times, positions):
        u, y = (t - newest) * scale, q - last
        uu = u * u
        s1, s2, s3, s4 = s1 + u, s2 + uu, s3 + uu * u, s4 + uu * uu
        b0, b1, b2, yy = b0 + y, b1 + y * u, b2 + y * uu, yy + y * y
    solution = _solve_symmetric(float(count), s1, s2, s3, s4, b0, b1, b2)
    if solution is None:  # bunched samples: the least-squares line
        c1, c2 = (count * b1 - s1 * b0) / (count * s2 - s1 * s1), 0.0
        c0 = (b0 - c1 * s1) / count
    else:
        c0, c1, c2 = solution
    misfit = max(yy - c0 * b0 - c1 * b1 - c2 * b2, 0.0) / count
    return Fit(c1 / span, 2.0 * c2 / span ** 2, misfit)


def _solve_symmetric(n: float, s1: float, s2: float, s3: float, s4: float, b0: float,
                     b1: float, b2: float) -> tuple[float, float, float] | None:
    """Solve [[n, s1, s2], [s1, s2, s3], [s2, s3, s4]] c = b by Cramer's rule (None: SINGULAR)."""
    m00, m01, m02 = s2 * s4 - s3 * s3, s2 * s3 - s1 * s4, s1 * s3 - s2 * s2
    det = n * m00 + s1 * m01 + s2 * m02
    if det <= SINGULAR * n * s2 * s4:
        return None
    c0 = (b0 * m00 + b1 * m01 + b2 * m02) / det
    c1 = (b0 * m01 + b1 * (n * s4 - s2 * s2) + b2 * (s1 * s2 - n * s3)) / det
    c2 = (b0 * m02 + b1 * (s1 * s2 - n * s3) + b2 * (n * s2 - s1 * s1)) / det
    return c0, c1, c2


class SpeedEstimator:
    """omega and alpha of a master from the samples of the last window_ns (see the module)."""

    def __init__(self, window_ns: int = 0):
        self.window_ns = int(window_ns)  # 0: the last three samples
        self.clock = CycleClock()
        self.reset()

    def reset(self) -> None:
        """Start afresh (after a master loss): no samples, the cycle unknown."""
        self._stamps: list[int] = []
        self._cycles: list[int] = []  # counted by the clock
        self._positions: list[float] = []
        self._misfits: tuple[float, float] | None = None  # smoothed: stamps, cycles
        self.clock.reset()

    def add(self, stamp_ns: int, position: float) -> None:
        """Take a sample (stamps ascending), keeping those of the window, at least three."""
        stamps = self._stamps
        stamps.append(stamp_ns)
        self.clock.time(stamp_ns)
        self._cycles.append(self.clock.cycle)
        self._positions.append(position)
        old = min(bisect_right(stamps, stamp_ns - self.window_ns), len(stamps) - QUADRATIC)
        if old > 0:
            del stamps[:old], self._cycles[:old], self._positions[:old]

    def estimate(self) -> tuple[float, float]:
        """Return (omega, alpha) at the newest sample."""
        by_stamps = fit_speed(self._stamps, self._positions)
        count, clock = len(self._stamps), self.clock
        if (count <= QUADRATIC or clock.samples < count  # three: no residual; a restart within
                or clock.exact):  # stamps on the cycle: one fit
            return by_stamps.omega, by_stamps.alpha
        by_cycles = fit_speed(self._cycles, self._positions, clock.period * 1e-9)
        stamps, cycles = self._misfits or (by_stamps.misfit, by_cycles.misfit)
        stamps += (by_stamps.misfit - stamps) / MISFIT_SAMPLES
        cycles += (by_cycles.misfit - cycles) / MISFIT_SAMPLES
        self._misfits = stamps, cycles
        best = by_cycles if cycles < stamps else by_stamps
        return best.omega, best.alpha
