"""
One segment of a motion program: a motion law on a cam-angle range and a follower travel.

A segment maps its cam-angle range [start, end] (rad) onto a law's u in [0, 1] and the law's y
onto the follower position: s = s_start + (s_end - s_start) * y(u), so that, with the span
beta = end - start and the stroke h = s_end - s_start, ds/dtheta = h y'/beta,
d2s/dtheta2 = h y''/beta**2, d3s/dtheta3 = h y'''/beta**3.  Positions are in m for a
translating follower, in rad (arm angle) for an oscillating one; derivatives are per rad of cam.
A segment that starts and ends moving (a VDI 2143 motion task, see tasks.py) adds a ramp:
s = s_start + ramp (theta - start) + amplitude y(u), amplitude = h - ramp beta unless given.
Here also: its values, its VDI 2143 task, its summary, and the checks of one segment.
"""

import math
import numbers
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..arrays import FloatArray
from ._law_base import LawValues, workspace
from ._polynomial import BoundaryPolynomial
from ..errors import InvalidParameter
from ..extremes import refine_extrema
from .laws import Dwell, LAWS, MotionLaw

#: Largest position mismatch accepted at a joint (m, or rad for an oscillating follower).
POSITION_TOLERANCE = 1e-9
#: The continuity report leaves out jumps of d^k s below this times the derivative's natural
#: scale there, |stroke| / span**k of the segments on either side (or the larger one-sided
#: value): rounding noise at joints that are smooth in exact arithmetic.
JUMP_TOLERANCE = 1e-9
#: Samples of a moving segment's velocity whose extremes are refined (peak, overshoot, reversal).
VELOCITY_SAMPLES = 1025


@dataclass(frozen=True)
class Segment:
    """
    One segment: a law from cam angle start to end (rad), the follower from s_start to s_end.

    A rise has s_end > s_start, a fall s_end < s_start, a dwell s_end == s_start.  ramp
    (ds/dtheta of a straight line under the law) and amplitude (what y = 1 adds to it; default
    s_end - s_start - ramp * span) shape the motion tasks that start or end moving.  Checked by
    MotionProgram, which knows the segment's index for its messages.
    """

    law: MotionLaw
    start: float
    end: float
    s_start: float
    s_end: float
    label: str = ''
    ramp: float = 0.0
    amplitude: float = math.nan  # nan: s_end - s_start - ramp * span

    def __post_init__(self) -> None:
        """Fill in the default amplitude (left nan when a field is no number: see checks)."""
        numbers_given = all(isinstance(getattr(self, name), numbers.Real)
                            for name in ('start', 'end', 's_start', 's_end', 'ramp', 'amplitude'))
        if numbers_given and math.isnan(self.amplitude):
            object.__setattr__(self, 'amplitude', self.stroke - self.ramp * self.span)

    @property
    def span(self) -> float:
        """Cam angle beta covered by the segment (rad)."""
        return self.end - self.start

    @property
    def stroke(self) -> float:
        """Signed follower travel h = s_end - s_start (m, or rad)."""
        return self.s_end - self.s_start


def segment_into(segment: Segment, values: LawValues) -> None:
    """Overwrite values, normalised u in [0, 1] in values.y, by s, ds, d2s, d3s per rad."""
    ramp, span = segment.ramp, segment.span
    line = values.y * (ramp * span) if ramp else None
    segment.law._derivatives_into(values)
    for value, scale in zip(values, _scales(segment)):
        value *= scale
    y, y1 = values.y, values.y1
    y += segment.s_start
    if line is not None:
        y += line
        y1 += ramp


def segment_values_at(segment: Segment, u: float) -> tuple[float, float, float, float]:
    """
    Return segment_values at one u in [0, 1] as plain floats: the same numbers.

    The law runs on 0-d arrays, the scaling in floats: NumPy's cost per call on an array of one
    element is some 70 times a float operation's.
    """
    values = workspace(u)
    segment.law._derivatives_into(values)
    s, ds, d2s, d3s = (float(value) * scale for value, scale in zip(values, _scales(segment)))
    s += segment.s_start
    if segment.ramp:
        s += u * (segment.ramp * segment.span)
        ds += segment.ramp
    return s, ds, d2s, d3s


def _scales(segment: Segment) -> tuple[float, float, float, float]:
    """Return the factors of the law's y and its three derivatives: amplitude / span**k."""
    amplitude, span = segment.amplitude, segment.span
    return amplitude, amplitude / span, amplitude / span ** 2, amplitude / span ** 3


def segment_values(segment: Segment, u: npt.ArrayLike) -> LawValues:
    """Return s, ds, d2s, d3s (per rad of cam) of a segment at normalised u in [0, 1]."""
    values = workspace(u)
    segment_into(segment, values)
    return values


def natural_scale(segment: Segment, order: int) -> float:
    """Return the natural size of d^order s on a segment: its largest travel over span**order."""
    travel = max(abs(segment.stroke), abs(segment.amplitude), abs(segment.ramp) * segment.span)
    return travel / segment.span ** order


#: A segment end's VDI 2143 type by (moving, accelerating): rest, constant velocity
#: (Gleichlauf), reversal (Umkehr), general motion (Bewegung).
_END_TYPES = {(False, False): 'R', (True, False): 'G', (False, True): 'U', (True, True): 'B'}


def motion_task(segment: Segment) -> str:
    """Return a segment's VDI 2143 motion task, the types of its two ends: 'R-R', 'R-G', ...

    The task a segment solves: a rest-to-rest law (with its ramp) solves R-R or G-G even where
    its own acceleration does not vanish at an end (simple harmonic: the continuity report lists
    that jump); a boundary polynomial's ends are what its given values say (U, B too).  ds or
    d2s counts as zero below JUMP_TOLERANCE times its natural scale.
    """
    orders = (1, 2) if isinstance(segment.law, BoundaryPolynomial) else (1,)
    types = []
    for at in (0.0, 1.0):
        values = segment_values(segment, at)
        moving = [abs(float(values[order])) > JUMP_TOLERANCE * natural_scale(segment, order)
                  for order in orders]
        types.append(_END_TYPES[(moving[0], moving[-1] and len(moving) == 2)])
    return '-'.join(types)


@dataclass(frozen=True)
class SegmentSummary:
    """Characteristic values of a segment's law and its peak |ds|, |d2s|, |d3s| per rad."""

    index: int
    law: str
    start: float
    end: float
    s_start: float
    s_end: float
    cv: float
    ca: float
    cj: float
    peak_ds: float
    peak_d2s: float
    peak_d3s: float
    task: str = 'R-R'
    inflection: float = 0.5
    #: How far peak |ds| exceeds the larger end |ds| of a task that starts or ends moving (an
    #: R-G rise whose mean slope equals its end velocity must overshoot it); 0 otherwise.
    overshoot: float = 0.0

    def peaks_at_speed(self, omega: float) -> tuple[float, float, float]:
        """Return peak |velocity|, |acceleration|, |jerk| at constant cam speed omega (rad/s)."""
        return self.peak_ds * omega, self.peak_d2s * omega ** 2, self.peak_d3s * omega ** 3


def summarize(number: int, segment: Segment) -> SegmentSummary:
    """Return segment number's law, cv, ca, cj, peaks per rad, task and overshoot."""
    law, amplitude, span = segment.law, abs(segment.amplitude), segment.span
    peaks = [amplitude * value / span ** order if amplitude else 0.0
             for order, value in ((1, law.cv), (2, law.ca), (3, law.cj))]
    task = motion_task(segment)
    excess = 0.0
    if segment.ramp or 'G' in task or 'B' in task:
        velocity = velocity_extremes(segment)
        if segment.ramp:  # ramp + amplitude y'/span does not peak where y' does
            peaks[0] = max(velocity[0][0], -velocity[1][0])
        excess = overshoot(segment, task, velocity)
    return SegmentSummary(
        number, law.name, segment.start, segment.end, segment.s_start, segment.s_end,
        law.cv, law.ca, law.cj, peaks[0], peaks[1], peaks[2], task,
        getattr(law, 'inflection', 0.5), excess)


def velocity_extremes(segment: Segment, low: float = 0.0,
                      high: float = 1.0) -> tuple[tuple[float, float], tuple[float, float]]:
    """Return (value, u) of the largest and of the smallest ds/dtheta on u in [low, high]."""
    u = np.linspace(low, high, VELOCITY_SAMPLES)

    def both(x: FloatArray) -> FloatArray:
        ds = segment_values(segment, x).y1
        return np.stack([ds, ds])

    highest, lowest = refine_extrema(both, u, both(u), ('max', 'min'),
                                     breaks=segment.law.breakpoints, period=None)
    return highest, lowest


def overshoot(segment: Segment, task: str,
              velocity: tuple[tuple[float, float], tuple[float, float]]) -> float:
    """Return how far ds/dtheta passes the larger end |ds| in the direction of a moving end.

    velocity: the segment's refined velocity_extremes; 0 when ds stays within (below
    JUMP_TOLERANCE of its scale).
    """
    ends = [float(segment_values(segment, at).y1) for at in (0.0, 1.0)]
    larger = max(abs(value) for value in ends)
    excess = max([velocity[0][0] - larger if value > 0.0 else -velocity[1][0] - larger
                  for value, kind in zip(ends, task.split('-')) if kind in 'GB'], default=0.0)
    return excess if excess > JUMP_TOLERANCE * natural_scale(segment, 1) else 0.0


def is_jump(left: float, right: float, order: int, near: Sequence[Segment]) -> bool:
    """Return whether d^order s jumps from left to right where the segments near meet.

    Differences below JUMP_TOLERANCE times the derivative's scale (|stroke| / span**order of
    those segments, or the larger one-sided value) are rounding noise, not a jump.
    """
    scale = max(abs(left), abs(right), *(natural_scale(item, order) for item in near))
    return abs(right - left) > JUMP_TOLERANCE * scale


def check_fields(name: str, segment: object, fields: Sequence[str]) -> None:
    """Raise InvalidParameter, naming the field, unless the fields are finite numbers and the
    segment (a Segment or its specification) spans a positive angle."""
    for field in fields:
        value = getattr(segment, field)
        if not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise InvalidParameter(f'{name}.{field}', value, 'must be a finite number')
    start, end = getattr(segment, 'start'), getattr(segment, 'end')
    if not end > start:
        raise InvalidParameter(f'{name}.end', end,
                               f'must exceed start = {start!r} rad (a positive span)')


def check_segment(name: str, segment: Segment) -> None:
    """Raise InvalidParameter, naming the field, unless one segment is valid on its own."""
    if not isinstance(segment, Segment):
        raise InvalidParameter(name, segment, 'must be a Segment')
    if not isinstance(segment.law, MotionLaw):
        raise InvalidParameter(f'{name}.law', segment.law,
                               'must be a MotionLaw; make_law(name, ...) knows ' + ', '.join(LAWS))
    check_fields(name, segment, ('start', 'end', 's_start', 's_end', 'ramp', 'amplitude'))
    if isinstance(segment.law, Dwell) and abs(segment.stroke) > POSITION_TOLERANCE:
        raise InvalidParameter(f'{name}.s_end', segment.s_end,
                               f'a dwell must end where it starts (s_start = {segment.s_start!r})')
    arrives = float(segment_values(segment, 1.0).y)
    if abs(arrives - segment.s_end) > POSITION_TOLERANCE:
        raise InvalidParameter(f'{name}.amplitude', segment.amplitude,
                               f'takes the law to {arrives!r}, not to s_end = {segment.s_end!r}')
