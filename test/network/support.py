"""What the network tests share (the reliability tests' helpers, and recorded stamps)."""
from __future__ import annotations

from typing import Any

from reliability.support import design_with, percentiles, wire_stamp_ns

__all__ = ['design_with', 'percentiles', 'recorded_stamps']


def recorded_stamps(recording: Any, topic: str) -> list[int]:
    """Return the header stamps (ns) of a recorded stamped topic, in recorded order."""
    return [wire_stamp_ns(message.message) for message in recording.messages([topic], raw=True)]
