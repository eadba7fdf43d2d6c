"""
Characteristic values of a design's segments, as PLC cam editors show them.

Per segment the smallest and largest slave position s, velocity ds/dtheta, acceleration
d2s/dtheta2 and jerk d3s/dtheta3 (per rad of master: master velocity 1) and the master angle
where each occurs: Beckhoff's `MC_TableCharacValues` (minimum and maximum slave position,
velocity, acceleration, jerk with their master positions) and the per-segment read-outs of
CODESYS's cam editor.  Each is refined on the exact law (extremes.refine_extrema over a dense
grid of the segment, the law's breakpoints as breaks), as the design report refines its
extremes; a segment's ends count with their one-sided values.  An acceleration jump (at a
breakpoint or a joint) is an unbounded jerk there, which no finite figure states.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays import FloatArray
from ..extremes import refine_extrema
from ..motion.program import MotionProgram
from ..motion.segment import Segment, segment_values

#: Samples of each segment from which the extremes are refined.
SAMPLES = 1025
#: The quantities, in the order of SegmentCharacteristics.minimum and maximum.
QUANTITIES = ('position', 'velocity', 'acceleration', 'jerk')


@dataclass(frozen=True)
class Extreme:
    """A refined extreme: its value (SI per rad^k) and the master angle (rad) where it occurs."""

    value: float
    angle: float


@dataclass(frozen=True)
class SegmentCharacteristics:
    """A segment's law, its master range (rad) and its extremes, in QUANTITIES order."""

    number: int
    law: str
    start: float
    end: float
    minimum: tuple[Extreme, ...]
    maximum: tuple[Extreme, ...]


def segment_characteristics(number: int, segment: Segment) -> SegmentCharacteristics:
    """Return the refined extremes of s and its first three derivatives on one segment."""
    def rows(u: FloatArray) -> FloatArray:
        values = segment_values(segment, np.clip(u, 0.0, 1.0))
        stacked = np.stack([values.y, values.y1, values.y2, values.y3])
        return np.concatenate((stacked, stacked))

    u = np.linspace(0.0, 1.0, SAMPLES)
    count = len(QUANTITIES)
    found = refine_extrema(rows, u, rows(u), ('min',) * count + ('max',) * count,
                           breaks=segment.law.breakpoints, period=None)
    flat = [low[0] == high[0] for low, high in zip(found[:count], found[count:])] * 2
    extremes = [Extreme(value, segment.start + (0.0 if constant else at) * segment.span)
                for (value, at), constant in zip(found, flat)]
    return SegmentCharacteristics(number, segment.law.name, segment.start, segment.end,
                                  tuple(extremes[:count]), tuple(extremes[count:]))


def characteristics(program: MotionProgram) -> tuple[SegmentCharacteristics, ...]:
    """Return every segment's characteristic values (see the module docstring)."""
    return tuple(segment_characteristics(number, segment)
                 for number, segment in enumerate(program.segments))
