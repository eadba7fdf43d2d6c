"""
Following error: what an axis was commanded for a time, minus where it reports it was then.

CommandHistory keeps the commands a node issued (stamp, then every axis's position and velocity)
for HISTORY_S. The reference at a report's stamp is interpolated between the two commands around
it: the cubic Hermite through both commands' positions and velocities (a master message's
command is exact at its stamp, and between two of them the axis moves as those velocities say;
the linear one would read a curving command short by up to a/8 h^2). A report newer than the
last command takes the last command carried on at its velocity (0 after a hold: stop()); one
older than the first command (or than the history) has no reference and is dropped.

ErrorWatch faults an axis when |error| stays above slave.following_error_limit for
slave.following_error_time (0: at once): a drive that stalls, hits a limit or was never enabled.
"""
from __future__ import annotations

from bisect import bisect_right
from collections import deque
from typing import NamedTuple, Optional, Sequence

#: How long commands are kept for reports that arrive late (s).
HISTORY_S = 2.0


class Reference(NamedTuple):
    """An axis's command at a time: position (m or rad) and velocity (per s)."""

    position: float
    velocity: float


class CommandHistory:
    """The commands a node issued, newest last (see the module docstring)."""

    def __init__(self, keep_ns: int = int(HISTORY_S * 1e9)):
        self.keep_ns = keep_ns
        self._stamps: deque[int] = deque()
        self._commands: deque[tuple[Sequence[float], Sequence[float]]] = deque()

    def add(self, stamp_ns: int, positions: Sequence[float], velocities: Sequence[float]) -> None:
        """Note the commands of every axis issued for stamp_ns (stamps ascending)."""
        if self._stamps and stamp_ns <= self._stamps[-1]:
            return  # a hold stamped by a clock behind the master's: the last command stands
        self._stamps.append(stamp_ns)
        self._commands.append((tuple(positions), tuple(velocities)))
        while self._stamps[0] < stamp_ns - self.keep_ns:
            self._stamps.popleft()
            self._commands.popleft()

    def stop(self) -> None:
        """Make the last command a hold: from its stamp on the axes stand where it put them."""
        if self._commands:
            positions, velocities = self._commands[-1]
            self._commands[-1] = (positions, (0.0,) * len(velocities))

    def reference(self, axis: int, stamp_ns: int) -> Optional[Reference]:
        """Return axis's command at stamp_ns, or None before the first kept command."""
        stamps = self._stamps
        if not stamps or stamp_ns < stamps[0]:
            return None
        index = bisect_right(stamps, stamp_ns) - 1
        positions, velocities = self._commands[index]
        p0, v0 = positions[axis], velocities[axis]
        if index == len(stamps) - 1:  # newer than the last command: carried on
            return Reference(p0 + v0 * (stamp_ns - stamps[index]) * 1e-9, v0)
        positions, velocities = self._commands[index + 1]
        p1, v1 = positions[axis], velocities[axis]
        h = (stamps[index + 1] - stamps[index]) * 1e-9
        u = (stamp_ns - stamps[index]) * 1e-9 / h
        # cubic Hermite basis and its derivative (per u)
        h00, h10 = (1 + 2 * u) * (1 - u) ** 2, u * (1 - u) ** 2
        h01, h11 = u * u * (3 - 2 * u), u * u * (u - 1)
        d00, d10 = 6 * u * u - 6 * u, 3 * u * u - 4 * u + 1
        d01, d11 = -6 * u * u + 6 * u, 3 * u * u - 2 * u
        return Reference(h00 * p0 + h10 * h * v0 + h01 * p1 + h11 * h * v1,
                         (d00 * p0 + d01 * p1) / h + d10 * v0 + d11 * v1)


class ErrorWatch:
    """Fault when |error| stays above limit (0: never) for hold_ns (0: at once)."""

    def __init__(self, limit: float, hold_ns: int):
        self.limit, self.hold_ns = limit, hold_ns
        self._since: Optional[int] = None  # stamp since which |error| is above the limit

    def update(self, stamp_ns: int, error: float) -> bool:
        """Take an error at a stamp; say whether it has been over the limit long enough."""
        if not self.limit or abs(error) <= self.limit:
            self._since = None
            return False
        if self._since is None or stamp_ns < self._since:
            self._since = stamp_ns
        return stamp_ns - self._since >= self.hold_ns

    def reset(self) -> None:
        """Forget an excursion (the fault was cleared)."""
        self._since = None
