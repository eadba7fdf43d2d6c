"""Laws whose acceleration is piecewise a constant plus sinusoids: the SCCA family, via point."""

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar, Sequence

import numpy as np

from ..arrays import finite_float, FloatArray
from ._law_base import LawValues, MotionLaw
from ..errors import InvalidParameter

#: Largest |b + c + d - 1| accepted for an SCCA law.
FRACTION_SUM_TOLERANCE = 1e-9
#: Smallest SCCA fraction taken as a zone; shorter ones are numerically zero.
MIN_FRACTION = 1e-12
#: Tolerance (in y') of the search for the via-point velocity.
VIA_VELOCITY_XATOL = 1e-12

#: One term A*sin(omega*t + phase) of a piece's acceleration (omega != 0).
Term = tuple[float, float, float]


@dataclass(frozen=True)
class AccelerationPiece:
    """
    One piece: y'' = const + sum(A sin(omega t + phase)) for local t in [0, length].

    position and velocity are y and y' at the piece's start.
    """

    start: float
    length: float
    const: float
    terms: tuple[Term, ...] = ()
    position: float = 0.0
    velocity: float = 0.0

    def values(self, t: FloatArray) -> LawValues:
        """Return y, y', y'', y''' at local t by integrating the acceleration twice."""
        const = self.const
        y = self.position + self.velocity * t + 0.5 * const * t * t
        y1 = self.velocity + const * t
        y2 = np.full(np.shape(t), const)
        y3 = np.zeros(np.shape(t))
        for amplitude, omega, phase in self.terms:
            angle = omega * t + phase
            sin, cos = np.sin(angle), np.cos(angle)
            ratio = amplitude / omega
            y += ratio * (t * math.cos(phase) - (sin - math.sin(phase)) / omega)
            y1 += ratio * (math.cos(phase) - cos)
            y2 += amplitude * sin
            y3 += amplitude * omega * cos
        return LawValues(y, y1, y2, y3)

    def scaled(self, factor: float) -> 'AccelerationPiece':
        """Return the piece with its acceleration, start position and velocity times factor."""
        terms = tuple((amplitude * factor, omega, phase) for amplitude, omega, phase in self.terms)
        return AccelerationPiece(self.start, self.length, self.const * factor, terms,
                                 self.position * factor, self.velocity * factor)


def chain(pieces: Sequence[tuple[float, float, Sequence[Term]]]) -> tuple[AccelerationPiece, ...]:
    """
    Join pieces (length, const, terms) from y(0) = y'(0) = 0, continuous in y and y'.

    y'' is continuous where the caller's pieces make it so; leave zero-length pieces out.
    """
    chained: list[AccelerationPiece] = []
    start = position = velocity = 0.0
    for length, const, terms in pieces:
        piece = AccelerationPiece(start, length, const, tuple(terms), position, velocity)
        end = piece.values(np.array(length))
        chained.append(piece)
        start, position, velocity = start + length, float(end.y), float(end.y1)
    return tuple(chained)


def evaluate_pieces(pieces: Sequence[AccelerationPiece], u: FloatArray) -> LawValues:
    """Return y, y', y'', y''' at u (a point on an edge belongs to the piece it starts)."""
    if len(pieces) == 1:
        return pieces[0].values(u - pieces[0].start)
    index = np.searchsorted([piece.start for piece in pieces[1:]], u, side='right')
    result = LawValues(*(np.empty(np.shape(u)) for _ in range(4)))
    for number, piece in enumerate(pieces):
        inside = index == number
        for out, part in zip(result, piece.values(u[inside] - piece.start)):
            out[inside] = part
    return result


@dataclass(frozen=True)
class SccaLaw(MotionLaw):
    """
    Sine-constant-cosine acceleration family with fractions b + c + d = 1 of the rise.

    Acceleration over u: a quarter sine up to +Ca on [0, b/2], constant +Ca for c/2, a half
    cosine from +Ca to -Ca over d, constant -Ca for c/2, a quarter sine back to 0 on
    [1 - b/2, 1].  Ca normalises y(1) = 1.  Special cases: (0, 1, 0) constant acceleration,
    (0, 0, 1) simple harmonic, (1/2, 0, 1/2) cycloidal, (1/4, 1/2, 1/4) modified trapezoid,
    (1/4, 0, 3/4) modified sine.
    """

    name: ClassVar[str] = 'scca'
    b: float
    c: float
    d: float

    def __post_init__(self) -> None:
        """Check the fractions once."""
        for name in ('b', 'c', 'd'):
            value = finite_float(name, getattr(self, name))
            if not 0.0 <= value <= 1.0:
                raise InvalidParameter(name, value, 'must be a fraction in [0, 1]')
            object.__setattr__(self, name, value)
        total = self.b + self.c + self.d
        if abs(total - 1.0) > FRACTION_SUM_TOLERANCE:
            raise InvalidParameter('b + c + d', float(f'{total:.12g}'),  # no rounding noise
                                   'the fractions must add up to 1')

    @cached_property
    def _pieces(self) -> tuple[AccelerationPiece, ...]:
        # A fraction under MIN_FRACTION counts as 0: pi / fraction would overflow.
        b, c, d = (x if x >= MIN_FRACTION else 0.0 for x in (self.b, self.c, self.d))
        total = b + c + d
        b, c, d = b / total, c / total, d / total
        half_pi = 0.5 * math.pi
        zones = [  # (length, const, terms) with unit peak acceleration
            (0.5 * b, 0.0, [(1.0, math.pi / b, 0.0)] if b else []),
            (0.5 * c, 1.0, []),
            (d, 0.0, [(1.0, math.pi / d, half_pi)] if d else []),
            (0.5 * c, -1.0, []),
            (0.5 * b, 0.0, [(1.0, math.pi / b, -half_pi)] if b else []),
        ]
        unit = chain([zone for zone in zones if zone[0] > 0.0])
        scale = 1.0 / float(evaluate_pieces(unit, np.array(1.0)).y)
        return tuple(piece.scaled(scale) for piece in unit)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Interior edges of the non-empty zones."""
        return tuple(piece.start for piece in self._pieces[1:])

    def _derivatives(self, u: FloatArray) -> LawValues:
        return evaluate_pieces(self._pieces, u)


@dataclass(frozen=True)
class ModifiedTrapezoid(SccaLaw):
    """Modified trapezoid: SCCA with b = 1/4, c = 1/2, d = 1/4."""

    name: ClassVar[str] = 'modified_trapezoid'
    b: float = field(default=0.25, init=False)
    c: float = field(default=0.5, init=False)
    d: float = field(default=0.25, init=False)


@dataclass(frozen=True)
class ModifiedSine(SccaLaw):
    """Modified sine: SCCA with b = 1/4, c = 0, d = 3/4."""

    name: ClassVar[str] = 'modified_sine'
    b: float = field(default=0.25, init=False)
    c: float = field(default=0.0, init=False)
    d: float = field(default=0.75, init=False)


def _part_amplitudes(length: float, height: float, velocity: float) -> tuple[float, float]:
    """Return (a, b) of y'' = a sin(pi t/L) + b sin(2 pi t/L) rising height to velocity."""
    return (0.5 * math.pi * velocity / length,
            2.0 * math.pi * (height - 0.5 * velocity * length) / length ** 2)


def _lobe_peak(a: float, b: float) -> float:
    """
    Return the peak of |a sin(x) + b sin(2x)| over x in [0, pi], in closed form.

    Stationary points: a cos(x) + 2b cos(2x) = 0, a quadratic 4b c^2 + a c - 2b = 0 in
    c = cos(x); there f = sqrt(1 - c^2) (a + 2b c).
    """
    if b == 0.0:
        return abs(a)
    root = math.sqrt(a * a + 32.0 * b * b)
    cosines = [c for c in ((root - a) / (8.0 * b), (-root - a) / (8.0 * b)) if -1.0 <= c <= 1.0]
    return max((abs(math.sqrt(1.0 - c * c) * (a + 2.0 * b * c)) for c in cosines), default=0.0)


@dataclass(frozen=True)
class ViaPointLaw(MotionLaw):
    """
    Rise from rest to rest through (u_via, y_via) without stopping there (after seed 002).

    Two parts meet at the via point with zero acceleration and velocity V > 0; on each part
    (length L1 = u_via, then L2 = 1 - u_via, local t) the acceleration is a half-sine lobe
    plus a full-sine lobe, both zero at the part's ends, so y'' is continuous and vanishes at
    u = 0, u_via and 1:
        [0, u_via]:  y'' =  a1 sin(pi t / L1) + b1 sin(2 pi t / L1)
        [u_via, 1]:  y'' = -a2 sin(pi t / L2) + b2 sin(2 pi t / L2)
    Unknowns a1, b1, a2, b2, V; conditions y(0) = y'(0) = 0 (by integration), y'(u_via) = V,
    y(u_via) = y_via, y'(1) = 0, y(1) = 1 fix the amplitudes linearly for any V:
        a1 = pi V / (2 L1), b1 = 2 pi (y_via - V L1 / 2) / L1**2, likewise a2, b2 with 1 - y_via.
    On the first part y' = (L1/pi)(1 - cos x)(a1 + b1 (1 + cos x)), x = pi t / L1, likewise on
    the mirrored second part; y' > 0 inside both parts iff
    0 < V <= (8/3) min(y_via / L1, (1 - y_via) / L2): every via point strictly inside the unit
    square is reachable, any other raises.  V is then the minimiser of the peak |y''|, found
    with scipy.optimize.minimize_scalar; that peak is a maximum of |affine functions of V|,
    hence convex in V, so the minimiser is unique in practice and the law is well defined.
    The jerk y''' jumps at u = 0, u_via and 1 (like the cycloidal law's at its ends).
    """

    name: ClassVar[str] = 'via_point'
    u_via: float
    y_via: float

    def __post_init__(self) -> None:
        """Check that the via point lies strictly inside the unit square."""
        for name in ('u_via', 'y_via'):
            value = finite_float(name, getattr(self, name))
            if not 0.0 < value < 1.0:
                raise InvalidParameter(
                    name, value, 'must lie strictly between 0 and 1 (else the rise stops there)')
            object.__setattr__(self, name, value)

    @cached_property
    def velocity(self) -> float:
        """Normalised velocity y' at the via point (minimises the peak |y''|)."""
        first, second = self.u_via, 1.0 - self.u_via

        def peak_acceleration(velocity: float) -> float:
            a1, b1 = _part_amplitudes(first, self.y_via, velocity)
            a2, b2 = _part_amplitudes(second, 1.0 - self.y_via, velocity)
            return max(_lobe_peak(a1, b1), _lobe_peak(-a2, b2))

        from scipy.optimize import minimize_scalar  # here: scipy costs the node 0.5 s start-up

        limit = 8.0 / 3.0 * min(self.y_via / first, (1.0 - self.y_via) / second)
        found = minimize_scalar(peak_acceleration, bounds=(0.0, limit), method='bounded',
                                options={'xatol': VIA_VELOCITY_XATOL})
        return float(found.x)

    @cached_property
    def _pieces(self) -> tuple[AccelerationPiece, ...]:
        first, second = self.u_via, 1.0 - self.u_via
        a1, b1 = _part_amplitudes(first, self.y_via, self.velocity)
        a2, b2 = _part_amplitudes(second, 1.0 - self.y_via, self.velocity)
        return chain([
            (first, 0.0, [(a1, math.pi / first, 0.0), (b1, 2.0 * math.pi / first, 0.0)]),
            (second, 0.0, [(-a2, math.pi / second, 0.0), (b2, 2.0 * math.pi / second, 0.0)]),
        ])

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The via point, where the two parts meet."""
        return (float(self.u_via),)

    def _derivatives(self, u: FloatArray) -> LawValues:
        return evaluate_pieces(self._pieces, u)
