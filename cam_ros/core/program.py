"""
Motion programs: ordered segments of motion laws covering one cam revolution.

A segment maps its cam-angle range [start, end] (rad) onto a law's u in [0, 1] and the law's y
onto the follower position: s = s_start + (s_end - s_start) * y(u), so that, with the span
beta = end - start and the stroke h = s_end - s_start, ds/dtheta = h y'/beta,
d2s/dtheta2 = h y''/beta**2, d3s/dtheta3 = h y'''/beta**3.  Positions are in m for a
translating follower, in rad (arm angle) for an oscillating one; derivatives are per rad of cam.

The segments follow each other without gap or overlap and cover exactly 2 pi, starting at the
first segment's start (any angle, e.g. 0 or -pi/2); `evaluate` takes any real angle modulo 2 pi.
"""

import math
import numbers
from dataclasses import dataclass
from functools import cached_property
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ._law_base import checked_array, FloatArray
from .errors import InvalidParameter
from .laws import Dwell, LAWS, MotionLaw

TWO_PI = 2.0 * math.pi
#: Largest gap, overlap, or error of the 2 pi total, accepted between segments (rad).
ANGLE_TOLERANCE = 1e-9
#: Largest position mismatch accepted at a joint (m, or rad for an oscillating follower).
POSITION_TOLERANCE = 1e-9
#: The continuity report leaves out jumps below this times max(1, |left|, |right|).
JUMP_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Segment:
    """
    One segment: a law from cam angle start to end (rad), the follower from s_start to s_end.

    A rise has s_end > s_start, a fall s_end < s_start, a dwell s_end == s_start.  Checked by
    MotionProgram, which knows the segment's index for its messages.
    """

    law: MotionLaw
    start: float
    end: float
    s_start: float
    s_end: float
    label: str = ''

    @property
    def span(self) -> float:
        """Cam angle beta covered by the segment (rad)."""
        return self.end - self.start

    @property
    def stroke(self) -> float:
        """Signed follower travel h = s_end - s_start (m, or rad)."""
        return self.s_end - self.s_start


def _segment_values(segment: Segment, u: npt.ArrayLike) -> tuple[FloatArray, ...]:
    """Return s, ds, d2s, d3s (per rad of cam) of a segment at normalised u in [0, 1]."""
    y, y1, y2, y3 = segment.law.evaluate(u)
    stroke, span = segment.stroke, segment.span
    return (segment.s_start + stroke * y, (stroke / span) * y1, (stroke / span ** 2) * y2,
            (stroke / span ** 3) * y3)


def _read_only(array: npt.ArrayLike) -> FloatArray:
    """Return array as a read-only float array (no copy when already one)."""
    result = np.asarray(array, dtype=float)
    result.flags.writeable = False
    return result


@dataclass(frozen=True, eq=False)
class TimeValues:
    """Follower motion in time at constant cam speed: SI units (m or rad, per s, s^2, s^3)."""

    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray


@dataclass(frozen=True, eq=False)
class ProgramValues:
    """Follower position s and its derivatives per rad of cam angle (read-only arrays)."""

    s: FloatArray
    ds: FloatArray
    d2s: FloatArray
    d3s: FloatArray

    def __post_init__(self) -> None:
        """Make the arrays read-only."""
        for name in ('s', 'ds', 'd2s', 'd3s'):
            object.__setattr__(self, name, _read_only(getattr(self, name)))

    def at_speed(self, omega: float) -> TimeValues:
        """Return position, velocity, acceleration and jerk at constant cam speed omega (rad/s)."""
        speed = float(omega)
        if not math.isfinite(speed):
            raise InvalidParameter('omega', omega, 'must be a finite cam speed in rad/s')
        return TimeValues(self.s, _read_only(speed * self.ds), _read_only(speed ** 2 * self.d2s),
                          _read_only(speed ** 3 * self.d3s))


@dataclass(frozen=True)
class Discontinuity:
    """
    A jump of s (order 0) or of its k-th derivative per rad (order k) at a cam angle.

    A jump of order k means an impulse (unbounded value) of order k + 1 at the same angle; it
    is not listed again (constant velocity after a dwell: one ds jump, the d2s impulse implied).
    `segment` is the index of the segment that starts at the angle (a joint) or contains it (a
    breakpoint inside a piecewise law).
    """

    angle: float
    order: int
    left: float
    right: float
    segment: int

    @property
    def jump(self) -> float:
        """Right limit minus left limit."""
        return self.right - self.left


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


@dataclass(frozen=True)
class MotionProgram:
    """
    Ordered segments covering one revolution [start, start + 2 pi) (see the module docstring).

    Construction checks every rule once and raises InvalidParameter naming the segment, e.g.
    'segments[2].start': non-finite values, end <= start, gaps and overlaps beyond
    ANGLE_TOLERANCE, a total other than 360 deg, a position jump at a joint (including the wrap
    from the last segment to the first), a dwell that moves, a law that is not a MotionLaw.
    """

    segments: tuple[Segment, ...]

    def __post_init__(self) -> None:
        """Check the segments once and store them as a tuple."""
        try:
            segments = tuple(self.segments)
        except TypeError as err:
            raise InvalidParameter('segments', self.segments, 'must be a sequence') from err
        _check_segments(segments)
        object.__setattr__(self, 'segments', segments)

    @property
    def start(self) -> float:
        """Cam angle where the first segment starts (rad)."""
        return self.segments[0].start

    @cached_property
    def _offsets(self) -> FloatArray:
        return np.array([segment.start - self.start for segment in self.segments])

    @cached_property
    def _spans(self) -> FloatArray:
        return np.array([segment.span for segment in self.segments])

    def evaluate(self, theta: npt.ArrayLike) -> ProgramValues:
        """Return s and its derivatives per rad at cam angles theta (rad, any real, mod 2 pi)."""
        angle = checked_array('theta', theta, np.isfinite, 'must be finite (rad)')
        local = angle - self.start
        if local.size and not (local.min() >= 0.0 and local.max() < TWO_PI):
            local = np.mod(local, TWO_PI)
        flat = local.ravel()
        index = np.searchsorted(self._offsets[1:], flat, side='right')
        values = [np.empty_like(flat) for _ in range(4)]
        for number, inside in self._segment_parts(index):
            u = np.clip((flat[inside] - self._offsets[number]) / self._spans[number], 0.0, 1.0)
            for out, part in zip(values, _segment_values(self.segments[number], u)):
                out[inside] = part
        return ProgramValues(*(value.reshape(local.shape) for value in values))

    def _segment_parts(self, index: npt.NDArray[np.intp]) -> list[tuple[int, slice | FloatArray]]:
        """Return (segment number, where) for each segment that has samples.

        Sorted angles (a profile, a sweep) give contiguous slices, which cost no gather or
        scatter; any other order gives boolean masks. Segments without samples are skipped.
        """
        count = len(self.segments)
        if index.size < 2 or bool(np.all(index[1:] >= index[:-1])):
            edges = np.searchsorted(index, np.arange(count + 1))
            return [(number, slice(int(low), int(high)))
                    for number, (low, high) in enumerate(zip(edges[:-1], edges[1:]))
                    if high > low]
        present = np.flatnonzero(np.bincount(index, minlength=count))
        return [(int(number), index == number) for number in present]

    def continuity_report(self) -> tuple[Discontinuity, ...]:
        """
        List every jump of s, ds, d2s or d3s, at the joints and inside piecewise laws.

        Joint limits come from the laws' end values (u = 1 of the segment before, u = 0 of the
        segment after; the joint at `start` is the wrap from the last segment).  Jumps below
        JUMP_TOLERANCE * max(1, |left|, |right|) are left out.  Sorted by angle, then order.
        """
        found: list[Discontinuity] = []
        for number, segment in enumerate(self.segments):
            before = self.segments[number - 1]
            places = [(segment.start, _segment_values(before, 1.0), _segment_values(segment, 0.0))]
            for at in segment.law.breakpoints:
                places.append((segment.start + at * segment.span,
                               _segment_values(segment, np.nextafter(at, -np.inf)),
                               _segment_values(segment, at)))
            for angle, left, right in places:
                for order, (low, high) in enumerate(zip(left, right)):
                    below, above = float(low), float(high)
                    if abs(above - below) > JUMP_TOLERANCE * max(1.0, abs(below), abs(above)):
                        found.append(Discontinuity(angle, order, below, above, number))
        return tuple(sorted(found, key=lambda item: (item.angle, item.order)))

    def segment_summary(self) -> tuple[SegmentSummary, ...]:
        """Return each segment's law name, cv, ca, cj and peak |ds|, |d2s|, |d3s| per rad."""
        summaries = []
        for number, segment in enumerate(self.segments):
            law, stroke, span = segment.law, abs(segment.stroke), segment.span
            peaks = [stroke * value / span ** order if stroke else 0.0
                     for order, value in ((1, law.cv), (2, law.ca), (3, law.cj))]
            summaries.append(SegmentSummary(number, law.name, segment.start, segment.end,
                                            segment.s_start, segment.s_end, law.cv, law.ca,
                                            law.cj, *peaks))
        return tuple(summaries)


def _check_segments(segments: Sequence[Segment]) -> None:
    """Raise InvalidParameter, naming the segment, unless the segments form a valid program."""
    if not segments:
        raise InvalidParameter('segments', list(segments), 'must hold at least one segment')
    for number, segment in enumerate(segments):
        _check_segment(f'segments[{number}]', segment)
    for number in range(1, len(segments)):
        gap = segments[number].start - segments[number - 1].end
        if abs(gap) > ANGLE_TOLERANCE:
            what = 'a gap' if gap > 0.0 else 'an overlap'
            raise InvalidParameter(
                f'segments[{number}].start', segments[number].start,
                f'must equal segments[{number - 1}].end = {segments[number - 1].end!r} rad '
                f'(leaves {what} of {math.degrees(abs(gap)):.6g} deg)')
    total = segments[-1].end - segments[0].start
    if abs(total - TWO_PI) > ANGLE_TOLERANCE:
        raise InvalidParameter(
            f'segments[{len(segments) - 1}].end', segments[-1].end,
            f'the segments must cover 360 deg from segments[0].start = {segments[0].start!r} rad, '
            f'not {math.degrees(total):.6g} deg')
    for number, segment in enumerate(segments):
        before = (number - 1) % len(segments)
        if abs(segment.s_start - segments[before].s_end) > POSITION_TOLERANCE:
            where = ' (the wrap joint 360 -> 0 deg)' if number == 0 else ''
            raise InvalidParameter(
                f'segments[{number}].s_start', segment.s_start,
                f'must equal segments[{before}].s_end = {segments[before].s_end!r}{where}: '
                'the follower cannot jump')


def _check_segment(name: str, segment: Segment) -> None:
    """Raise InvalidParameter, naming the field, unless one segment is valid on its own."""
    if not isinstance(segment, Segment):
        raise InvalidParameter(name, segment, 'must be a Segment')
    if not isinstance(segment.law, MotionLaw):
        raise InvalidParameter(f'{name}.law', segment.law,
                               'must be a MotionLaw; make_law(name, ...) knows ' + ', '.join(LAWS))
    for field in ('start', 'end', 's_start', 's_end'):
        value = getattr(segment, field)
        if not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise InvalidParameter(f'{name}.{field}', value, 'must be a finite number')
    if not segment.end > segment.start:
        raise InvalidParameter(f'{name}.end', segment.end,
                               f'must exceed start = {segment.start!r} rad (a positive span)')
    if isinstance(segment.law, Dwell) and abs(segment.stroke) > POSITION_TOLERANCE:
        raise InvalidParameter(f'{name}.s_end', segment.s_end,
                               f'a dwell must end where it starts (s_start = {segment.s_start!r})')
