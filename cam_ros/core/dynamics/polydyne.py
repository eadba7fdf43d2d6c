"""Polydyne compensation (Dudley, 1948): the cam whose elastic train outputs the designed motion.

The train (see vibration.py) turns the cam's input y into the output x with
x + (2 zeta / omega_n) x_t + x_tt / omega_n^2 = y. Shaping the cam as

    y = s + (2 zeta / omega_n) s_t + s_tt / omega_n^2     (time derivatives at the cam speed)

makes x = s exactly at that speed. Per rad of cam at speed omega, with s = s0 + f(u) on a
segment of span beta (f = h y(u), plus the ramp of a motion task), y = s0 + F(u),
F = f + a f' + b f'', a = 2 zeta omega / (omega_n beta),
b = (omega / (omega_n beta))^2: for a polynomial law F is a polynomial too, so the compensated
cam is again a motion program of polynomial segments, and every geometry check applies to it
unchanged. y'' holds s'''', so s must be continuous to its 4th derivative (polynomial_9 next to
a dwell). At another speed omega' the output is off: s + e, where e answers the input
(2 zeta (omega - omega') / omega_n) s' + ((omega^2 - omega'^2) / omega_n^2) s''.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import polynomial

from ..errors import InvalidParameter
from ..motion.laws import ConstantVelocity, Dwell, PolynomialShape
from ..motion.program import MotionProgram
from ..motion.segment import is_jump, Segment
from .train import TrainConfig

#: Derivatives of s that must be continuous everywhere for the compensated cam to be smooth.
ORDERS = 4
_ORDINALS = ('1st', '2nd', '3rd', '4th')
PARAMETER = 'dynamics.compensate'


def _coefficients(segment: Segment, index: int) -> np.ndarray:
    """Return s - s_start of a segment as a polynomial in u, or raise naming the law."""
    law = segment.law
    if isinstance(law, PolynomialShape):
        shape = np.array(law.coefficients)
    elif isinstance(law, Dwell):
        shape = np.zeros(1)
    elif isinstance(law, ConstantVelocity):
        shape = np.array([0.0, 1.0])
    else:
        raise InvalidParameter(PARAMETER, True,
                               f'shapes polynomial laws (polynomial_9 is continuous and at rest '
                               f'to the 4th derivative at both ends); motion.laws[{index}] is '
                               f'{law.name}')
    return polynomial.polyadd(segment.amplitude * shape, [0.0, segment.ramp * segment.span])


def _end_derivatives(segment: Segment, coefficients: np.ndarray, u: float) -> np.ndarray:
    """Return s, ds, ..., d4s per rad of a segment at its end u (0 or 1)."""
    return np.array([segment.s_start + polynomial.polyval(u, coefficients)]
                    + [polynomial.polyval(u, polynomial.polyder(coefficients, k))
                       / segment.span ** k for k in range(1, ORDERS + 1)])


def _check_continuity(program: MotionProgram, laws: list[np.ndarray]) -> None:
    """Raise naming the joint and laws where s or a derivative up to the 4th jumps."""
    segments = program.segments
    for index, segment in enumerate(segments):
        before = segments[index - 1]
        left = _end_derivatives(before, laws[index - 1], 1.0)
        right = _end_derivatives(segment, laws[index], 0.0)
        for order in range(1, ORDERS + 1):
            if is_jump(float(left[order]), float(right[order]), order, (before, segment)):
                raise InvalidParameter(
                    PARAMETER, True,
                    f'needs the motion continuous to its 4th derivative: its '
                    f'{_ORDINALS[order - 1]} derivative '
                    f'jumps from {left[order]:.6g} to {right[order]:.6g} at '
                    f'{math.degrees(segment.start) % 360.0:g} deg, between '
                    f'motion.laws[{(index - 1) % len(segments)}] ({before.law.name}) and '
                    f'motion.laws[{index}] ({segment.law.name}); polynomial_9 rests to the 4th '
                    'derivative at both ends')


def compensated_program(program: MotionProgram, omega: float,
                        train: TrainConfig) -> MotionProgram:
    """Return the polydyne cam's motion: the input y that makes the train output s at omega.

    Raises InvalidParameter naming dynamics.compensate and the law when a segment is not a
    polynomial or s jumps in a derivative up to the 4th.
    """
    laws = [_coefficients(segment, index) for index, segment in enumerate(program.segments)]
    _check_continuity(program, laws)
    segments = []
    for segment, f in zip(program.segments, laws):
        if isinstance(segment.law, Dwell):
            segments.append(segment)
            continue
        ratio = omega / (train.omega_n * segment.span)
        shaped = polynomial.polyadd(
            polynomial.polyadd(f, 2.0 * train.damping_ratio * ratio * polynomial.polyder(f)),
            ratio ** 2 * polynomial.polyder(f, 2))
        low, high = float(shaped[0]), float(np.sum(shaped))  # F(0), F(1) - s_start
        scale = segment.amplitude or segment.stroke or 1.0  # keeps y of order 1
        rise = shaped.copy()
        rise[0] = 0.0
        segments.append(Segment(PolynomialShape(tuple(rise / scale)), segment.start, segment.end,
                                segment.s_start + low, segment.s_start + high,
                                f'{segment.law.name}, compensated', amplitude=scale))
    return MotionProgram(tuple(segments))
