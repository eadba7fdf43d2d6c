"""
Hand a running electronic cam over to a new design without a step in its commands.

The new cam takes over only where both cams command the same slave position and the same
dy/dtheta (so the same velocity at any master speed): a common dwell, the cycle start of two
designs that both start at rest there, any stretch the two share. These places are found from the
two designs on a dense grid of cam angles joined with both programs' segment joints (where common
points of two different designs usually are), and each end is refined by bisection to round-off.

The change is due at the first master sample whose path from the previous sample meets such a
place: the command then differs from the old cam's by the second order of the cam angle travelled
past it, a small part of one step's travel. Designs that share no such place (also whenever the
master offset or scaling change) are no handover: the follower moves onto the new cam in time
(follow.py).
"""
from __future__ import annotations

import math

import numpy as np

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from .master import ElectronicCam

#: Largest slave position difference (m, or rad of arm angle) at which two cams agree.
POSITION_TOLERANCE = 1e-9
#: Largest difference of dy/dtheta (per rad of cam) at which two cams agree.
SLOPE_TOLERANCE = 1e-9
#: Grid of cam angles searched for agreement (plus both programs' joints): 0.05 deg.
GRID_SAMPLES = 7200
#: Bisection steps that refine each end of an agreement interval (2 pi / 7200 / 2**52 < 1 ulp).
BISECTIONS = 52


def _agree(old: ElectronicCam, new: ElectronicCam, theta: FloatArray) -> np.ndarray:
    """Return where the two cams agree in position and slope, at cam angles theta."""
    old_y, old_slope = old.slave(theta)
    new_y, new_slope = new.slave(theta)
    return ((np.abs(new_y - old_y) <= POSITION_TOLERANCE)
            & (np.abs(new_slope - old_slope) <= SLOPE_TOLERANCE))


def _refine(old: ElectronicCam, new: ElectronicCam, inside: FloatArray,
            outside: FloatArray) -> FloatArray:
    """Move each agreeing angle toward its disagreeing neighbour as far as agreement holds."""
    for _ in range(BISECTIONS):
        middle = 0.5 * (inside + outside)
        agree = _agree(old, new, middle)
        inside, outside = np.where(agree, middle, inside), np.where(agree, outside, middle)
    return inside


def agreement(old: ElectronicCam, new: ElectronicCam) -> FloatArray:
    """
    Return the cam angle intervals (n x 2, rad) where the two cams agree, sorted.

    Each row is [low, high] with low in [0, 2 pi) and high >= low (beyond 2 pi for an interval
    across the cycle start); a single agreeing point has low == high; [[0, 2 pi]] means
    everywhere. None when the master offsets or scalings differ (the same master position
    would then be at another cam angle).
    """
    nothing = np.empty((0, 2))
    if (old.mapping.master_offset, old.mapping.master_scaling) != (
            new.mapping.master_offset, new.mapping.master_scaling):
        return nothing
    joints = [segment.start for cam in (old, new) for segment in cam.program.segments]
    grid = np.unique(np.mod(np.concatenate(
        [np.linspace(0.0, TWO_PI, GRID_SAMPLES, endpoint=False), joints]), TWO_PI))
    agree = _agree(old, new, grid)
    if agree.all():
        return np.array([[0.0, TWO_PI]])
    if not agree.any():
        return nothing
    first = int(np.argmin(agree))  # a disagreeing angle starts the unrolled revolution
    theta = np.concatenate([grid[first:], grid[:first] + TWO_PI, grid[first:first + 1] + TWO_PI])
    edges = np.diff(np.concatenate([[0], np.roll(agree, -first).astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    low = _refine(old, new, theta[starts], theta[starts - 1])
    high = _refine(old, new, theta[ends], theta[ends + 1])
    turns = np.floor(low / TWO_PI) * TWO_PI
    intervals = np.column_stack([low - turns, high - turns])
    return intervals[np.argsort(intervals[:, 0])]


class Handover:
    """A pending change from one electronic cam to another, and when it is due."""

    def __init__(self, old: ElectronicCam, new: ElectronicCam):
        self.old, self.new = old, new
        self.intervals = agreement(old, new)

    def due(self, master: float, step: float) -> bool:
        """
        Say whether the new cam may take over at a master sample.

        master is the sample's position, step the unwrapped master travel since the previous
        sample (rad): due when the path from master - step to master meets an agreement
        interval (at rest: when the master stands in one).
        """
        end = float(self.old.mapping.turns(master))
        start = end - step / self.old.mapping.master_scaling
        low, high = min(start, end), max(start, end)
        turn = np.ceil((low - self.intervals[:, 1]) / TWO_PI) * TWO_PI
        return bool(np.any(self.intervals[:, 0] + turn <= high))

    def describe(self) -> str:
        """Say where the change can happen, in degrees of cam angle."""
        places = ', '.join(f'{math.degrees(low):.2f}' if high == low else
                           f'{math.degrees(low):.2f}-{math.degrees(high) % 360.0:.2f}'
                           for low, high in self.intervals)
        return f'waits for cam angle {places} deg'
