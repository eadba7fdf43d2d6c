"""Moving the inflection of a symmetric rest-to-rest law (Beckhoff's and Siemens' "symmetry").

A symmetric law g (g(u) + g(1 - u) = 1) changes the sign of its acceleration at u = 1/2.  With
the inflection at lambda its accelerating half is scaled onto [0, lambda] and its decelerating
half onto [lambda, 1], so that f(lambda) = lambda:

    f(z) = 2 lambda g(z / (2 lambda))                                   for z <= lambda
    f(z) = 1 - 2 (1 - lambda) (1 - g(1/2 + (z - lambda) / (2 (1 - lambda))))   for z > lambda

f' keeps the peak Cv of g; the accelerating side's peak |f''| is Ca / (2 lambda), the
decelerating side's Ca / (2 (1 - lambda)); f''' jumps at lambda unless lambda = 1/2.
"""
from dataclasses import dataclass

import numpy as np

from ..arrays import FloatArray
from ..errors import InvalidParameter
from ._law_base import LawValues, MotionLaw

#: u at which a law must satisfy g(u) + g(1 - u) = 1 to count as symmetric.
_SYMMETRY_SAMPLES = np.linspace(0.0, 0.5, 17)
_SYMMETRY_TOLERANCE = 1e-9


@dataclass(frozen=True)
class InflectedLaw(MotionLaw):
    """A symmetric rest-to-rest law with its inflection at `inflection` in (0, 1)."""

    base: MotionLaw
    inflection: float

    @property
    def name(self) -> str:  # type: ignore[override]
        """The base law's name: the inflection is a parameter of it, reported beside it."""
        return self.base.name

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The inflection, and the base law's breakpoints carried onto their side."""
        return tuple(sorted({self.inflection, *(self._mapped(at)
                                                for at in self.base.breakpoints)}))

    def _mapped(self, at: float) -> float:
        """Return where the base law's u = at lands."""
        low = self.inflection
        return 2.0 * low * at if at <= 0.5 else low + (at - 0.5) * 2.0 * (1.0 - low)

    def _derivatives(self, u: FloatArray) -> LawValues:
        low = self.inflection
        left = u < low  # the inflection itself belongs to the decelerating side
        scale = np.where(left, 2.0 * low, 2.0 * (1.0 - low))
        z = np.where(left, u / (2.0 * low), 0.5 + (u - low) / (2.0 * (1.0 - low)))
        g = self.base._derivatives(np.clip(z, 0.0, 1.0))
        return LawValues(np.where(left, 0.0, 1.0 - scale) + scale * g.y, np.array(g.y1, float),
                         g.y2 / scale, g.y3 / scale ** 2)


def inflected(law: MotionLaw, inflection: float) -> MotionLaw:
    """Return law with its inflection at `inflection` (the law itself for 1/2).

    Raises InvalidParameter unless inflection lies in (0, 1) and law is symmetric about
    u = 1/2 (a table, via-point or boundary polynomial law is not: the halves would not meet).
    """
    if not 0.0 < inflection < 1.0:
        raise InvalidParameter('inflection', inflection, 'must lie strictly between 0 and 1')
    if inflection == 0.5:
        return law
    y = law.evaluate(np.concatenate([_SYMMETRY_SAMPLES, 1.0 - _SYMMETRY_SAMPLES])).y
    half = _SYMMETRY_SAMPLES.size
    if np.any(np.abs(y[:half] + y[half:] - 1.0) > _SYMMETRY_TOLERANCE):
        raise InvalidParameter('inflection', inflection,
                               f'moves the inflection of a law symmetric about u = 1/2 '
                               f'(g(u) + g(1 - u) = 1); {law.name} is not')
    return InflectedLaw(law, float(inflection))
