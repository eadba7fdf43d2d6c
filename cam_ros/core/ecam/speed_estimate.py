"""
Master speed and acceleration from stamped positions: a least-squares quadratic over a window.

The quadratic q(t) = c0 + c1 (t - t_n) + c2 (t - t_n)^2 that fits the positions of a window best
(least squares) gives omega = c1 and alpha = 2 c2 at the newest stamp t_n. Through three samples
it is the interpolating quadratic (the classic three-point estimate); over more it averages stamp
jitter. Either way it is exact for a master at constant acceleration, at any stamp spacing.

Delay: for a master whose acceleration changes (jerk j), a window of length T (samples spread
evenly over it) estimates alpha as it was T/2 ago (alpha - j T / 2) and omega with an error of
about -j T^2 / 10; after a step of the acceleration both settle within one window.
"""
from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Fewest samples the quadratic needs; fewer give the mean speed (two) or none (one).
QUADRATIC = 3


def fit_speed(times_ns: npt.ArrayLike, positions: npt.ArrayLike) -> tuple[float, float]:
    """
    Return (omega, alpha) at the last of stamps times_ns (ns, ascending) of positions (rad).

    Two samples give their mean speed and no acceleration, one sample neither.
    """
    t = np.asarray(times_ns, dtype=np.int64)
    q = np.asarray(positions, dtype=float)
    if t.size < 2:
        return 0.0, 0.0
    span = (t[-1] - t[0]) * 1e-9
    if t.size < QUADRATIC:
        return float((q[-1] - q[0]) / span), 0.0
    u = (t - t[-1]) * 1e-9 / span  # in [-1, 0]: a well-conditioned Vandermonde matrix
    basis = np.stack((np.ones_like(u), u, u * u), axis=1)
    c = np.linalg.lstsq(basis, q - q[-1], rcond=None)[0]
    return float(c[1] / span), float(2.0 * c[2] / span ** 2)
