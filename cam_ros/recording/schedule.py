"""Make recorded calls (parameter sets, ~/engage) at their places in a replayed stream.

An electronic cam node takes a call between two master messages; the recording says after which
(by its stamp), so the call is made before the next recorded master message is replayed.
"""

from collections.abc import Callable, Sequence
from typing import Generic, Optional, Protocol, TypeVar

from rclpy.time import Time

from cam_ros.recording.reader import Recording


class Due(Protocol):
    """Anything due before the first replayed message of its log time."""

    @property
    def time_ns(self) -> int:
        """Return the log time (ns) the item is due at."""


T = TypeVar('T', bound=Due)


class Schedule(Generic[T]):
    """Call apply(item) for every item due before a message of a given log time (once each)."""

    def __init__(self, items: Sequence[T], apply: Callable[[T], None]) -> None:
        """Take items in due order (time_ns not decreasing)."""
        self._items = list(items)
        self._apply = apply
        self._next = 0

    def __call__(self, log_time_ns: int) -> None:
        """Apply the items due at or before log_time_ns not applied yet."""
        while self._next < len(self._items) and self._items[self._next].time_ns <= log_time_ns:
            self._next += 1
            self._apply(self._items[self._next - 1])

    def finish(self) -> None:
        """Apply the items left (due after the last replayed message)."""
        while self._next < len(self._items):
            self._next += 1
            self._apply(self._items[self._next - 1])


def master_stamps(recording: Recording, topic: str) -> list[tuple[int, int]]:
    """Return (log time, header stamp) in ns of a recorded JointState topic's messages."""
    if topic not in recording.topics:
        return []
    return [(recorded.log_time_ns, Time.from_msg(recorded.message.header.stamp).nanoseconds)
            for recorded in recording.messages([topic])]


def next_master_message(stamps: list[tuple[int, int]], after_ns: Optional[int],
                        default_ns: int) -> int:
    """
    Return the log time of the first master message after the one stamped after_ns.

    after_ns None (no master message followed yet): the first master message. default_ns when
    none follows.
    """
    if after_ns is None:
        return stamps[0][0] if stamps else default_ns
    start = next((index + 1 for index, (_, stamp) in enumerate(stamps) if stamp == after_ns), 0)
    return next((log_ns for log_ns, stamp in stamps[start:] if stamp > after_ns), default_ns)
