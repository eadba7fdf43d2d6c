"""
Motion programs: ordered segments of motion laws covering one cam revolution.

Each segment maps a cam-angle range onto a motion law and a follower travel (segment.py).

The segments follow each other without gap or overlap and cover exactly 2 pi, starting at the
first segment's start (any angle, e.g. 0 or -pi/2); `evaluate` takes any real angle modulo 2 pi.
A program may advance: end `advance` above where it starts (a rotary slave turning on by a
full turn per cycle); then s(theta + 2 pi n) = s(theta) + n advance.
"""

import math
from bisect import bisect_right
from dataclasses import dataclass
from functools import cached_property
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..arrays import BLOCK, checked_array, finite_float, float_array, FloatArray, Values
from ..cam_angles import TWO_PI
from ._law_base import LawValues
from ..errors import InvalidParameter
from .laws import Dwell
from .segment import (check_segment, is_jump, POSITION_TOLERANCE, Segment, segment_into,
                      segment_values, segment_values_at, SegmentSummary, summarize)
#: Largest gap, overlap, or error of the 2 pi total, accepted between segments (rad).
ANGLE_TOLERANCE = 1e-9


def _ungrouped(grouped: FloatArray, order: npt.NDArray[np.intp]) -> FloatArray:
    """Return the values grouped[i] of angle order[i] back in the order of the angles."""
    values = np.empty_like(grouped)
    values[order] = grouped
    return values


def _read_only(array: npt.ArrayLike) -> FloatArray:
    """Return array as a read-only float array (no copy when already one)."""
    result = np.asarray(array, dtype=float)
    result.flags.writeable = False
    return result


def _speed(omega: float) -> float:
    """Return a cam speed omega (rad/s) as a float, or raise unless it is finite."""
    speed = float(omega)
    if not math.isfinite(speed):
        raise InvalidParameter('omega', omega, 'must be a finite cam speed in rad/s')
    return speed


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
        timed = time_derivatives(omega, self.ds, self.d2s, self.d3s)
        return TimeValues(self.s, *map(_read_only, timed))


def time_derivatives(omega: float, ds: Values, d2s: Values,
                     d3s: Values) -> tuple[Values, Values, Values]:
    """Return velocity, acceleration and jerk at constant cam speed omega (rad/s) from the
    derivatives per rad; floats (one angle) or arrays."""
    speed = _speed(omega)
    return speed * ds, speed ** 2 * d2s, speed ** 3 * d3s


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
class MotionProgram:
    """
    Ordered segments covering one revolution [start, start + 2 pi) (see the module docstring).

    Construction checks every rule once and raises InvalidParameter naming the segment, e.g.
    'segments[2].start': non-finite values, end <= start, gaps and overlaps beyond
    ANGLE_TOLERANCE, a total other than 360 deg, a position jump at a joint (including the wrap
    from the last segment to the first), a dwell that moves, a law that is not a MotionLaw.
    """

    segments: tuple[Segment, ...]
    advance: float = 0.0

    def __post_init__(self) -> None:
        """Check the segments once and store them as a tuple."""
        try:
            segments = tuple(self.segments)
        except TypeError as err:
            raise InvalidParameter('segments', self.segments, 'must be a sequence') from err
        finite_float('advance', self.advance)
        _check_segments(segments, self.advance)
        object.__setattr__(self, 'segments', segments)

    @property
    def start(self) -> float:
        """Cam angle where the first segment starts (rad)."""
        return self.segments[0].start

    @cached_property
    def breaks(self) -> FloatArray:
        """Cam angles (rad, read-only) where the motion or a derivative may jump.

        Every segment joint and every breakpoint inside a piecewise law.
        """
        return _read_only([segment.start + at * segment.span for segment in self.segments
                           for at in (0.0, *segment.law.breakpoints)])

    @cached_property
    def _offsets(self) -> FloatArray:
        return np.array([segment.start - self.start for segment in self.segments])

    @cached_property
    def _boundaries(self) -> FloatArray:
        # Where segments 1, 2, ... take over. Non-decreasing even where a segment shorter than an
        # accepted overlap lets the next offset step back: the earlier segment keeps the overlap.
        return np.maximum.accumulate(self._offsets)[1:]

    @cached_property
    def _boundary_list(self) -> list[float]:
        return self._boundaries.tolist()

    @cached_property
    def _spans(self) -> FloatArray:
        return np.array([segment.span for segment in self.segments])

    @cached_property
    def _dwell_values(self) -> dict[int, LawValues]:
        # s, ds, d2s, d3s of each dwell, the same at every angle: filled in, not evaluated.
        return {number: segment_values(segment, 0.0)
                for number, segment in enumerate(self.segments) if isinstance(segment.law, Dwell)}

    def evaluate(self, theta: npt.ArrayLike) -> ProgramValues:
        """Return s and its derivatives per rad at cam angles theta (rad, any real, mod 2 pi)."""
        return ProgramValues(*self._values(theta, None))

    def evaluate_at_speed(self, theta: npt.ArrayLike, omega: float) -> TimeValues:
        """Return evaluate(theta).at_speed(omega) without keeping the per-rad derivatives."""
        speed = _speed(omega)
        return TimeValues(*(_read_only(value) for value in self._values(
            theta, (speed, speed ** 2, speed ** 3))))

    def at(self, theta: float) -> tuple[float, float, float, float]:
        """
        Return s, ds, d2s, d3s per rad at one cam angle (rad, any real) as plain floats.

        The path of one master message or one requested angle: the same numbers as evaluate,
        with the law evaluated once on a 0-d array and the rest in floats (NumPy costs about
        1.5 us a call on an array of one element, a float operation some 20 ns).
        """
        if not math.isfinite(theta):
            raise InvalidParameter('theta', theta, 'must be finite (rad)')
        turns, local = 0.0, theta - self.start if self.start else theta
        if self.advance:
            turns, local = divmod(theta - self.start, TWO_PI)
        elif not 0.0 <= local < TWO_PI:
            local %= TWO_PI
        number = bisect_right(self._boundary_list, local)
        values = self._dwell_floats.get(number)
        if values is None:
            u = min((local - self._offset_list[number]) / self._span_list[number], 1.0)
            values = segment_values_at(self.segments[number], u)
        if turns:
            return (values[0] + self.advance * turns, *values[1:])
        return values

    @cached_property
    def _dwell_floats(self) -> dict[int, tuple[float, float, float, float]]:
        return {number: (float(s), float(ds), float(d2s), float(d3s))
                for number, (s, ds, d2s, d3s) in self._dwell_values.items()}

    @cached_property
    def _offset_list(self) -> list[float]:
        return self._offsets.tolist()

    @cached_property
    def _span_list(self) -> list[float]:
        return self._spans.tolist()

    def _values(self, theta: npt.ArrayLike,
                scales: tuple[float, float, float] | None) -> LawValues:
        """Return s, ds, d2s, d3s at theta, the derivatives times scales (if given)."""
        if isinstance(theta, float) or isinstance(theta, np.ndarray) and theta.size == 1 \
                and theta.dtype == np.float64:  # one angle (a master message): no grouping
            s, *derivatives = self.at(float(np.reshape(theta, -1)[0]))
            scaled = [value * scale for value, scale in zip(derivatives, scales or (1.0,) * 3)]
            return LawValues(*(np.full(np.shape(theta), value) for value in (s, *scaled)))
        local = self._local_angles(theta)
        turns = None
        if self.advance:
            turns, local = np.divmod(np.asarray(theta, dtype=float) - self.start, TWO_PI)
        flat = local.reshape(-1)
        order, bounds = self._grouping(flat)
        grouped = flat if order is None else flat[order]
        values = LawValues(*(np.empty(flat.size) for _ in range(4)))
        for number, (low, high) in enumerate(zip(bounds[:-1], bounds[1:])):
            for first in range(low, high, BLOCK):  # blocks: the law's work stays in cache
                end = min(first + BLOCK, high)
                part = LawValues(*(value[first:end] for value in values))
                self._evaluate_segment(number, grouped[first:end], part)
                for value, scale in zip(part[1:], scales or ()):
                    value *= scale
        if order is not None:
            values = LawValues(*(_ungrouped(value, order) for value in values))
        if turns is not None:
            values.y[...] += self.advance * turns.reshape(-1)
        return LawValues(*(value.reshape(local.shape) for value in values))

    def _end_values(self, number: int) -> LawValues:
        """Return s and its derivatives where segment number ends, as the next one sees them.

        At the wrap joint (the last segment's end) the next cycle starts `advance` lower.
        """
        values = segment_values(self.segments[number], 1.0)
        if number % len(self.segments) == len(self.segments) - 1 and self.advance:
            values.y[...] -= self.advance
        return values

    def segment_at(self, angle: float) -> int:
        """Return the number of the segment that owns a cam angle (rad, any finite value)."""
        return bisect_right(self._boundary_list, (angle - self.start) % TWO_PI)

    def _local_angles(self, theta: npt.ArrayLike) -> FloatArray:
        """Return theta - start, wrapped into [0, 2 pi] if needed, or raise unless finite."""
        rule = 'must be finite (rad)'
        angle = float_array('theta', theta, rule)
        local = angle - self.start if self.start else angle
        if local.size:
            low, high = local.min(), local.max()  # NaN or inf fails the range test too
            if not (low >= 0.0 and high < TWO_PI):
                if not (math.isfinite(low) and math.isfinite(high)):
                    checked_array('theta', angle, np.isfinite, rule)  # raises, naming the angle
                local = np.mod(local, TWO_PI)
        return local

    def _grouping(self, flat: FloatArray) -> tuple[npt.NDArray[np.intp] | None, list[int]]:
        """
        Return (order, bounds): segment k owns grouped[bounds[k]:bounds[k + 1]].

        grouped is flat[order], or flat itself when order is None: sorted angles (a profile, a
        sweep) split into slices by one search of the boundaries, without a gather or scatter.
        Other angles are grouped by a stable sort of their segment numbers.
        """
        if flat.size < 2 or bool((flat[1:] >= flat[:-1]).all()):
            return None, [0, *np.searchsorted(flat, self._boundaries).tolist(), flat.size]
        count = len(self.segments)
        index = np.searchsorted(self._boundaries, flat, side='right')
        index = index.astype(np.min_scalar_type(count))  # 8 or 16 bits: a radix sort
        bounds = np.cumsum(np.bincount(index, minlength=count)).tolist()
        return np.argsort(index, kind='stable'), [0, *bounds]

    def _evaluate_segment(self, number: int, angles: FloatArray, values: LawValues) -> None:
        """Write s, ds, d2s, d3s of a segment at its angles (local, in order) into values."""
        constants = self._dwell_values.get(number)
        if constants is not None:
            for value, constant in zip(values, constants):
                value.fill(constant)
            return
        u = values.y
        np.subtract(angles, self._offsets[number], out=u)
        np.divide(u, self._spans[number], out=u)
        np.minimum(u, 1.0, out=u)  # past 1 by round-off or a joint gap; >= 0 by the grouping
        segment_into(self.segments[number], values)

    def continuity_report(self) -> tuple[Discontinuity, ...]:
        """
        List every jump of s, ds, d2s or d3s, at the joints and inside piecewise laws.

        Joint limits come from the laws' end values (u = 1 of the segment before, u = 0 of the
        segment after; the joint at `start` is the wrap from the last segment).  Jumps below
        JUMP_TOLERANCE times the derivative's scale (|stroke| / span**order of the segments
        meeting there, or the larger one-sided value) are rounding noise and left out, so a
        joint that is smooth in exact arithmetic is never listed.  Sorted by angle, then order.
        """
        found: list[Discontinuity] = []
        for number, segment in enumerate(self.segments):
            before = self.segments[number - 1]
            places: list[tuple[float, tuple[Segment, ...], LawValues, LawValues]] = [
                (segment.start, (before, segment), self._end_values(number - 1),
                 segment_values(segment, 0.0))]
            for at in segment.law.breakpoints:
                places.append((segment.start + at * segment.span, (segment,),
                               segment_values(segment, np.nextafter(at, -np.inf)),
                               segment_values(segment, at)))
            for angle, near, left, right in places:
                for order, (low, high) in enumerate(zip(left, right)):
                    below, above = float(low), float(high)
                    if is_jump(below, above, order, near):
                        found.append(Discontinuity(angle, order, below, above, number))
        return tuple(sorted(found, key=lambda item: (item.angle, item.order)))

    def segment_summary(self) -> tuple[SegmentSummary, ...]:
        """Return each segment's law name, cv, ca, cj, peak |ds|, |d2s|, |d3s| per rad, task."""
        return self._summaries

    @cached_property
    def _summaries(self) -> tuple[SegmentSummary, ...]:
        return tuple(summarize(number, segment) for number, segment in enumerate(self.segments))


def _check_segments(segments: Sequence[Segment], advance: float) -> None:
    """Raise InvalidParameter, naming the segment, unless the segments form a valid program."""
    if not segments:
        raise InvalidParameter('segments', list(segments), 'must hold at least one segment')
    for number, segment in enumerate(segments):
        check_segment(f'segments[{number}]', segment)
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
        arrives = segments[before].s_end - (advance if number == 0 else 0.0)
        if abs(segment.s_start - arrives) > POSITION_TOLERANCE:
            where = ' (the wrap joint 360 -> 0 deg)' if number == 0 else ''
            less = f' - advance {advance!r}' if number == 0 and advance else ''
            raise InvalidParameter(
                f'segments[{number}].s_start', segment.s_start,
                f'must equal segments[{before}].s_end = {segments[before].s_end!r}{less}{where}: '
                'the follower cannot jump')
