"""
Bring a moving slave to rest within its acceleration limit, in time (not in master travel).

Used where the cam can no longer be followed while the slave moves: the master reversed under a
one-way axis, the cam exceeds the axis's velocity at the master's present speed, a disengage.
From position p0 and velocity v0 at stamp t0 the slave decelerates at the limit A:

    p(t) = p0 + v0 t - sign(v0) A t^2 / 2,   v(t) = v0 - sign(v0) A t,   t <= |v0| / A

then stands at p0 + v0 |v0| / (2 A). Without a limit (A = 0) it stands at p0 at once.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt


@dataclass(frozen=True)
class Stop:
    """A deceleration from (position, velocity) at stamp_ns at deceleration (0: at once)."""

    stamp_ns: int
    position: float
    velocity: float
    deceleration: float

    @property
    def duration(self) -> float:
        """Return the time to rest (s)."""
        return abs(self.velocity) / self.deceleration if self.deceleration else 0.0

    @property
    def rest(self) -> float:
        """Return where the slave comes to rest."""
        return self.position + 0.5 * self.velocity * self.duration

    def done(self, stamp_ns: int) -> bool:
        """Say whether the slave is at rest at a stamp (ns)."""
        return (stamp_ns - self.stamp_ns) * 1e-9 >= self.duration

    def at(self, seconds: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Return position, velocity and acceleration at times (s) after the stop began."""
        t = np.clip(np.asarray(seconds, dtype=float), 0.0, self.duration)
        moving = t < self.duration
        braking = -math.copysign(self.deceleration, self.velocity)
        return (self.position + self.velocity * t + 0.5 * braking * t * t,
                np.where(moving, self.velocity + braking * t, 0.0),
                np.where(moving, braking, 0.0))
