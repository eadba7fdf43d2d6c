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
from ..cam_angles import TWO_PI


@dataclass(frozen=True, eq=False)
class SwitchTable:
    """Track names, on and off cam angles (rad), lead times (s) and the hysteresis (rad)."""

    names: tuple[str, ...]
    on: FloatArray
    off: FloatArray
    lead_time: FloatArray
    hysteresis: float

    def same(self, other: 'SwitchTable') -> bool:
        """Say whether two tables switch the same tracks at the same angles."""
        return (self.names, self.hysteresis) == (other.names, other.hysteresis) and all(
            np.array_equal(a, b) for a, b in ((self.on, other.on), (self.off, other.off),
                                              (self.lead_time, other.lead_time)))


def switch_table(parameters: Mapping[str, Any]) -> SwitchTable:
    """Return the switches.* parameters (already checked) in SI."""
    names = tuple(parameters['switches.names'])
    lead = parameters['switches.lead_time'] or (0.0,) * len(names)
    return SwitchTable(names, np.radians(np.array(parameters['switches.on_deg'], dtype=float)),
                       np.radians(np.array(parameters['switches.off_deg'], dtype=float)),
                       np.array(lead, dtype=float),
                       math.radians(parameters['switches.hysteresis_deg']))


class SwitchTracks:
    """
    The track states of a SwitchTable, updated by master samples.

    Plain floats: a sample moves a few tracks (a UInt32 word holds at most 32), where a NumPy
    call costs more than the arithmetic (three tracks: 60 us a sample on arrays, a few us here).
    """

    def __init__(self, table: SwitchTable):
        self.table = table
        self.word: int | None = None  # None: nothing said yet
        self._z: float | None = None
        self._phase: list[float] = []
        self._edges = list(zip(table.on.tolist(), table.off.tolist()))
        self._lead = table.lead_time.tolist()
        self._width = [(off - on) % TWO_PI for on, off in self._edges]  # of the on range

    def reset(self) -> None:
        """Forget the master (lost): the next sample sets the states without edges."""
        self._z = None

    def update(self, turns: float, cam_speed: float) -> list[int]:
        """
        Return the words after each change since the previous sample (the last is now's).

        turns is the unwrapped cam angle (rad), cam_speed the cam's speed omega / m (rad/s).
        """
        if not self.table.names:  # no tracks: the word is 0 for good, said once
            changes, self.word = ([] if self.word == 0 else [0]), 0
            return changes
        fresh = self._z is None
        z = turns if self._z is None else min(max(self._z, turns),
                                              turns + self.table.hysteresis)
        self._z = z
        phase = [z + lead * cam_speed for lead in self._lead]
        before, self._phase = self._phase, phase
        now = self._word(phase)
        words = [] if fresh else self._crossed(before, phase)
        if not words or words[-1] != now:  # round-off at an edge: the state now rules
            words.append(now)
        changes = [w for previous, w in zip([self.word, *words], words) if w != previous]
        self.word = now
        return changes

    def _word(self, phase: list[float]) -> int:
        """Return the bit word of the tracks on at their phases (rad, one per track)."""
        return sum(1 << track for track, (at, (on, _), width)
                   in enumerate(zip(phase, self._edges, self._width))
                   if (at - on) % TWO_PI < width)

    def _crossed(self, before: list[float], after: list[float]) -> list[int]:
        """Return the word after each edge crossed from phases before to after, in order."""
        crossings = []  # (fraction of the way from before to after, track)
        for track, (start, end, edges) in enumerate(zip(before, after, self._edges)):
            low, high = min(start, end), max(start, end)
            for edge in edges:
                turn = math.floor((low - edge) / TWO_PI) + 1  # first k: low < edge + k 2 pi
                first = edge + turn * TWO_PI
                crossings += [((first + TWO_PI * k - start) / (end - start), track)
                              for k in range(max(math.floor((high - edge) / TWO_PI) - turn + 1,
                                                 0))]
        crossings.sort(key=lambda crossing: crossing[0])  # stable: simultaneous keep track order
        word, words = self._word(before), []
        for number, (fraction, track) in enumerate(crossings):
            word ^= 1 << track
            if number + 1 == len(crossings) or crossings[number + 1][0] > fraction:
                words.append(word)  # after the last of simultaneous edges
        return words
