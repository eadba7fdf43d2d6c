"""
Normalised motion laws y(u) of a cam follower and their registry.

A law maps u in [0, 1] (the fraction of a segment's cam angle) to y in [0, 1] (the fraction of
its stroke), y(0) = 0, y(1) = 1 (a dwell stays at 0).  `MotionLaw.evaluate(u)` returns y and
its first three derivatives with respect to u; `cv`, `ca`, `cj` are the peaks of |y'|, |y''|,
|y'''|.  `make_law(name, **params)` builds a law from its snake_case name (see `LAWS`).
"""

import inspect
import math
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType
from typing import Callable, ClassVar, Mapping, Sequence, TYPE_CHECKING

import numpy as np

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ._law_base import full_like, InPlaceLaw, LawValues, MotionLaw
from ._polynomial import (BoundaryPolynomial, Condition, Poly5, Poly7, Polynomial345,
                          Polynomial4567, Polynomial9, PolynomialLaw, PolynomialShape)
from ._sine_acceleration import ModifiedSine, ModifiedTrapezoid, SccaLaw, ViaPointLaw
from ..errors import did_you_mean, InvalidParameter

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

__all__ = [
    'BoundaryPolynomial', 'ConstantAcceleration', 'ConstantVelocity', 'Cycloidal', 'Dwell',
    'LAWS', 'LawValues', 'make_law', 'ModifiedSine', 'ModifiedTrapezoid', 'MotionLaw', 'Poly5',
    'Poly7', 'Polynomial345', 'Polynomial4567', 'Polynomial9', 'PolynomialLaw', 'PolynomialShape',
    'SccaLaw', 'SimpleHarmonic', 'TableLaw', 'ViaPointLaw',
]


@dataclass(frozen=True)
class Dwell(InPlaceLaw):
    """Dwell: the follower rests, y = 0 on the whole segment."""

    name: ClassVar[str] = 'dwell'

    def _derivatives_into(self, values: LawValues) -> None:
        for array in values:
            array.fill(0.0)


@dataclass(frozen=True)
class ConstantVelocity(InPlaceLaw):
    """Constant velocity y = u: y' = 1 jumps against a dwell (an acceleration impulse there)."""

    name: ClassVar[str] = 'constant_velocity'

    def _derivatives_into(self, values: LawValues) -> None:
        values.y1.fill(1.0)
        values.y2.fill(0.0)
        values.y3.fill(0.0)


@dataclass(frozen=True)
class ConstantAcceleration(MotionLaw):
    """Constant acceleration (parabolic): y = 2u^2, then 1 - 2(1 - u)^2; y'' = +-4 steps."""

    name: ClassVar[str] = 'constant_acceleration'

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The middle, where the acceleration flips from +4 to -4."""
        return (0.5,)

    def _derivatives(self, u: FloatArray) -> LawValues:
        first = u < 0.5
        rest = 1.0 - u
        return LawValues(np.where(first, 2.0 * u * u, 1.0 - 2.0 * rest * rest),
                         4.0 * np.where(first, u, rest),
                         np.where(first, 4.0, -4.0),
                         full_like(u, 0.0))


@dataclass(frozen=True)
class SimpleHarmonic(InPlaceLaw):
    """Simple harmonic: y = (1 - cos(pi u)) / 2; y'' = pi^2/2 at the ends (steps vs a dwell)."""

    name: ClassVar[str] = 'simple_harmonic'

    def _derivatives_into(self, values: LawValues) -> None:
        # One tan per angle instead of a sin and a cos, in place: with t = tan(pi u / 2) and
        # w = 1 / (1 + t^2), sin(pi u) = 2 t w and cos(pi u) = (1 - t^2) w, so y = t^2 w,
        # y' = pi t w, y'' = pi^2/2 (1 - t^2) w, y''' = -pi^2 y'.
        u, y1, y2, y3 = values
        np.multiply(u, 0.5 * math.pi, out=y1)
        np.tan(y1, out=y1)
        np.multiply(y1, y1, out=y2)
        np.add(y2, 1.0, out=y3)
        np.divide(1.0, y3, out=y3)
        np.multiply(y2, y3, out=u)
        np.subtract(y3, u, out=y2)
        y2 *= 0.5 * math.pi ** 2
        y1 *= y3
        y1 *= math.pi
        np.multiply(y1, -math.pi ** 2, out=y3)


@dataclass(frozen=True)
class Cycloidal(InPlaceLaw):
    """Cycloidal: y = u - sin(2 pi u) / (2 pi); y, y', y'' vanish at the ends, y''' does not."""

    name: ClassVar[str] = 'cycloidal'

    def _derivatives_into(self, values: LawValues) -> None:
        # One tan per angle instead of a sin and a cos, in place: with t = tan(pi u) and
        # w = 1 / (1 + t^2), sin(2 pi u) = 2 t w and cos(2 pi u) = (1 - t^2) w, so
        # y = u - t w / pi, y' = 2 t^2 w, y'' = 4 pi t w, y''' = 4 pi^2 (1 - t^2) w.
        u, y1, y2, y3 = values
        np.multiply(u, math.pi, out=y2)
        np.tan(y2, out=y2)
        np.multiply(y2, y2, out=y1)
        np.add(y1, 1.0, out=y3)
        np.divide(1.0, y3, out=y3)
        y2 *= y3
        y1 *= y3
        y3 -= y1
        y3 *= TWO_PI ** 2
        y1 *= 2.0
        y2 *= 1.0 / math.pi
        u -= y2
        y2 *= TWO_PI ** 2


@dataclass(frozen=True)
class TableLaw(MotionLaw):
    """
    User law through normalised points (u_i, y_i): a quintic interpolating spline.

    scipy's make_interp_spline(k=5) with y' = y'' = 0 at both ends, evaluated as a PPoly: C4
    inside, at rest at both ends (so y, y', y'' match a neighbouring dwell).  u must rise
    strictly from 0 to 1; y must start at 0, end at 1 and stay in [0, 1].  With the two end
    points only it is the 3-4-5 law.  The spline may overshoot (even run backwards) between
    points close in u but far apart in y.
    """

    name: ClassVar[str] = 'table'
    u: tuple[float, ...]
    y: tuple[float, ...]

    def __post_init__(self) -> None:
        """Check the points once and store them as tuples of floats."""
        u = _finite_vector('u', self.u)
        y = _finite_vector('y', self.y)
        if u.size < 2 or u[0] != 0.0 or u[-1] != 1.0 or np.any(np.diff(u) <= 0.0):
            raise InvalidParameter('u', self.u,
                                   'must rise strictly from 0 to 1 (2 or more points)')
        if y.size != u.size:
            raise InvalidParameter('y', self.y, f'must have {u.size} entries, one per u')
        if y[0] != 0.0 or y[-1] != 1.0 or np.any((y < 0.0) | (y > 1.0)):
            raise InvalidParameter('y', self.y, 'must start at 0, end at 1 and stay in [0, 1]')
        object.__setattr__(self, 'u', tuple(u.tolist()))
        object.__setattr__(self, 'y', tuple(y.tolist()))

    @cached_property
    def _splines(self) -> tuple['PPoly', ...]:
        from scipy.interpolate import make_interp_spline, PPoly  # here: scipy costs start-up

        rest = [(1, 0.0), (2, 0.0)]
        spline = PPoly.from_spline(make_interp_spline(self.u, self.y, k=5, bc_type=(rest, rest)))
        return tuple(spline.derivative(order) if order else spline for order in range(4))

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The interior table points (knots of the spline)."""
        return self.u[1:-1]

    def _derivatives(self, u: FloatArray) -> LawValues:
        return LawValues(*(np.asarray(spline(u), dtype=float) for spline in self._splines))


def _finite_vector(parameter: str, values: Sequence[float]) -> FloatArray:
    """Return values as a 1-D float array, or raise unless they are finite numbers."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as err:
        raise InvalidParameter(parameter, values, 'must be a list of numbers') from err
    if array.ndim != 1 or not np.all(np.isfinite(array)):
        raise InvalidParameter(parameter, values, 'must be a list of finite numbers')
    return array


def _polynomial(coefficients: Sequence[float] | None = None,
                conditions: Sequence[Condition] | None = None,
                powers: Sequence[int] | None = None) -> PolynomialLaw:
    """Build a polynomial law from its coefficients or from conditions (and powers)."""
    if (coefficients is None) == (conditions is None):
        raise InvalidParameter('coefficients', coefficients,
                               'give either coefficients or conditions, not both or neither')
    if conditions is not None:
        return PolynomialLaw.from_conditions(conditions, powers)
    if powers is not None:
        raise InvalidParameter('powers', powers, 'only applies together with conditions')
    return PolynomialLaw(tuple(coefficients or ()))


#: Every law by its snake_case name: a callable taking the law's parameters as keywords.
LAWS: Mapping[str, Callable[..., MotionLaw]] = MappingProxyType({
    'dwell': Dwell,
    'constant_velocity': ConstantVelocity,
    'constant_acceleration': ConstantAcceleration,
    'simple_harmonic': SimpleHarmonic,
    'cycloidal': Cycloidal,
    'polynomial_345': Polynomial345,
    'polynomial_4567': Polynomial4567,
    'polynomial_9': Polynomial9,
    'modified_trapezoid': ModifiedTrapezoid,
    'modified_sine': ModifiedSine,
    'scca': SccaLaw,
    'polynomial': _polynomial,
    'table': TableLaw,
    'via_point': ViaPointLaw,
    'poly5': Poly5.through,
    'poly7': Poly7.through,
})


def make_law(name: str, **params: object) -> MotionLaw:
    """Return the law called name (a key of LAWS) built from its keyword parameters."""
    factory = LAWS.get(name) if isinstance(name, str) else None
    if factory is None:
        hint = did_you_mean(name, LAWS) if isinstance(name, str) else ''
        raise InvalidParameter('law', name, 'must be one of ' + ', '.join(LAWS) + hint)
    accepted = inspect.signature(factory).parameters
    for key, value in params.items():
        if key not in accepted:
            takes = ', '.join(accepted) or 'no parameters'
            raise InvalidParameter(key, value,
                                   f'is not a parameter of law {name} (takes: {takes})')
    for key, parameter in accepted.items():
        if parameter.default is inspect.Parameter.empty and key not in params:
            raise InvalidParameter(key, None, f'is required by law {name}')
    return factory(**params)
