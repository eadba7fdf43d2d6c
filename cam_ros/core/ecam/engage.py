"""
Join one slave path onto another over a distance of master travel without a step.

A path is y(q), the slave position as a function of the master position q (rad), with its
derivatives per rad of master (MasterDerivatives); an electronic cam is one, a held slave another.
A blend from path A to path B, begun at master q0 over a master distance D, is

    Y(q) = A(q) + b(u) (B(q) - A(q)),    u = min(|q - q0| / D, 1)

with the quintic smoothstep b(u) = 10 u^3 - 15 u^4 + 6 u^5: b, b', b'' are 0, 0, 0 at u = 0 and
1, 0, 0 at u = 1, so Y and its first two derivatives equal A's where the blend begins and B's where
it ends. The setpoints are those derivatives by the chain rule (velocity y' omega, acceleration
y'' omega^2 + y' alpha): position, velocity and acceleration are continuous at both ends at any
master speed, and a master that reverses within the blend unwinds it the same way.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from ..motion.laws import Polynomial345
from .master import MasterDerivatives


class SlavePath(Protocol):
    """Anything that gives y(q) and its derivatives per rad of master."""

    def derivatives(self, master: npt.ArrayLike) -> MasterDerivatives:
        """Return the path and its derivatives at master positions (rad)."""

    def breaks(self, low: float, high: float) -> np.ndarray:
        """Return the master positions in [low, high] where a derivative may jump."""


#: b(u) = 10 u^3 - 15 u^4 + 6 u^5 is the 3-4-5 motion law.
_SMOOTHSTEP = Polynomial345()


def smoothstep(u: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return b(u) and its three derivatives (u clipped to [0, 1])."""
    t: np.ndarray = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
    inside = np.where(t < 1.0, 1.0, 0.0)  # past the end the blend is B itself: no derivatives
    b = _SMOOTHSTEP.evaluate(t)
    return b.y, inside * b.y1, inside * b.y2, inside * b.y3


@dataclass(frozen=True)
class Held:
    """A slave standing at position (m or rad) whatever the master does."""

    position: float

    def derivatives(self, master: npt.ArrayLike) -> MasterDerivatives:
        """Return the constant position and zero derivatives (floats for a float)."""
        zero = 0.0 if isinstance(master, float) else np.zeros_like(master, dtype=float)
        return MasterDerivatives(zero + self.position, zero, zero, zero)

    def breaks(self, low: float, high: float) -> np.ndarray:
        """Return no breaks: a held slave is smooth."""
        return np.empty(0)


@dataclass(frozen=True, eq=False)
class Blend:
    """Path start blending into path end from master q0 over distance (rad of master, > 0)."""

    start: SlavePath
    end: SlavePath
    q0: float
    distance: float

    def breaks(self, low: float, high: float) -> np.ndarray:
        """Return both paths' breaks and the blend's own ends in [low, high]."""
        ends = np.array([self.q0 - self.distance, self.q0, self.q0 + self.distance])
        return np.concatenate([self.start.breaks(low, high), self.end.breaks(low, high),
                               ends[(ends >= low) & (ends <= high)]])

    def done(self, master: float) -> bool:
        """Say whether the master has travelled the whole distance from q0."""
        return abs(master - self.q0) >= self.distance

    def derivatives(self, master: npt.ArrayLike) -> MasterDerivatives:
        """Return Y(q) and its derivatives (see the module docstring)."""
        q = np.asarray(master, dtype=float)
        a, b = self.start.derivatives(q), self.end.derivatives(q)
        d = [end - start for start, end in zip(a, b)]  # B - A and its derivatives
        sign = np.where(q >= self.q0, 1.0, -1.0) / self.distance  # du/dq
        s0, s1, s2, s3 = smoothstep(np.abs(q - self.q0) / self.distance)
        s1, s2, s3 = s1 * sign, s2 * sign ** 2, s3 * sign ** 3  # per rad of master
        return MasterDerivatives(a.y + s0 * d[0],
                                 a.dy + s0 * d[1] + s1 * d[0],
                                 a.d2y + s0 * d[2] + 2.0 * s1 * d[1] + s2 * d[0],
                                 a.d3y + s0 * d[3] + 3.0 * s1 * d[2] + 3.0 * s2 * d[1]
                                 + s3 * d[0])
