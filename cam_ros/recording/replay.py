"""Publish a recording back onto a live graph with its original timing."""

from collections.abc import Callable, Iterable
import os
import threading
import time
from typing import Optional, Union

from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile

from cam_ros.core.errors import InvalidParameter
from cam_ros.recording.qos import DEFAULT_DEPTH, qos_from_dict
from cam_ros.recording.reader import open_recording, RecordedMessage, Recording
from cam_ros.recording.schema import import_type

#: Seconds each reliable publisher may take, at the end, to have its messages acknowledged.
ACK_TIMEOUT = 1.0
_POLL = 0.01  # seconds between subscriber-count checks


def replay(recording: Union[Recording, str, os.PathLike], node: Node, *,
           rate: Optional[float] = 1.0, topics: Optional[Iterable[str]] = None,
           loop: bool = False, on_message: Optional[Callable[[RecordedMessage], None]] = None,
           stop: Optional[threading.Event] = None, wait_for_subscribers: float = 0.0) -> int:
    """
    Publish the recorded wire bytes of `topics` (default all) from `node`; return the count.

    Each topic gets a publisher offering its recorded QoS (so latched topics stay latched while
    replaying). Messages keep their log-time spacing divided by `rate` (None: as fast as
    possible); `loop` repeats until `stop` is set. `wait_for_subscribers` seconds are allowed for
    every topic to have a subscriber before the first message; `on_message` sees each published
    message. Blocks until done: run it in a thread to replay alongside other work.
    """
    if rate is not None and not rate > 0:
        raise InvalidParameter('rate', rate, 'must be positive (or None: as fast as possible)')
    if wait_for_subscribers < 0:
        raise InvalidParameter('wait_for_subscribers', wait_for_subscribers,
                               'must be non-negative seconds')
    if not isinstance(recording, Recording):
        recording = open_recording(recording)
    selected = list(recording.topics) if topics is None else list(topics)
    for index, name in enumerate(selected):
        if name not in recording.topics:
            raise InvalidParameter(f'topics[{index}]', name,
                                   f'must be a recorded topic: {sorted(recording.topics)}')
    stop = stop or threading.Event()
    publishers = {name: _publisher(node, recording, name) for name in selected}
    try:
        deadline = time.monotonic() + wait_for_subscribers
        while (any(p.get_subscription_count() == 0 for p in publishers.values())
               and time.monotonic() < deadline and not stop.wait(_POLL)):
            pass
        count = 0
        while not stop.is_set():
            published = _play_once(recording, publishers, rate, on_message, stop)
            count += published
            if not loop or not published:
                break
        for publisher in publishers.values():
            publisher.wait_for_all_acked(Duration(seconds=ACK_TIMEOUT))
        return count
    finally:
        for publisher in publishers.values():
            node.destroy_publisher(publisher)


def _publisher(node: Node, recording: Recording, name: str) -> Publisher:
    """Create the publisher of one recorded topic, offering its (first) recorded QoS."""
    info = recording.topics[name]
    qos = qos_from_dict(info.qos[0]) if info.qos else QoSProfile(depth=DEFAULT_DEPTH)
    return node.create_publisher(import_type(info.type), name, qos)


def _play_once(recording: Recording, publishers: dict[str, Publisher], rate: Optional[float],
               on_message: Optional[Callable[[RecordedMessage], None]],
               stop: threading.Event) -> int:
    """Publish the selected messages once, paced by log time; return how many were published."""
    count = 0
    origin: Optional[tuple[float, int]] = None  # (monotonic s, log time ns) of the first message
    for message in recording.messages(publishers, raw=True):
        if rate is not None:
            origin = origin or (time.monotonic(), message.log_time_ns)
            delay = origin[0] + (message.log_time_ns - origin[1]) / (rate * 1e9) - time.monotonic()
            if delay > 0 and stop.wait(delay):
                break
        if stop.is_set():
            break
        publishers[message.topic].publish(bytes(message.message))
        count += 1
        if on_message is not None:
            on_message(message)
    return count
