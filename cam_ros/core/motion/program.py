"""
Motion programs: ordered segments of motion laws covering one cam revolution.

A segment maps its cam-angle range [start, end] (rad) onto a law's u in [0, 1] and the law's y
onto the follower position: s = s_start + (s_end - s_start) * y(u), so that, with the span
beta = end - start and the stroke h = s_end - s_start, ds/dtheta = h y'/beta,
d2s/dtheta2 = h y''/beta**2, d3s/dtheta3 = h y'''/beta**3.  Positions are in m for a
translating follower, in rad (arm angle) for an oscillating one; derivatives are per rad of cam.
A segment that starts and ends moving (a VDI 2143 motion task, see tasks.py) adds a ramp:
s = s_start + ramp (theta - start) + amplitude y(u), amplitude = h - ramp beta unless given.

The segments follow each other without gap or overlap and cover exactly 2 pi, starting at the
first segment's start (any angle, e.g. 0 or -pi/2); `evaluate` takes any real angle modulo 2 pi.
A program may advance: end `advance` above where it starts (a rotary slave turning on by a
full turn per cycle); then s(theta + 2 pi n) = s(theta) + n advance.
"""

import math
import numbers
from bisect import bisect_right
from dataclasses import dataclass
from functools import cached_property
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..arrays import BLOCK, checked_array, finite_float, float_array, FloatArray
from ._law_base import LawValues, workspace
from ._polynomial import BoundaryPolynomial
from ..errors import InvalidParameter
from ..extremes import refine_extrema
from .laws import Dwell, LAWS, MotionLaw

TWO_PI = 2.0 * math.pi
#: Largest gap, overlap, or error of the 2 pi total, accepted between segments (rad).
ANGLE_TOLERANCE = 1e-9
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


def _segment_into(segment: Segment, values: LawValues) -> None:
    """Overwrite values, normalised u in [0, 1] in values.y, by s, ds, d2s, d3s per rad."""
    ramp, span = segment.ramp, segment.span
    line = values.y * (ramp * span) if ramp else None
    segment.law._derivatives_into(values)
    y, y1, y2, y3 = values
    amplitude = segment.amplitude
    y *= amplitude
    y += segment.s_start
    y1 *= amplitude / span
    y2 *= amplitude / span ** 2
    y3 *= amplitude / span ** 3
    if line is not None:
        y += line
        y1 += ramp


def segment_values(segment: Segment, u: npt.ArrayLike) -> LawValues:
    """Return s, ds, d2s, d3s (per rad of cam) of a segment at normalised u in [0, 1]."""
    values = workspace(u)
    _segment_into(segment, values)
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
        speed = _speed(omega)
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
    task: str = 'R-R'
    inflection: float = 0.5
    #: How far peak |ds| exceeds the larger end |ds| of a task that starts or ends moving (an
    #: R-G rise whose mean slope equals its end velocity must overshoot it); 0 otherwise.
    overshoot: float = 0.0

    def peaks_at_speed(self, omega: float) -> tuple[float, float, float]:
        """Return peak |velocity|, |acceleration|, |jerk| at constant cam speed omega (rad/s)."""
        return self.peak_ds * omega, self.peak_d2s * omega ** 2, self.peak_d3s * omega ** 3


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

    def _values(self, theta: npt.ArrayLike,
                scales: tuple[float, float, float] | None) -> LawValues:
        """Return s, ds, d2s, d3s at theta, the derivatives times scales (if given)."""
        if isinstance(theta, float) or isinstance(theta, np.ndarray) and theta.size == 1 \
                and theta.dtype == np.float64:  # one angle (a master message): no grouping
            return LawValues(*(value.reshape(np.shape(theta))
                               for value in self._value(float(np.reshape(theta, -1)[0]), scales)))
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

    def _value(self, theta: float, scales: tuple[float, float, float] | None) -> LawValues:
        """Return _values at one angle (arrays of one), the same numbers as an array of more."""
        if not math.isfinite(theta):
            raise InvalidParameter('theta', theta, 'must be finite (rad)')
        turns, local = 0.0, theta - self.start if self.start else theta
        if self.advance:
            turns, local = divmod(theta - self.start, TWO_PI)
        elif not 0.0 <= local < TWO_PI:
            local %= TWO_PI
        values = LawValues(*(np.empty(1) for _ in range(4)))
        self._evaluate_segment(bisect_right(self._boundary_list, local), np.array([local]), values)
        for value, scale in zip(values[1:], scales or ()):
            value *= scale
        if turns:
            values.y[0] += self.advance * turns
        return values

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
        return int(np.searchsorted(self._boundaries, (angle - self.start) % TWO_PI, side='right'))

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
        _segment_into(self.segments[number], values)

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
        summaries = []
        for number, segment in enumerate(self.segments):
            law, amplitude, span = segment.law, abs(segment.amplitude), segment.span
            peaks = [amplitude * value / span ** order if amplitude else 0.0
                     for order, value in ((1, law.cv), (2, law.ca), (3, law.cj))]
            task = motion_task(segment)
            overshoot = 0.0
            if segment.ramp or 'G' in task or 'B' in task:
                velocity = velocity_extremes(segment)
                if segment.ramp:  # ramp + amplitude y'/span does not peak where y' does
                    peaks[0] = max(velocity[0][0], -velocity[1][0])
                overshoot = _overshoot(segment, task, velocity)
            summaries.append(SegmentSummary(
                number, law.name, segment.start, segment.end, segment.s_start, segment.s_end,
                law.cv, law.ca, law.cj, peaks[0], peaks[1], peaks[2], task,
                getattr(law, 'inflection', 0.5), overshoot))
        return tuple(summaries)


def velocity_extremes(segment: Segment) -> tuple[tuple[float, float], tuple[float, float]]:
    """Return (value, u) of the largest and of the smallest ds/dtheta on a segment, refined."""
    u = np.linspace(0.0, 1.0, VELOCITY_SAMPLES)

    def both(x: FloatArray) -> FloatArray:
        ds = segment_values(segment, x).y1
        return np.stack([ds, ds])

    highest, lowest = refine_extrema(both, u, both(u), ('max', 'min'),
                                     breaks=segment.law.breakpoints, period=None)
    return highest, lowest


def _overshoot(segment: Segment, task: str,
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


def _check_segments(segments: Sequence[Segment], advance: float) -> None:
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
        arrives = segments[before].s_end - (advance if number == 0 else 0.0)
        if abs(segment.s_start - arrives) > POSITION_TOLERANCE:
            where = ' (the wrap joint 360 -> 0 deg)' if number == 0 else ''
            less = f' - advance {advance!r}' if number == 0 and advance else ''
            raise InvalidParameter(
                f'segments[{number}].s_start', segment.s_start,
                f'must equal segments[{before}].s_end = {segments[before].s_end!r}{less}{where}: '
                'the follower cannot jump')


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


def _check_segment(name: str, segment: Segment) -> None:
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
