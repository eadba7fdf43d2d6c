"""
Moves off the cams on a machine: plan them, check them against every interference pair over their
whole duration, and order them when they would collide together.

Every axis of the machine is commanded during the moves: a moving axis its move (ecam.moves:
y_cam(theta_v(t)) + e(t)), every other its cam at theta_v(t), all with the same theta_v motion
(MasterMotion: theta + omega t). Each pair is checked as the machine's cycle check does
(interference.py: a rotary slave modulo a turn), but over time t in [0, T], T the end of the
longest move (with theta_v moving, plus the time of the largest min_margin after it, when every
axis is on its cam again and a zone margin may still end):

- clearance: the smallest gap over t, located on a dense time grid (every move's own grid, and
  CHECK_SAMPLES per machine cycle theta_v travels) and refined to the true minimum by
  refine_extremum, every joint of a move's pieces, every cam joint and every whole turn of a
  rotary axis a break;
- zones: never both axes in the zone at once (an overlap is a negative margin: minus its longest
  stretch), and from one leaving to the other entering, within the window, at least the time the
  master takes for min_margin_deg at the larger of |omega| and cam_speed (on the cams at cam_speed
  that is the cycle check's rule; with theta_v at rest the rule needs a time, and takes
  cam_speed's). A margin is reported as that time times that speed, in machine angle, so it reads
  as the cycle check's and compares with min_margin_deg. An axis in the zone when the moves start
  has not entered it then, one still in it at the window's end has not left.

sequence_moves tries the moves together first; if a pair collides, one axis after another (each
waiting at its start, ecam.moves.Move.delayed, until the one before has reached its cam), the
orders in turn, and returns the first order in which no pair collides; else it refuses, with the
pair, its figure and the master angle and time where it fails together.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import permutations
from typing import Callable, Mapping, NamedTuple, Optional, Union

import numpy as np

from ..arrays import FloatArray
from ..ecam.master import MasterConfig
from ..ecam.moves import AxisState, MasterMotion, Move, on_cam, plan_move
from ..ecam.slave_limits import AxisUnit, SlaveLimits
from ..extremes import CHECK_SAMPLES, refine_extremum, refine_roots
from .config import InterferencePair
from .interference import as_checked, cycles, PairCheck, rotary, turn_crossings
from .machine import Axis, Machine
from .served import pair_line, pair_name

#: Most moving axes whose orders sequence_moves tries (n! orders).
MOST_ORDERED = 5
#: Fewest samples of a window in time.
FEWEST_SAMPLES = 2000


@dataclass(frozen=True)
class MoveCheck:
    """One pair during the moves: check.value a gap (m) or a margin (rad at speed, see the module),
    check.at the master angle (rad, in [0, 2 pi)) where, time the time after the start (s)."""

    check: PairCheck
    time: float

    @property
    def ok(self) -> bool:
        """Say whether the pair keeps its limit during the moves."""
        return self.check.ok

    def line(self, length_unit: str) -> str:
        """Say the pair's verdict in one line: the cycle check's (pair_line) and the time."""
        check = self.check
        if check.value == math.inf:
            return (f'{pair_name(check)}: never both in the zone, and no axis enters it after '
                    f'the other leaves: limit >= {math.degrees(check.pair.min_margin):.6g} deg: '
                    'ok')
        return f'{pair_line(check, length_unit)} ({self.time:.6g} s into the moves)'


class Sequence(NamedTuple):
    """Moves that do not collide: each axis's move (delayed to its turn), the order and checks.

    order: the moving axes one after another, or () when they move together.
    """

    moves: dict[str, Move]
    order: tuple[str, ...]
    checks: tuple[MoveCheck, ...]


def axis_limits(axis: Axis) -> tuple[SlaveLimits, AxisUnit, float]:
    """Return an axis's slave limits, its unit and its nominal master speed (at cam_speed)."""
    config = axis.design.config
    return (SlaveLimits.from_config(config), AxisUnit.of(config),
            MasterConfig.from_config(config).nominal_speed)


def plan_moves(machine: Machine, starts: Mapping[str, AxisState],
               master: MasterMotion) -> Union[dict[str, Move], str]:
    """Return every axis's move onto its cam from its start (axes not in starts stay on their
    cams: a move of duration 0), or why one cannot be made ('axis NAME: ...')."""
    moves = {}
    for axis in machine.axes:
        limits, unit, nominal = axis_limits(axis)
        if axis.name not in starts:
            moves[axis.name] = on_cam(axis.cam, limits, master)
            continue
        move = plan_move(axis.cam, limits, starts[axis.name], master, nominal, unit)
        if isinstance(move, str):
            return f'axis {axis.name}: {move}'
        moves[axis.name] = move
    return moves


def _window(machine: Machine, moves: Mapping[str, Move], master: MasterMotion) -> float:
    """Return the end (s) of the time checked: the longest move, and a margin after it."""
    end = max(move.duration for move in moves.values())
    margins = [pair.min_margin for pair in machine.config.interference if pair.type == 'zones']
    if master.omega and margins:
        end += max(margins) / _margin_speed(machine, master)
    return end


def _margin_speed(machine: Machine, master: MasterMotion) -> float:
    """Return the speed (rad/s) a zone margin in time is measured at (see the module)."""
    return max(abs(master.omega), float(machine.config.parameters['cam_speed']))


def _grid(machine: Machine, moves: Mapping[str, Move], master: MasterMotion,
          end: float) -> FloatArray:
    """Return sample times over [0, end]: every move's own grid, and the master's travel's."""
    travelled = abs(master.omega) * end / (2.0 * math.pi)
    count = max(FEWEST_SAMPLES, math.ceil(CHECK_SAMPLES * travelled
                                          * max(cycles(axis) for axis in machine.axes)))
    parts = [np.linspace(0.0, end, count + 1)]
    parts += [move.grid() for move in moves.values() if move.duration > 0.0]
    parts += [move.breaks(end) for move in moves.values()]
    return np.unique(np.concatenate(parts))


Position = Callable[[FloatArray], FloatArray]


def _track(axis: Axis, move: Move, grid: FloatArray,
           end: float) -> tuple[Position, FloatArray]:
    """Return an axis's position over time as checked (SI; rotary modulo a turn), its breaks."""
    def raw(times: FloatArray) -> FloatArray:
        return move.commands(times)[0]

    def y(times: FloatArray) -> FloatArray:
        return as_checked(axis, raw(times))
    breaks = move.breaks(end)
    if rotary(axis) and end > 0.0:  # nothing to cross in no time (grid: the one time 0)
        breaks = np.concatenate((breaks, turn_crossings(raw, grid, breaks, period=None)))
    return y, breaks


def check_moves(machine: Machine, moves: Mapping[str, Move],
                master: MasterMotion) -> tuple[MoveCheck, ...]:
    """Check every interference pair of the machine during the moves (see the module).

    moves: every axis's move (plan_moves), all planned with master.
    """
    end = _window(machine, moves, master)
    grid = _grid(machine, moves, master, end)
    return tuple(_check(machine, pair, moves, master, grid, end)
                 for pair in machine.config.interference)


def _check(machine: Machine, pair: InterferencePair, moves: Mapping[str, Move],
           master: MasterMotion, grid: FloatArray, end: float) -> MoveCheck:
    """Check one pair over [0, end]."""
    (y_a, breaks_a), (y_b, breaks_b) = (_track(machine.axis(name), moves[name], grid, end)
                                        for name in (pair.axis_a, pair.axis_b))
    if pair.type == 'clearance':
        def gap(times: FloatArray) -> FloatArray:
            return pair.offset + pair.gain_a * y_a(times) + pair.gain_b * y_b(times)
        if end > 0.0:
            value, time = refine_extremum(gap, grid, gap(grid), 'min',
                                          breaks=np.concatenate((breaks_a, breaks_b)),
                                          period=None)
        else:
            value, time = float(gap(np.zeros(1))[0]), 0.0
        return _result(pair, value, time, value >= pair.min_clearance, master)
    arcs_a = _stretches(y_a, pair.zone_a, grid, breaks_a, end)
    arcs_b = _stretches(y_b, pair.zone_b, grid, breaks_b, end)
    margin, time = time_margin(arcs_a, arcs_b, end)
    value = margin * _margin_speed(machine, master)
    return _result(pair, value, time, value >= pair.min_margin, master)


def _result(pair: InterferencePair, value: float, time: float, ok: bool,
            master: MasterMotion) -> MoveCheck:
    """Return a pair's check at a time, with the master angle there."""
    at = float(np.mod(master.at(time), 2.0 * math.pi))
    return MoveCheck(PairCheck(pair, value, at, bool(ok)), time)


Stretches = tuple[FloatArray, FloatArray]  # starts and ends (s) of the times in a zone


def _stretches(y: Position, level: float, grid: FloatArray, breaks: FloatArray,
               end: float) -> Stretches:
    """Return the stretches of time in [0, end] where y > level."""
    def above(times: FloatArray) -> FloatArray:
        return y(times) - level
    if end <= 0.0:
        now = int(above(np.zeros(1))[0] > 0.0)
        return np.zeros(now), np.zeros(now)
    roots = refine_roots(above, grid, above(grid), breaks=breaks, period=None)
    edges = np.unique(np.concatenate(([0.0], roots[(roots > 0.0) & (roots < end)], [end])))
    inside = above(0.5 * (edges[:-1] + edges[1:])) > 0.0
    rising = np.flatnonzero(inside & ~np.concatenate(([False], inside[:-1])))
    falling = np.flatnonzero(inside & ~np.concatenate((inside[1:], [False])))
    return edges[rising], edges[falling + 1]


def time_margin(a: Stretches, b: Stretches, end: float) -> tuple[float, float]:
    """Return the smallest time (s) from one axis leaving the zone to the other entering it, and
    when the leaving one leaves; an overlap: minus its longest stretch, and when it starts.

    A stretch starting at 0 was not entered in the window, one ending at end not left; +inf when
    no axis leaves before the other enters.
    """
    (start_a, end_a), (start_b, end_b) = a, b
    lower = np.maximum.outer(start_a, start_b)
    overlap = np.minimum.outer(end_a, end_b) - lower
    if overlap.size and overlap.max() > 0.0:
        index = np.unravel_index(np.argmax(overlap), overlap.shape)
        return -float(overlap[index]), float(lower[index])
    best, when = math.inf, 0.0
    for leaves, enters in ((end_a, start_b), (end_b, start_a)):
        left = leaves[leaves < end]
        entered = enters[enters > 0.0]
        margins = np.subtract.outer(entered, left)
        margins = np.where(margins >= 0.0, margins, math.inf)
        if margins.size and margins.min() < best:
            index = np.unravel_index(np.argmin(margins), margins.shape)
            best, when = float(margins[index]), float(left[index[1]])
    return best, when


def sequence_moves(machine: Machine, moves: Mapping[str, Move],
                   master: MasterMotion) -> Union[Sequence, str]:
    """Return the moves together if no pair collides, else the first order of one axis after
    another in which none does; else why not (the pair that collides together, with its figure,
    master angle and time)."""
    together = check_moves(machine, moves, master)
    if all(check.ok for check in together):
        return Sequence(dict(moves), (), together)
    moving = [name for name, move in moves.items() if move.duration > 0.0]
    if 1 < len(moving) <= MOST_ORDERED:
        for order in permutations(moving):
            ordered = _in_order(moves, order)
            if ordered is None:
                continue
            checks = check_moves(machine, ordered, master)
            if all(check.ok for check in checks):
                return Sequence(ordered, order, checks)
    failed = next(check for check in together if not check.ok)
    tried = ' or one after another' if len(moving) > 1 else ''
    return (f'the moves collide together{tried}: '
            f'{failed.line(machine.config.length_unit)}')


def checked_moves(machine: Machine, moves: Mapping[str, Move],
                  master: MasterMotion) -> Union[dict[str, Move], str]:
    """Return the moves to make (sequence_moves: together, else one after another), or why
    none: the check of an engagement's moves on the line shaft (ecam.engagement.CheckMoves)."""
    found = sequence_moves(machine, moves, master)
    return found if isinstance(found, str) else found.moves


def _in_order(moves: Mapping[str, Move], order: tuple[str, ...]) -> Optional[dict[str, Move]]:
    """Return the moves delayed to go one after another in order (None: one cannot wait)."""
    ordered, delay = dict(moves), 0.0
    for name in order:
        move = moves[name]
        if delay and not move.waits:
            return None
        ordered[name] = move.delayed(delay)
        delay += move.duration
    return ordered
