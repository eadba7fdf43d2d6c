"""Polynomial motion laws, including the general solve from boundary and via-point conditions."""

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar, Sequence

import numpy as np
from numpy.polynomial import polynomial

from ..arrays import finite_float, FloatArray
from ._law_base import InPlaceLaw, LawValues
from ..errors import InvalidParameter

#: Largest |y(0)| and |y(1) - 1| accepted for a polynomial rise.
END_TOLERANCE = 1e-9
#: Largest condition number of the linear system accepted by `PolynomialLaw.from_conditions`.
MAX_CONDITION_NUMBER = 1e12

#: One condition of a polynomial law: (u, derivative order, value of that derivative at u).
Condition = tuple[float, int, float]


def _finite_floats(parameter: str, values: Sequence[float]) -> tuple[float, ...]:
    """Return values as a non-empty tuple of finite floats, or raise naming the parameter."""
    rule = 'must be a non-empty sequence of finite numbers'
    try:
        numbers = tuple(finite_float(parameter, value) for value in values)
    except (InvalidParameter, TypeError) as err:
        raise InvalidParameter(parameter, values, rule) from err
    if not numbers:
        raise InvalidParameter(parameter, values, rule)
    return numbers


def solve_coefficients(conditions: Sequence[Condition],
                       powers: Sequence[int] | None = None) -> FloatArray:
    """
    Return the coefficients (lowest power first) meeting one condition per unknown.

    A condition is (u, derivative order, value); the unknowns are the coefficients of u**p for
    p in `powers` (default 0, 1, ..., n - 1 for n conditions), every other one is zero.
    """
    rows = [_checked_condition(index, condition) for index, condition in enumerate(conditions)]
    exponents = list(range(len(rows))) if powers is None else _checked_powers(powers)
    if not rows or len(exponents) != len(rows):
        raise InvalidParameter('conditions', conditions,
                               f'need exactly one condition per power {exponents}')
    at, order, value = (np.array(column, dtype=float) for column in zip(*rows))
    exponent = np.array(exponents, dtype=float)
    ratio = np.array([[_falling_factorial(p, k) for p in exponents] for _, k, _ in rows])
    power = np.maximum(exponent[None, :] - order[:, None], 0.0)
    matrix = ratio * at[:, None] ** power
    if np.linalg.cond(matrix) > MAX_CONDITION_NUMBER:
        raise InvalidParameter('conditions', conditions, 'do not determine a unique polynomial')
    coefficients = np.zeros(max(exponents) + 1)
    coefficients[exponents] = np.linalg.solve(matrix, value)
    return coefficients


@dataclass(frozen=True)
class PolynomialShape(InPlaceLaw):
    """y(u) = sum_k coefficients[k] * u**k: the evaluation every polynomial law shares."""

    name: ClassVar[str] = 'polynomial'
    coefficients: tuple[float, ...]

    def __post_init__(self) -> None:
        """Store the coefficients as a tuple of finite floats."""
        object.__setattr__(self, 'coefficients', _finite_floats('coefficients',
                                                                self.coefficients))

    @cached_property
    def _derivative_coefficients(self) -> tuple[FloatArray, ...]:
        coefficients = np.array(self.coefficients)
        return tuple(polynomial.polyder(coefficients, order) for order in range(4))

    def _derivatives_into(self, values: LawValues) -> None:
        u = values.y.copy()
        for out, coefficients in zip(values, self._derivative_coefficients):
            _horner(u, coefficients, out)


@dataclass(frozen=True)
class PolynomialLaw(PolynomialShape):
    """
    Polynomial rise y(u) = sum_k coefficients[k] * u**k.

    The coefficients must give y(0) = 0 and y(1) = 1 (within END_TOLERANCE).  Build one from
    conditions on y, y', y'', ... at u = 0, u = 1 or interior via points with `from_conditions`.
    """

    def __post_init__(self) -> None:
        """Check the coefficients once and store them as a tuple of floats."""
        super().__post_init__()
        coefficients = self.coefficients
        at_end = math.fsum(coefficients)
        if abs(coefficients[0]) > END_TOLERANCE or abs(at_end - 1.0) > END_TOLERANCE:
            raise InvalidParameter('coefficients', coefficients, 'must give y(0) = 0 and y(1) = 1')

    @classmethod
    def from_conditions(cls, conditions: Sequence[Condition],
                        powers: Sequence[int] | None = None) -> 'PolynomialLaw':
        """
        Solve the coefficients from one condition (u, derivative order, value) per unknown.

        The unknowns are the coefficients of u**p for p in `powers` (default 0, 1, ..., n - 1
        for n conditions); every other coefficient is zero.  One linear solve.
        """
        return PolynomialLaw(tuple(solve_coefficients(conditions, powers)))


def _horner(u: FloatArray, coefficients: FloatArray, out: FloatArray) -> None:
    """
    Write the polynomial with coefficients (lowest power first) at u into out.

    The steps of numpy.polynomial.polynomial.polyval (Horner), without its temporaries.
    """
    out.fill(coefficients[-1])
    for coefficient in coefficients[-2::-1]:
        out *= u
        out += coefficient


def _falling_factorial(p: int, k: int) -> float:
    """Return p (p - 1) ... (p - k + 1), the factor of d^k/du^k u^p (0 for k > p, inf if huge)."""
    return math.prod(range(p - k + 1, p + 1), start=1.0) if k <= p else 0.0


def _checked_condition(index: int, condition: Condition) -> Condition:
    """Return one condition as (u, order, value), or raise naming its index."""
    parameter = f'conditions[{index}]'
    try:
        at, order, value = condition
    except (TypeError, ValueError) as err:
        raise InvalidParameter(parameter, condition,
                               'must be (u, derivative order, value)') from err
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 0:
        raise InvalidParameter(parameter, condition, 'derivative order must be an integer >= 0')
    at, value = _finite_floats(parameter, (at, value))
    if not 0.0 <= at <= 1.0:
        raise InvalidParameter(parameter, condition, 'u must lie in [0, 1]')
    return at, int(order), value


def _checked_powers(powers: Sequence[int]) -> list[int]:
    """Return the powers as distinct non-negative integers, or raise."""
    exponents = list(powers)
    if (not all(isinstance(p, (int, np.integer)) and not isinstance(p, bool) and p >= 0
                for p in exponents) or len(set(exponents)) != len(exponents)):
        raise InvalidParameter('powers', powers, 'must be distinct integers >= 0')
    return [int(p) for p in exponents]


@dataclass(frozen=True)
class Polynomial345(PolynomialLaw):
    """3-4-5 polynomial: y = 10u^3 - 15u^4 + 6u^5 (y, y', y'' fixed at both ends)."""

    name: ClassVar[str] = 'polynomial_345'
    coefficients: tuple[float, ...] = field(default=(0.0, 0.0, 0.0, 10.0, -15.0, 6.0),
                                            init=False)


@dataclass(frozen=True)
class Polynomial4567(PolynomialLaw):
    """4-5-6-7 polynomial: y = 35u^4 - 84u^5 + 70u^6 - 20u^7 (also y''' = 0 at both ends)."""

    name: ClassVar[str] = 'polynomial_4567'
    coefficients: tuple[float, ...] = field(
        default=(0.0, 0.0, 0.0, 0.0, 35.0, -84.0, 70.0, -20.0), init=False)


@dataclass(frozen=True)
class Polynomial9(PolynomialLaw):
    """9th-order rest-to-rest polynomial: y = 126u^5 - 420u^6 + 540u^7 - 315u^8 + 70u^9.

    y', y'', y''' and y'''' vanish at both ends: the law polydyne compensation needs, since the
    compensated cam's acceleration contains the motion's 4th derivative.
    """

    name: ClassVar[str] = 'polynomial_9'
    coefficients: tuple[float, ...] = field(
        default=(0.0, 0.0, 0.0, 0.0, 0.0, 126.0, -420.0, 540.0, -315.0, 70.0), init=False)


@dataclass(frozen=True)
class BoundaryPolynomial(PolynomialShape):
    """The polynomial through given end derivatives of a segment: VDI 2143's Poly5 / Poly7.

    The shape is y = (s - s_start) / amplitude, amplitude the stroke, or for a segment that ends
    where it starts (a U-U loop) its largest excursion |s - s_start|, so that y stays of order 1
    and its peaks cv, ca, cj compare with the other laws'.  Build one with `through`.
    """

    amplitude: float = 1.0
    #: The derivatives fixed at each end: 1 .. orders (2: velocity and acceleration).
    orders: ClassVar[int] = 2

    @classmethod
    def through(cls, stroke: float, span: float, start: Sequence[float],
                end: Sequence[float]) -> 'BoundaryPolynomial':
        """Return the law of a segment of stroke and span (rad) with the given end derivatives.

        start and end hold ds/dtheta, d2s/dtheta2 (and d3s/dtheta3 for poly7) per rad.
        """
        for side, values in (('start', start), ('end', end)):
            if len(values) != cls.orders:
                raise InvalidParameter(side, values, f'{cls.name} takes {cls.orders} end '
                                                     f'derivatives (1st to {cls.orders}th)')
            _finite_floats(side, values)
        shape = cls._absolute(stroke, span, start, end)
        amplitude = stroke if stroke else _peak_excursion(shape)
        normalised = shape / amplitude if amplitude else shape
        return cls(tuple(normalised.tolist()), float(amplitude))

    @classmethod
    def _absolute(cls, stroke: float, span: float, start: Sequence[float],
                  end: Sequence[float]) -> FloatArray:
        """Return s(u) - s_start as coefficients in u from the conditions (one linear solve)."""
        conditions = [(0.0, 0, 0.0), (1.0, 0, stroke)]
        for at, values in ((0.0, start), (1.0, end)):
            conditions += [(at, k, value * span ** k) for k, value in enumerate(values, 1)]
        return solve_coefficients(conditions)


def _peak_excursion(coefficients: FloatArray) -> float:
    """Return max |p(u)| over [0, 1]: at an end or a real root of p' inside.

    Leading terms of p' negligible next to its largest drop first: a 1e-273 leading
    coefficient would scale the companion matrix and lose the true roots.
    """
    slope = polynomial.polyder(coefficients)
    scale = float(np.max(np.abs(slope), initial=0.0))
    stationary = polynomial.polyroots(polynomial.polytrim(slope, 1e-15 * scale) if scale
                                      else [0.0])
    inside = stationary.real[(np.abs(stationary.imag) < 1e-12)
                             & (stationary.real > 0.0) & (stationary.real < 1.0)]
    return float(np.max(np.abs(polynomial.polyval(np.array([0.0, 1.0, *inside]), coefficients))))


@dataclass(frozen=True)
class Poly5(BoundaryPolynomial):
    """General quintic through (s, s', s'') at both ends (VDI 2143 Poly5, closed form)."""

    name: ClassVar[str] = 'poly5'
    orders: ClassVar[int] = 2

    @classmethod
    def _absolute(cls, stroke: float, span: float, start: Sequence[float],
                  end: Sequence[float]) -> FloatArray:
        """Return s(u) - s_start: the standard closed form (Biagiotti & Melchiorri, ch. 2)."""
        (v0, a0), (v1, a1), h, x = start, end, stroke, span
        xx = x * x / 2.0
        return np.array([0.0, v0 * x, a0 * xx,
                         10.0 * h - (6.0 * v0 + 4.0 * v1) * x - (3.0 * a0 - a1) * xx,
                         -15.0 * h + (8.0 * v0 + 7.0 * v1) * x + (3.0 * a0 - 2.0 * a1) * xx,
                         6.0 * h - 3.0 * (v0 + v1) * x - (a0 - a1) * xx])


@dataclass(frozen=True)
class Poly7(BoundaryPolynomial):
    """General septic through (s, s', s'', s''') at both ends (VDI 2143 Poly7, one solve)."""

    name: ClassVar[str] = 'poly7'
    orders: ClassVar[int] = 3
