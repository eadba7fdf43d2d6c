"""Base class of the normalised motion laws and the search for their characteristic values."""

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from functools import cached_property
from typing import Callable, ClassVar, NamedTuple

import numpy as np
import numpy.typing as npt

from ..arrays import checked_array, FloatArray
from ..kept import kept

#: Samples per law piece in the search for the peaks of |y'|, |y''|, |y'''|.
PEAK_SAMPLES = 1025
#: Bracket tolerance (in u) of the refinement of each sampled peak.
PEAK_XATOL = 1e-13
#: Sampled local maxima within this fraction of the largest sample are refined.
PEAK_CANDIDATE_RTOL = 1e-2
#: A jump of y, y' or y'' larger than this at an interior breakpoint makes the next peak infinite.
INTERIOR_JUMP_TOLERANCE = 1e-9


class LawValues(NamedTuple):
    """Normalised displacement y(u) and its first three derivatives with respect to u."""

    y: FloatArray
    y1: FloatArray
    y2: FloatArray
    y3: FloatArray


Derivatives = Callable[[FloatArray], LawValues]


def workspace(u: npt.ArrayLike) -> LawValues:
    """Return arrays for `_derivatives_into`: a copy of u in y, then room for the derivatives."""
    array = np.array(u, dtype=float)
    return LawValues(array, *(np.empty(array.shape) for _ in range(3)))


def full_like(u: FloatArray, value: float) -> FloatArray:
    """Return an array shaped like u filled with value."""
    return np.full(np.shape(u), value, dtype=float)


@dataclass(frozen=True)
class MotionLaw(ABC):
    """
    A normalised rise y(u) on u in [0, 1] with y(0) = 0 and y(1) = 1 (a dwell stays at 0).

    `evaluate` rejects u outside [0, 1] (a motion program maps each cam angle into its segment,
    so a law is never asked to extrapolate).  The characteristic values `cv`, `ca`, `cj` are the
    peaks of |y'|, |y''|, |y'''| over [0, 1], found once by dense sampling of every piece and a
    bounded refinement of the largest sampled local maxima.  A jump of y, y' or y'' *inside*
    the law (at one of its `breakpoints`) makes the next peak infinite (constant acceleration:
    cj = inf).  Jumps at u = 0 or 1 against the neighbouring segments are the motion program's
    business: its continuity report lists them (constant velocity: cv = 1, ca = cj = 0 inside
    the law, but y' jumps against a dwell, an acceleration impulse).
    """

    name: ClassVar[str]

    @abstractmethod
    def _derivatives(self, u: FloatArray) -> LawValues:
        """Return y, y', y'', y''' at u, already checked to lie in [0, 1]."""

    def _derivatives_into(self, values: LawValues) -> None:
        """
        Overwrite values, u (checked to lie in [0, 1]) in values.y, by y, y', y'', y''' at u.

        The motion program's path, straight into its output arrays; this default copies the
        results of `_derivatives`, an InPlaceLaw computes them there without temporaries.
        """
        for target, result in zip(values, self._derivatives(values.y.copy())):  # a result may be u
            np.copyto(target, result)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Interior values of u where the law switches piece (empty for a single formula)."""
        return ()

    def evaluate(self, u: npt.ArrayLike) -> LawValues:
        """Return y and its first three derivatives at u in [0, 1] (float arrays shaped like u)."""
        x = checked_array('u', u, lambda x: (x >= 0.0) & (x <= 1.0), 'must lie in [0, 1]')
        return LawValues(*(np.asarray(values, dtype=float) for values in self._derivatives(x)))

    @cached_property
    def _characteristic_values(self) -> tuple[float, float, float]:
        return kept(_peaks, self)  # a law is built anew with every design: searched once

    @property
    def cv(self) -> float:
        """Peak of |y'| over [0, 1] (velocity coefficient)."""
        return self._characteristic_values[0]

    @property
    def ca(self) -> float:
        """Peak of |y''| over [0, 1] (acceleration coefficient; inf if y' jumps inside)."""
        return self._characteristic_values[1]

    @property
    def cj(self) -> float:
        """Peak of |y'''| over [0, 1] (jerk coefficient; inf if y' or y'' jumps inside)."""
        return self._characteristic_values[2]


@dataclass(frozen=True)
class InPlaceLaw(MotionLaw):
    """A law computed in the caller's arrays: `_derivatives_into` is its one formula."""

    def _derivatives(self, u: FloatArray) -> LawValues:
        values = workspace(u)
        self._derivatives_into(values)
        return values

    @abstractmethod
    def _derivatives_into(self, values: LawValues) -> None:
        """Overwrite values, u in values.y, by y, y', y'', y''' at u (see MotionLaw)."""


def piece_grid(breakpoints: tuple[float, ...], samples: int) -> FloatArray:
    """
    Return a (pieces, samples) grid of u covering each piece between breakpoints.

    Row p starts at the piece's first u and ends one ulp before the next breakpoint, so that
    every sample is evaluated by the formula of its own piece (the last row ends at u = 1).
    """
    edges = np.array([0.0, *breakpoints, 1.0])
    low = edges[:-1]
    high = np.nextafter(edges[1:], -np.inf)
    high[-1] = 1.0
    return low[:, None] + (high - low)[:, None] * np.linspace(0.0, 1.0, samples)


def _candidate_peaks(magnitude: FloatArray) -> list[tuple[int, int]]:
    """
    Return (piece, index) of the sampled local maxima of magnitude worth refining.

    Strict local maxima along each row (and the global maximum, which may sit on a plateau)
    within PEAK_CANDIDATE_RTOL of the largest sample: two lobes of nearly equal height are
    both refined.
    """
    padded = np.pad(magnitude, ((0, 0), (1, 1)), constant_values=-np.inf)
    middle = padded[:, 1:-1]
    local = (middle > padded[:, :-2]) & (middle >= padded[:, 2:])
    local &= middle >= (1.0 - PEAK_CANDIDATE_RTOL) * magnitude.max()
    local.flat[np.argmax(magnitude)] = True
    return [(int(piece), int(index)) for piece, index in zip(*np.nonzero(local))]


def _peaks(law: MotionLaw) -> tuple[float, float, float]:
    return characteristic_values(law._derivatives, law.breakpoints)


def characteristic_values(derivatives: Derivatives,
                          breakpoints: tuple[float, ...]) -> tuple[float, float, float]:
    """Return the peaks of |y'|, |y''|, |y'''| of a law given by its derivatives function."""
    from scipy.optimize import minimize_scalar  # here: scipy costs the node 0.5 s start-up

    grid = piece_grid(breakpoints, PEAK_SAMPLES)
    values = derivatives(grid)
    peaks: list[float] = []
    for order in (1, 2, 3):
        lower = values[order - 1]
        jumps = np.abs(lower[1:, 0] - lower[:-1, -1])
        if (peaks and math.isinf(peaks[-1])) or np.any(jumps > INTERIOR_JUMP_TOLERANCE):
            peaks.append(math.inf)
            continue
        magnitude = np.abs(values[order])
        best = float(magnitude.max())
        for piece, index in _candidate_peaks(magnitude):
            row = grid[piece]
            refined = minimize_scalar(
                lambda x: -abs(float(derivatives(np.array(x))[order])),
                bounds=(row[max(index - 1, 0)], row[min(index + 1, row.size - 1)]),
                method='bounded', options={'xatol': PEAK_XATOL})
            best = max(best, -float(refined.fun))
        peaks.append(best)
    return peaks[0], peaks[1], peaks[2]
