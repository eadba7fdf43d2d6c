"""
Compiled cams: the steady commands of many axes in one NumPy pass.

Evaluating N axes' programs angle by angle costs N times the single-axis path in Python. A
ProgramTable holds one motion program s(theta) over one cam cycle as a piecewise quintic Hermite
table: knots on a uniform grid plus every segment joint and law breakpoint (program.breaks), with
s, s', s'' the program's own at both ends of every interval, one-sided at a break (the interval
after it starts with the values after it, the one before ends with those before), so every jump
of a derivative falls on a knot. The grid is doubled from FIRST_INTERVALS until the table's
errors, scanned on every interval and refined to the largest (extremes.refine_extrema, then
times SAFETY), are at most ACCURACY of the program's stroke (position) and of its largest |s'|
(velocity), and further while that halves the position error, down to the exact program's own
rounding (ROUNDING); the table keeps them (ProgramTable.errors).

CompiledCams stacks the tables of N axes (each table's knots shifted by its place in the stack):
one searchsorted and one polynomial evaluation give every axis's s and s' at its cam angle, and
the chain rule with each axis's mapping (as ElectronicCam.derivatives: master offset and scaling,
slave scaling and offset, an advancing program's advance per whole turn) its position and
velocity command: what the node sends and publishes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Optional, Sequence

import numpy as np

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ..extremes import refine_extrema
from ..motion.program import MotionProgram
from ..motion.segment import segment_values
from .master import ElectronicCam

#: Largest error of a table: of the stroke (position) and of the largest |s'| (velocity).
ACCURACY = 1e-9
#: The grid is refined further, while that halves the position error, down to this fraction of
#: the stroke: the exact program's own rounding (a few ulps).
ROUNDING = 1e-15
#: Uniform grid intervals per cam cycle: the first tried, and the most (doubling in between).
FIRST_INTERVALS, MOST_INTERVALS = 64, 2 ** 14
#: Grid knots nearer a break than this fraction of the grid spacing are left out (a sliver
#: interval would turn the rounding of s into large derivatives).
NEAREST_KNOT = 0.25
#: Samples per interval of the error scan (its ends included).
SCAN_SAMPLES = 8
#: The errors stated are the refined largest times this: the exact program's own rounding makes
#: the error noisy by a few percent where it is below 1e-12 of the stroke (polydyne.yaml).
SAFETY = 1.5
#: Where each stacked table's knots start: table j at j * STACK_SPACING (> 2 pi).
STACK_SPACING = 8.0
#: Factor of coefficient c[j + k] in the k-th derivative's coefficient of t**j: (j + k)! / j!.
_FACTORS = np.array([[math.factorial(j + k) / math.factorial(j) if j + k < 6 else 0.0
                      for j in range(6)] for k in range(4)])
_POWERS = np.arange(6)


class TableErrors(NamedTuple):
    """A table's largest errors against its program, and the scales they are measured against.

    position, velocity: largest |s - s_table| and |s' - s'_table| over the cycle (per rad,
    refined, times SAFETY);
    stroke, slope: the program's range of s and largest |s'| over its values at the knots (its
    true ones to rounding where the extremes are at breaks, else a little less: the bounds they
    set err on the safe side).
    """

    position: float
    velocity: float
    stroke: float
    slope: float

    @property
    def accurate(self) -> bool:
        """Say whether both errors are within ACCURACY of their scales."""
        return (self.position <= ACCURACY * self.stroke
                and self.velocity <= ACCURACY * self.slope)


@dataclass(frozen=True, eq=False)
class ProgramTable:
    """One program as a piecewise quintic: knots (local angle theta - start, 0 .. 2 pi) and rows.

    rows[i, k, j] is the coefficient of t**j of the k-th derivative on the interval starting at
    knot i (t = local angle - knots[i]); the last knot's row is the last interval's polynomial
    about 2 pi, for a local angle of 2 pi itself (an angle just below a whole turn rounded up).
    """

    program: MotionProgram
    knots: FloatArray
    rows: FloatArray
    errors: TableErrors

    def evaluate(self, theta: FloatArray) -> FloatArray:
        """Return rows s, s', s'', s''' (per rad) at cam angles theta (rad, any real)."""
        program = self.program
        angles = np.asarray(theta, dtype=float)
        turns, local = np.divmod(angles.reshape(-1) - program.start, TWO_PI)
        values = _interpolate(self.knots, *_padded([self]), local)
        values[0] += program.advance * turns
        return values.reshape((4, *angles.shape))


def compile_program(program: MotionProgram) -> ProgramTable:
    """
    Return the program's table, as exact as its rounding allows.

    The grid doubles until the table meets ACCURACY and its position error is down to
    ROUNDING of the stroke or no longer halves (the exact program's own rounding); at
    MOST_INTERVALS it stops, with its errors, met or not.
    """
    intervals, before = FIRST_INTERVALS, math.inf
    while True:
        table = _table(program, intervals)
        errors = table.errors
        settled = errors.position <= ROUNDING * errors.stroke or errors.position > before / 2
        if errors.accurate and settled or intervals >= MOST_INTERVALS:
            return table
        intervals, before = 2 * intervals, errors.position


class CompiledCams:
    """The cams of N axes, their tables stacked: every axis's command at one master sample."""

    def __init__(self, cams: Sequence[ElectronicCam], tables: Sequence[ProgramTable]):
        """Stack the tables (tables[i]: cams[i].program's; one copy of each table)."""
        self.cams = tuple(cams)
        unique = list({id(table): table for table in tables}.values())
        place = np.array([unique.index(table) for table in tables])
        self._keys = np.concatenate([table.knots + STACK_SPACING * number
                                     for number, table in enumerate(unique)])
        knots, rows = _padded(unique)
        self._knots, self._rows = knots, np.ascontiguousarray(rows[:, :2])  # s and s' only
        self._shift = None if len(unique) == 1 else STACK_SPACING * place
        mappings = [cam.mapping for cam in cams]
        scaling = np.array([mapping.master_scaling for mapping in mappings])
        starts = np.array([cam.program.start for cam in cams])
        # (q - q0) / m - start = q / m - (q0 / m + start)
        self._origin = np.array([mapping.master_offset for mapping in mappings]) / scaling \
            + starts
        self._per_turn = None if (scaling == 1.0).all() else 1.0 / scaling
        k = np.array([mapping.slave_scaling for mapping in mappings])
        advance = k * np.array([cam.program.advance for cam in cams])  # of y per whole turn
        self._advance = advance if advance.any() else None
        self._per_master = np.array([k, k / scaling])  # dy/ds and dy'/ds' per rad of master
        self._offset = np.array([[mapping.slave_offset for mapping in mappings], [0.0] * len(k)])
        #: Each axis's largest velocity error per rad/s of master (the table's, chained).
        self.velocity_error = np.abs(self._per_master[1]) * np.array(
            [table.errors.velocity for table in tables])

    def commands(self, master: float, omega: float) -> FloatArray:
        """
        Return rows position and velocity, one entry per axis, at a master sample.

        What the node commands and publishes (ElectronicCam.setpoints' first two, with master
        position and speed); the chain rule of acceleration and jerk is left out.
        """
        turned = (master if self._per_turn is None else master * self._per_turn) - self._origin
        if self._advance is None:
            cycles, local = None, np.remainder(turned, TWO_PI)
        else:
            cycles, local = np.divmod(turned, TWO_PI)
        values = _interpolate(self._keys, self._knots, self._rows, local, self._shift,
                              self._per_master)  # y - y0 in a cycle, and y' per rad of master
        if cycles is not None:
            values[0] += self._advance * cycles
        values[1] *= omega
        values += self._offset
        return values


def _padded(tables: Sequence[ProgramTable]) -> tuple[FloatArray, FloatArray]:
    """Return the tables' knots and rows concatenated after one unused entry: the interval of
    knot i is then entry i + 1, the index searchsorted(side='right') gives."""
    knots = np.concatenate([[0.0], *(table.knots for table in tables)])
    rows = np.concatenate([np.zeros((1, 4, 6)), *(table.rows for table in tables)])
    return knots, rows


def _interpolate(keys: FloatArray, knots: FloatArray, rows: FloatArray, local: FloatArray,
                 shift: Optional[FloatArray] = None,
                 scale: Optional[FloatArray] = None) -> FloatArray:
    """
    Return the rows' s, s', ... (as many as rows holds) at local angles in [0, 2 pi] (1-D) of
    stacked tables, each times scale (same shape) if given.

    keys: the knots, each table's shifted by its place; shift: the shift of each angle's table
    (None: a single table, unshifted); knots and rows as _padded gives them.
    """
    if shift is None:
        index = np.searchsorted(keys, local, side='right')
    else:
        index = np.searchsorted(keys, local + shift, side='right')
        index -= local < knots[index]  # the shift rounded an angle just below a knot onto it
    t = local - knots.take(index)
    coefficients, powers = rows.take(index, axis=0), np.power(t[:, np.newaxis], _POWERS)
    values: FloatArray = (np.einsum('nkj,nj->kn', coefficients, powers) if scale is None else
                          np.einsum('nkj,nj,kn->kn', coefficients, powers, scale))
    return values


def _table(program: MotionProgram, intervals: int) -> ProgramTable:
    """Return the program's table on a grid of intervals per cycle, with its errors."""
    knots, left, right = _knot_values(program, intervals)
    h = np.diff(knots)
    (y0, d0, a0), (y1, d1, a1) = left, right
    gap = y1 - y0 - h * (d0 + 0.5 * a0 * h)  # what the quadratic from the left end misses
    slope, bend = d1 - d0 - a0 * h, a1 - a0
    c = np.zeros((knots.size, 6))
    c[:-1, :3] = np.column_stack((y0, d0, 0.5 * a0))
    c[:-1, 3] = (20.0 * gap - 8.0 * slope * h + bend * h * h) / (2.0 * h ** 3)
    c[:-1, 4] = (-30.0 * gap + 14.0 * slope * h - 2.0 * bend * h * h) / (2.0 * h ** 4)
    c[:-1, 5] = (12.0 * gap - 6.0 * slope * h + bend * h * h) / (2.0 * h ** 5)
    # The last interval about its end (a Taylor shift by h): sum_j C(j, m) c_j h**(j - m).
    c[-1] = [sum(math.comb(j, m) * c[-2, j] * h[-1] ** (j - m) for j in range(m, 6))
             for m in range(6)]
    rows = np.zeros((knots.size, 4, 6))
    for order in range(4):
        rows[:, order, :6 - order] = c[:, order:] * _FACTORS[order, :6 - order]
    both = np.concatenate((left, right), axis=1)
    scales = (float(np.ptp(both[0])), float(np.abs(both[1]).max()))
    table = ProgramTable(program, knots, rows, TableErrors(0.0, 0.0, *scales))
    object.__setattr__(table, 'errors', TableErrors(*_errors(table), *scales))
    return table


def _knot_values(program: MotionProgram, intervals: int
                 ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return the knots (local angles, 0 .. 2 pi) and rows s, s', s'' at each interval's left
    end (the values after it) and right end (the values before it)."""
    segments = program.segments
    offsets = np.array([segment.start for segment in segments]) - program.start
    owned = [0.0, *np.maximum.accumulate(offsets)[1:].tolist(), TWO_PI]  # as program.at
    breaks = np.unique(np.concatenate((program.breaks - program.start, owned)))
    grid = np.linspace(0.0, TWO_PI, intervals + 1)
    nearest = np.abs(grid[:, np.newaxis] - breaks).min(axis=1)
    grid = grid[nearest > NEAREST_KNOT * TWO_PI / intervals]
    knots, lefts, rights = [], [], []
    for number, segment in enumerate(segments):
        low, high = owned[number], owned[number + 1]
        if high <= low:
            continue
        span, offset = segment.span, float(offsets[number])
        at = np.array(segment.law.breakpoints, dtype=float)
        laws = offset + at * span
        grid_in, law_in = grid[(grid > low) & (grid < high)], (laws > low) & (laws < high)
        angles = np.concatenate((grid_in, laws[law_in]))
        order = np.argsort(angles, kind='stable')
        u_after = np.concatenate(((grid_in - offset) / span, at[law_in]))[order]
        u_before = np.concatenate(((grid_in - offset) / span,
                                   np.nextafter(at[law_in], -np.inf)))[order]
        knots.append(np.concatenate(([low], angles[order])))
        lefts.append(segment_values(segment, np.concatenate((
            [max((low - offset) / span, 0.0)], u_after)))[:3])
        rights.append(segment_values(segment, np.concatenate((
            u_before, [min((high - offset) / span, 1.0)])))[:3])
    ends = np.concatenate(knots + [[TWO_PI]])
    return ends, np.concatenate(lefts, axis=1), np.concatenate(rights, axis=1)


def _errors(table: ProgramTable) -> tuple[float, float]:
    """Return the table's largest |error| of s and of s', refined from a scan of every
    interval (SCAN_SAMPLES each)."""
    program, knots = table.program, table.knots
    fractions = np.arange(SCAN_SAMPLES - 1) / (SCAN_SAMPLES - 1)
    local = (knots[:-1, np.newaxis] + np.diff(knots)[:, np.newaxis] * fractions).reshape(-1)
    theta = program.start + np.unique(local)

    def error(angles: FloatArray) -> FloatArray:
        exact = program.evaluate(angles)
        return np.abs(table.evaluate(angles)[:2] - np.array([exact.s, exact.ds]))

    found = refine_extrema(error, theta, error(theta), ('max', 'max'),
                           breaks=program.start + knots)
    return SAFETY * found[0][0], SAFETY * found[1][0]
