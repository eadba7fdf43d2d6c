"""Collisions of a machine's axes over the whole machine cycle, pair by pair.

y_a(theta) is what the node commands for axis a at machine angle theta (its cam through its own
master offset and scaling and its slave offset and scaling; Machine.positions). A rotary slave's
y (length_unit deg: a knife or feed roll that advances a turn per cycle) is taken modulo one
turn, in [0, 2 pi), for both checks: its geometry repeats every turn.

- clearance: the gap g(theta) = offset + gain_a y_a(theta) + gain_b y_b(theta) must stay
  >= min_clearance. Reported: its smallest value (m), located on a dense scan and refined to the
  true minimum by refine_extremum, with every segment joint of both axes (and every turn of a
  rotary one) as a break, so one-sided limits at a jump count.
- zones: axis a is in the shared zone where y_a > zone_a, b where y_b > zone_b; never both at
  once, and the machine angle from one leaving to the other entering (both orders, cyclic) must
  stay >= min_margin. Reported: the smallest such margin (rad); negative: minus the longest arc
  during which both are in the zone; -inf when one axis never leaves its zone and the other
  enters; +inf when one never enters. Crossings are refined by refine_roots.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import numpy.typing as npt

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ..extremes import CHECK_SAMPLES, refine_extremum, refine_roots
from .config import InterferencePair
from .machine import Axis, Machine


@dataclass(frozen=True)
class PairCheck:
    """One pair's verdict: value (clearance: smallest gap, m; zones: smallest margin, rad).

    at: the machine angle (rad, in [0, 2 pi)) where it occurs: of the smallest gap, of the axis
    leaving before the smallest margin, or where the longest overlap starts.
    """

    pair: InterferencePair
    value: float
    at: float
    ok: bool


Position = Callable[[FloatArray], FloatArray]


def cycles(axis: Axis) -> int:
    """Return how many times an axis repeats per machine cycle (1 / master.scaling)."""
    return round(1.0 / axis.cam.mapping.master_scaling)


def rotary(axis: Axis) -> bool:
    """Say whether an axis is a rotary slave (length_unit deg), checked modulo a turn."""
    return axis.design.config.length_unit == 'deg'


def as_checked(axis: Axis, y: npt.ArrayLike) -> FloatArray:
    """Return an axis's positions (SI) as the checks take them: a rotary slave's modulo a turn."""
    values = np.asarray(y, dtype=float)
    return np.mod(values, TWO_PI) if rotary(axis) else values


def _position(axis: Axis) -> Position:
    """Return y(theta) of an axis at machine angles (SI; a rotary slave's modulo a turn)."""
    def y(theta: FloatArray) -> FloatArray:
        return as_checked(axis, axis.cam.derivatives(theta).y)
    return y


def turn_crossings(y: Callable[[FloatArray], npt.ArrayLike], grid: FloatArray,
                   breaks: FloatArray,
                   period: float | None = TWO_PI) -> FloatArray:
    """Return where positions y(x) (SI, rad) pass a whole turn: where y modulo a turn jumps.

    grid: a dense sampling of x; breaks: where y or a derivative jumps; period as refine_roots.
    """
    def half_sine(x: FloatArray) -> FloatArray:
        return np.sin(0.5 * np.asarray(y(x), dtype=float))
    return refine_roots(half_sine, grid, half_sine(grid), breaks=breaks, period=period)


def _breaks(axis: Axis, theta: FloatArray) -> FloatArray:
    """Return the machine angles where an axis's y or a derivative may jump.

    Its segment joints, the machine cycle's start (an advancing program's wrap) and, for a
    rotary slave, every whole turn of y (where y modulo a turn jumps).
    """
    joints = np.concatenate((axis.cam.breaks(0.0, TWO_PI), [0.0]))
    if not rotary(axis):
        return joints
    turns = turn_crossings(lambda angles: axis.cam.derivatives(angles).y, theta, joints)
    return np.concatenate((joints, turns))


def _grid(*axes: Axis) -> FloatArray:
    """Return CHECK_SAMPLES machine angles per cycle of the fastest-repeating axis."""
    count = CHECK_SAMPLES * max(cycles(axis) for axis in axes)
    return np.linspace(0.0, TWO_PI, count, endpoint=False)


def check_interference(machine: Machine) -> tuple[PairCheck, ...]:
    """Check every interference pair of a machine over one machine cycle."""
    return tuple(_check(machine, pair) for pair in machine.config.interference)


def _check(machine: Machine, pair: InterferencePair) -> PairCheck:
    """Check one pair."""
    axis_a, axis_b = machine.axis(pair.axis_a), machine.axis(pair.axis_b)
    theta = _grid(axis_a, axis_b)
    y_a, y_b = _position(axis_a), _position(axis_b)
    breaks_a, breaks_b = _breaks(axis_a, theta), _breaks(axis_b, theta)
    if pair.type == 'clearance':
        def gap(angles: FloatArray) -> FloatArray:
            return pair.offset + pair.gain_a * y_a(angles) + pair.gain_b * y_b(angles)
        value, at = refine_extremum(gap, theta, gap(theta), 'min',
                                    breaks=np.concatenate((breaks_a, breaks_b)))
        return PairCheck(pair, value, at, value >= pair.min_clearance)
    value, at = zone_margin(_zone(y_a, pair.zone_a, theta, breaks_a),
                            _zone(y_b, pair.zone_b, theta, breaks_b))
    return PairCheck(pair, value, at, value >= pair.min_margin)


Arcs = tuple[FloatArray, FloatArray]  # starts in [0, 2 pi) and lengths (0, 2 pi] of arcs


def _zone(y: Position, level: float, theta: FloatArray, breaks: FloatArray) -> Arcs:
    """Return the arcs of machine angle where y > level (a full turn: start 0, length 2 pi)."""
    def above(angles: FloatArray) -> FloatArray:
        return y(angles) - level
    roots = refine_roots(above, theta, above(theta), breaks=breaks)
    if roots.size == 0:
        always = int(above(np.zeros(1))[0] > 0.0)
        return np.zeros(always), np.full(always, TWO_PI)
    following = np.concatenate((roots[1:], roots[:1] + TWO_PI))
    inside = above(0.5 * (roots + following)) > 0.0  # each arc between two crossings
    if inside.all():  # y touches the level without going below it
        return np.zeros(1), np.full(1, TWO_PI)
    enter = np.flatnonzero(inside & ~np.roll(inside, 1))
    leave = np.flatnonzero(~inside & np.roll(inside, 1))
    ends = leave[np.searchsorted(leave, enter) % leave.size]  # the first leave after each entry
    return roots[enter], np.mod(roots[ends] - roots[enter], TWO_PI)


def zone_margin(arcs_a: Arcs, arcs_b: Arcs) -> tuple[float, float]:
    """Return the smallest margin (rad) between two axes' zone arcs and where it starts.

    See the module docstring for the signs; at is the angle where the leaving axis leaves, or
    where the longest overlap starts.
    """
    (start_a, length_a), (start_b, length_b) = arcs_a, arcs_b
    if start_a.size == 0 or start_b.size == 0:
        return math.inf, 0.0
    full = [starts for starts, lengths in (arcs_a, arcs_b) if lengths[0] == TWO_PI]
    if full:
        other = start_b if full[0] is start_a else start_a
        return -math.inf, float(other[0])
    sa, la = start_a[:, np.newaxis], length_a[:, np.newaxis]
    sb, lb = start_b[np.newaxis, :], length_b[np.newaxis, :]
    shift = np.mod(sb - sa, TWO_PI)  # b's start after a's
    head = np.clip(np.minimum(la, shift + lb) - shift, 0.0, None)  # b over a, from b's start
    tail = np.clip(np.minimum(la, shift + lb - TWO_PI), 0.0, None)  # b over a, from a's start
    overlap = np.maximum(head, tail)
    if overlap.max() > 0.0:
        index = np.unravel_index(np.argmax(overlap), overlap.shape)
        begins = np.where(head >= tail, sa + shift, sa)
        return -float(overlap[index]), float(np.mod(begins[index], TWO_PI))
    gaps = np.stack((np.mod(sb - (sa + la), TWO_PI), np.mod(sa - (sb + lb), TWO_PI)))
    leaves = np.stack(np.broadcast_arrays(sa + la, sb + lb))
    index = np.unravel_index(np.argmin(gaps), gaps.shape)
    return float(gaps[index]), float(np.mod(leaves[index], TWO_PI))
