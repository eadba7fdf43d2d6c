"""VDI 2143 motion tasks: segments whose ends are at rest (R), at constant velocity (G), at a
reversal (U) or in general motion (B), built from given end derivatives.

Each segment end may give ds/dtheta, d2s/dtheta2 and d3s/dtheta3 (per rad; nan: automatic).

* A rest-to-rest law g (cycloidal, 3-4-5, ..., table, via point) serves R-R and, with equal end
  velocities v, G-G by superposition: s = s_start + v x + (H - v X) g(x / X) (x the angle into
  the segment, X its span, H its stroke); automatic means rest.  Any other given value must be
  what the law gives there, or the segment is refused naming poly5/poly7.
* poly5 / poly7 (see _polynomial.py) pass through the given velocity and acceleration (and
  jerk) at both ends; an automatic value takes the neighbouring segment's at that joint.
* `inflection` moves a symmetric law's change of acceleration sign from 1/2 (inflection.py).

`build_segments` resolves every end, builds the segments and refuses a specification that cannot
be met, naming the segment field (`segments[2].end_velocity`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..arrays import FloatArray
from ..errors import InvalidParameter
from ..extremes import refine_roots
from ._polynomial import BoundaryPolynomial, Poly5, Poly7
from .inflection import inflected
from .laws import Dwell, MotionLaw
from .segment import (check_fields, motion_task, natural_scale, Segment, segment_values,
                      VELOCITY_SAMPLES, velocity_extremes)

#: The boundary polynomials by name, and what the end fields are called.
BOUNDARY_LAWS: dict[str, type[BoundaryPolynomial]] = {'poly5': Poly5, 'poly7': Poly7}
END_FIELDS = ('velocity', 'acceleration', 'jerk')
#: A given end value matches the law's own within this times its natural scale.
MATCH_TOLERANCE = 1e-9


@dataclass(frozen=True)
class TaskSpec:
    """One segment as specified: a law (or a boundary law's name) and its given end values."""

    law: MotionLaw | str
    start: float
    end: float
    s_start: float
    s_end: float
    begin: tuple[float, float, float] = (math.nan,) * 3  # ds, d2s, d3s per rad; nan: automatic
    finish: tuple[float, float, float] = (math.nan,) * 3
    inflection: float = 0.5


def _field(index: int, side: str, order: int) -> str:
    return f'segments[{index}].{side}_{END_FIELDS[order - 1]}'


def _superposed(spec: TaskSpec, index: int) -> Segment:
    """Build a rest-to-rest law's segment: R-R, or G-G with one velocity under it."""
    law = spec.law
    assert isinstance(law, MotionLaw)
    v0, v1 = (0.0 if math.isnan(end[0]) else end[0] for end in (spec.begin, spec.finish))
    if v0 != v1:
        raise InvalidParameter(_field(index, 'end', 1), spec.finish[0],
                               f'differs from the start velocity {v0!r} per rad^1: law {law.name} '
                               'joins equal end velocities only (R-R, G-G); poly5 or poly7 joins '
                               'any')
    if isinstance(law, Dwell) and v0:
        raise InvalidParameter(_field(index, 'start', 1), v0,
                               'must be 0 for a dwell (constant_velocity moves)')
    try:
        shaped = inflected(law, spec.inflection)
    except InvalidParameter as err:
        raise InvalidParameter(f'segments[{index}].inflection', spec.inflection,
                               err.rule) from err
    segment = Segment(shaped, spec.start, spec.end, spec.s_start, spec.s_end, ramp=v0)
    for side, given, at in (('start', spec.begin, 0.0), ('end', spec.finish, 1.0)):
        actual = segment_values(segment, at)
        for order, value in enumerate(given, 1):
            scale = natural_scale(segment, order)
            has = float(actual[order]) if abs(actual[order]) > MATCH_TOLERANCE * scale else 0.0
            if not math.isnan(value) and abs(value - has) > MATCH_TOLERANCE * scale:
                raise InvalidParameter(
                    _field(index, side, order), value,
                    f'law {law.name} has {has!r} per rad^{order} there (its own shape sets it); '
                    'give poly5 (velocity, acceleration) or poly7 (and jerk) for other end '
                    'values')
    return segment


def _inherited(specs: Sequence[TaskSpec], built: dict[int, Segment], index: int, side: str,
               order: int) -> float:
    """Return a boundary law's automatic end value: the neighbour's at their joint."""
    count = len(specs)
    other = (index - 1) % count if side == 'start' else (index + 1) % count
    if other in built:
        return float(segment_values(built[other], 1.0 if side == 'start' else 0.0)[order])
    neighbour = specs[other]
    value = (neighbour.finish if side == 'start' else neighbour.begin)[order - 1]
    if math.isnan(value):
        joint = specs[index].start if side == 'start' else specs[index].end
        facing = _field(other, 'end' if side == 'start' else 'start', order)
        raise InvalidParameter(
            _field(index, side, order), value,
            f'is automatic, and so is {facing} at their joint '
            f'({math.degrees(joint) % 360.0:g} deg): both are {neighbour.law} segments; give '
            f'the {END_FIELDS[order - 1]} at this joint')
    return value


def _boundary(spec: TaskSpec, index: int, specs: Sequence[TaskSpec],
              built: dict[int, Segment]) -> Segment:
    """Build a poly5/poly7 segment, its automatic ends taken from the neighbours."""
    cls = BOUNDARY_LAWS[str(spec.law)]
    if spec.inflection != 0.5:
        raise InvalidParameter(f'segments[{index}].inflection', spec.inflection,
                               f'does not apply to {cls.name}: its boundary values shape it')
    ends = []
    for side, given in (('start', spec.begin), ('end', spec.finish)):
        if cls.orders < 3 and not math.isnan(given[2]):
            raise InvalidParameter(_field(index, side, 3), given[2],
                                   'poly5 sets velocity and acceleration only; give poly7 '
                                   'for a jerk')
        ends.append(tuple(_inherited(specs, built, index, side, order)
                          if math.isnan(given[order - 1]) else given[order - 1]
                          for order in range(1, cls.orders + 1)))
    law = cls.through(spec.s_end - spec.s_start, spec.end - spec.start, *ends)
    return Segment(law, spec.start, spec.end, spec.s_start, spec.s_end, amplitude=law.amplitude)


def _check_reversal(segment: Segment, index: int) -> None:
    """Refuse a task with a U end whose velocity changes sign where it may not.

    A segment with a stroke may not reverse inside (its refined largest and smallest ds/dtheta
    both beyond rounding: it runs both ways); one of zero stroke is a loop and must reverse
    exactly once, at its far point (_check_loop).
    """
    task = motion_task(segment)
    if 'U' not in task:
        return
    tolerance = MATCH_TOLERANCE * natural_scale(segment, 1)
    if abs(segment.stroke) <= MATCH_TOLERANCE * natural_scale(segment, 0):
        _check_loop(segment, index, task, tolerance)
        return
    (highest, _), (lowest, _) = velocity_extremes(segment)
    if highest > tolerance and lowest < -tolerance:
        raise InvalidParameter(
            f'segments[{index}].s_end', segment.s_end,
            f'a {task} segment reverses at its U end, but this one runs both ways (ds/dtheta '
            f'from {lowest:.6g} per rad^1 to {highest:.6g} per rad^1): its reversal point lies '
            'behind its start; the stroke must point the way the follower moves')


def _check_loop(segment: Segment, index: int, task: str, tolerance: float) -> None:
    """Refuse a zero-stroke segment unless it runs out to one far point and straight back.

    The far point is the sign change of ds/dtheta (refined) farthest from s_start; ds/dtheta
    must keep the excursion's sign before it and the opposite sign after it (beyond rounding).
    """
    def velocity(u: FloatArray) -> FloatArray:
        return segment_values(segment, u).y1

    inner = np.linspace(0.0, 1.0, VELOCITY_SAMPLES)[1:-1]
    turns = refine_roots(velocity, inner, velocity(inner), breaks=segment.law.breakpoints,
                         period=None)
    excursion = segment_values(segment, turns).y - segment.s_start
    far = int(np.argmax(np.abs(excursion))) if turns.size else -1
    ways = [velocity_extremes(segment, *half)
            for half in ((0.0, turns[far]), (turns[far], 1.0))] if turns.size else []
    sign = math.copysign(1.0, excursion[far]) if turns.size else 0.0
    if not ways or min(sign * value for value, _ in ways[0]) < -tolerance or \
            max(sign * value for value, _ in ways[1]) > tolerance:
        (high, _), (low, _) = velocity_extremes(segment)
        raise InvalidParameter(
            f'segments[{index}].end_acceleration', float(segment_values(segment, 1.0).y2),
            f'a {task} segment of zero stroke is a loop out to one far point and back, but this '
            f'one turns {turns.size} times inside (ds/dtheta from {low:.6g} per rad^1 to '
            f'{high:.6g} per rad^1): it must leave its start and come back to it from the same '
            'side (a poly5 U-U: start and end accelerations of one sign)')


def build_segments(specs: Sequence[TaskSpec]) -> tuple[Segment, ...]:
    """Return the segments of specs in order, every automatic end resolved (see the module)."""
    for index, spec in enumerate(specs):
        check_fields(f'segments[{index}]', spec, ('start', 'end', 's_start', 's_end'))
    built = {index: _superposed(spec, index) for index, spec in enumerate(specs)
             if isinstance(spec.law, MotionLaw)}
    for index, spec in enumerate(specs):
        if index not in built:
            built[index] = _boundary(spec, index, specs, built)
    segments = tuple(built[index] for index in range(len(specs)))
    for index, segment in enumerate(segments):
        _check_reversal(segment, index)
    return segments
