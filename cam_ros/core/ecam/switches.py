"""
Cam switches (a programmable limit switch, PLS): outputs on over ranges of the cam angle.

Track i is on for cam angles in [on_i, off_i), through 0 when off_i < on_i. It reads the phase

    phi_i = z + lead_i * omega / m

z is the unwrapped cam angle t passed through a play of width h (the hysteresis): z = t while t
rises, and lags h behind while t falls, z = clip(z, t, t + h); so in the positive direction a
track switches at its edge, in the negative direction h past it, and a master standing at an
edge with noise below h never chatters. lead_i * omega / m (omega the master speed, m
master.scaling) moves every edge earlier by the track's lead time in the direction of travel: the
dead time of the valve or glue gun it drives.

Between two master samples each phase is taken to move straight from its old to its new value;
every edge crossed on the way counts, in the order crossed, so a short track passed between two
samples still gives its on and its off.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ..arrays import FloatArray
from ..motion.program import TWO_PI


@dataclass(frozen=True, eq=False)
class SwitchTable:
    """Track names, on and off cam angles (rad), lead times (s) and the hysteresis (rad)."""

    names: tuple[str, ...]
    on: FloatArray
    off: FloatArray
    lead_time: FloatArray
    hysteresis: float

    def inside(self, phase: FloatArray) -> np.ndarray:
        """Return which tracks are on at their phases (rad, one per track)."""
        return np.mod(phase - self.on, TWO_PI) < np.mod(self.off - self.on, TWO_PI)


def switch_table(parameters: Mapping[str, Any]) -> SwitchTable:
    """Return the switches.* parameters (already checked) in SI."""
    names = tuple(parameters['switches.names'])
    lead = parameters['switches.lead_time'] or (0.0,) * len(names)
    return SwitchTable(names, np.radians(np.array(parameters['switches.on_deg'], dtype=float)),
                       np.radians(np.array(parameters['switches.off_deg'], dtype=float)),
                       np.array(lead, dtype=float),
                       math.radians(parameters['switches.hysteresis_deg']))


def word(states: np.ndarray) -> int:
    """Return track states as a bit word: bit i is track i."""
    return int(np.sum(np.left_shift(1, np.flatnonzero(states), dtype=np.int64)))


class SwitchTracks:
    """The track states of a SwitchTable, updated by master samples."""

    def __init__(self, table: SwitchTable):
        self.table = table
        self.word: int | None = None  # None: nothing said yet
        self._z: float | None = None
        self._phase = np.zeros(len(table.names))

    def reset(self) -> None:
        """Forget the master (lost): the next sample sets the states without edges."""
        self._z = None

    def update(self, turns: float, cam_speed: float) -> list[int]:
        """
        Return the words after each change since the previous sample (the last is now's).

        turns is the unwrapped cam angle (rad), cam_speed the cam's speed omega / m (rad/s).
        """
        table = self.table
        if not table.names:  # no tracks: the word is 0 for good, said once
            changes, self.word = ([] if self.word == 0 else [0]), 0
            return changes
        fresh = self._z is None
        z = turns if self._z is None else min(max(self._z, turns), turns + table.hysteresis)
        self._z = z
        phase = z + table.lead_time * cam_speed
        before, self._phase = self._phase, phase
        now = word(table.inside(phase))
        words = [] if fresh else self._crossed(before, phase)
        if not words or words[-1] != now:  # round-off at an edge: the state now rules
            words.append(now)
        changes = [w for previous, w in zip([self.word, *words], words) if w != previous]
        self.word = now
        return changes

    def _crossed(self, before: FloatArray, after: FloatArray) -> list[int]:
        """Return the word after each edge crossed from phases before to after, in order."""
        edges = np.stack((self.table.on, self.table.off), axis=1)  # (tracks, 2)
        low = np.minimum(before, after)[:, None]
        high = np.maximum(before, after)[:, None]
        turn = np.floor((low - edges) / TWO_PI) + 1.0  # first k: low < edge + k 2 pi <= high
        count = np.maximum(np.floor((high - edges) / TWO_PI) - turn + 1.0, 0.0).astype(int)
        if not count.any():
            return []
        per_edge = count.ravel()
        track = np.repeat(np.repeat(np.arange(edges.shape[0]), 2), per_edge)
        offset = np.arange(per_edge.sum()) - np.repeat(np.cumsum(per_edge) - per_edge, per_edge)
        at = np.repeat((edges + turn * TWO_PI).ravel(), per_edge) + TWO_PI * offset
        fraction = (at - before[track]) / (after[track] - before[track])
        order = np.argsort(fraction, kind='stable')
        toggles = np.left_shift(1, track[order], dtype=np.int64)
        words = np.bitwise_xor.accumulate(np.concatenate(([word(self.table.inside(before))],
                                                          toggles)))[1:]
        last_of_each = np.append(np.diff(fraction[order]) > 0.0, True)  # simultaneous edges
        return [int(w) for w in words[last_of_each]]
