"""
Slave paths other than a cam: a path is y(q), the slave position as a function of the master
position q (rad), with its derivatives per rad of master (MasterDerivatives); an electronic cam is
one, a held slave (Held) another.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from .master import MasterDerivatives


class SlavePath(Protocol):
    """Anything that gives y(q) and its derivatives per rad of master."""

    def derivatives(self, master: npt.ArrayLike) -> MasterDerivatives:
        """Return the path and its derivatives at master positions (rad)."""

    def breaks(self, low: float, high: float) -> np.ndarray:
        """Return the master positions in [low, high] where a derivative may jump."""


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
