"""
Motion functions: the design as points with a function type per interval, for a controller that
runs motion laws itself (Beckhoff Tc2_MC2_Camming `MC_MotionFunctionPoint`).

Each interval between two points is one of
- LINE: the straight line through the two positions (a dwell, constant velocity);
- REST_QUINTIC: the fifth-degree polynomial from rest to rest (both ends with ds = d2s = 0);
- QUINTIC: the fifth-degree polynomial through s, ds, d2s at both ends (quintic Hermite).

A segment whose law is a polynomial of degree <= 5 (dwell, constant velocity, polynomial_345,
poly5, a polynomial law, each with its ramp) is written as one such interval: exact.  Every
other law (cycloidal, simple harmonic, modified sine, ...) becomes quintic pieces placed greedily
as `cam_table.tolerance_table` places them (each piece as long as the tolerance allows; not
proven the fewest), with its refined worst deviation.  A native segment whose ds or d2s jumps
where it ends is pieced too: one point holds one velocity and acceleration, so the point just
before the joint that the placement adds keeps the segment's own end values.

Points are in rad of master and SI (m or rad) of slave, derivatives per rad; each point holds
the values of the interval that starts there, the last (2 pi) those of the next cycle's start
(the start plus the program's advance).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ..errors import InvalidParameter
from ..motion.laws import ConstantVelocity, Dwell, PolynomialShape
from ..motion.program import MotionProgram
from ..motion.segment import Segment
from .cam_table import (BOUNDARY_MERGE, check_tolerance, interval_errors, MAX_POINTS,
                        piece_bounds, place_knots)

LINE, REST_QUINTIC, QUINTIC = 'line', 'rest_quintic', 'quintic'


@dataclass(frozen=True, eq=False)
class MotionFunction:
    """Points (rad), exact s, ds, d2s, d3s there, and each interval's kind and segment.

    pieced maps a segment written as quintic pieces to its refined worst deviation (m or rad);
    the other segments are exact.
    """

    angle: FloatArray
    s: FloatArray
    ds: FloatArray
    d2s: FloatArray
    d3s: FloatArray
    kinds: tuple[str, ...]
    owner: tuple[int, ...]
    pieced: dict[int, float]
    tolerance: Optional[float]

    @property
    def max_error(self) -> float:
        """Return the worst deviation over the revolution (0 when every segment is native)."""
        return max(self.pieced.values(), default=0.0)


def polynomial_degree(segment: Segment) -> Optional[int]:
    """Return the degree of a segment's s(theta) when its law is a polynomial (else None)."""
    law = segment.law
    if isinstance(law, (Dwell, ConstantVelocity)):
        return 1
    if isinstance(law, PolynomialShape):
        coefficients = np.trim_zeros(np.asarray(law.coefficients, dtype=float), 'b')
        return max(coefficients.size - 1, 1)
    return None


def motion_function(program: MotionProgram, tolerance: Optional[float] = None, *,
                    unit: tuple[str, float] = ('m or rad', 1.0)) -> MotionFunction:
    """Return the program as motion-function points: native laws exact, others quintic pieces.

    tolerance (m or rad) bounds the pieces; it may be None when every segment is native.
    """
    if tolerance is not None:
        check_tolerance(program, tolerance, unit)
    jumps = _derivative_jumps(program)
    bounds = piece_bounds(program)
    knots, kinds, owner = [0.0], [], []
    pieced: dict[int, float] = {}
    for start, end in zip(bounds[:-1], bounds[1:]):
        number = program.segment_at(0.5 * (start + end))
        degree = polynomial_degree(program.segments[number])
        smooth_end = not np.any(np.abs(jumps - end) <= BOUNDARY_MERGE)
        if degree is not None and (degree == 1 or (degree <= 5 and smooth_end)):
            knots.append(float(end))
            kinds.append(LINE if degree == 1 else QUINTIC)
            owner.append(number)
            continue
        if tolerance is None:
            raise InvalidParameter('tolerance', None, f'is needed: segment {number} '
                                   f'({program.segments[number].law.name}) has no native '
                                   'function and becomes quintic pieces within it')
        placed = place_knots(program, float(start), float(end), float(tolerance), 'quintic')
        worst = interval_errors(program, np.array(knots[-1:] + placed[:-1]), np.array(placed),
                                'quintic')
        pieced[number] = max(pieced.get(number, 0.0), float(worst.max()))
        knots += placed
        kinds += [QUINTIC] * len(placed)
        owner += [number] * len(placed)
        if len(knots) > MAX_POINTS:
            raise InvalidParameter('tolerance', tolerance,
                                   f'needs more than {MAX_POINTS} points: choose a larger one')
    angle = np.array(knots)
    values = program.evaluate(angle)
    at_rest = (values.ds == 0.0) & (values.d2s == 0.0)
    kinds = [REST_QUINTIC if kind == QUINTIC and at_rest[i] and at_rest[i + 1] else kind
             for i, kind in enumerate(kinds)]
    return MotionFunction(angle, np.array(values.s), np.array(values.ds),
                          np.array(values.d2s), np.array(values.d3s), tuple(kinds),
                          tuple(owner), pieced, tolerance)


def _derivative_jumps(program: MotionProgram) -> FloatArray:
    """Return the angles in [0, 2 pi] where ds or d2s jumps (2 pi for a jump at 0)."""
    angles = np.mod([jump.angle for jump in program.continuity_report()
                     if jump.order in (1, 2)], TWO_PI)
    return np.concatenate((angles, angles[angles <= BOUNDARY_MERGE] + TWO_PI))
