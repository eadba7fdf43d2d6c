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
from cam_ros.recording.engage_replay import engage_topics
from cam_ros.recording.parameters import PARAMETER_EVENTS_TOPIC
from cam_ros.recording.qos import DEFAULT_DEPTH, qos_from_dict
from cam_ros.recording.reader import open_recording, RecordedMessage, Recording
from cam_ros.recording.schema import import_type

#: Seconds each reliable publisher may take, at the end, to have its messages acknowledged.
ACK_TIMEOUT = 1.0
_POLL = 0.01  # seconds between subscriber-count checks


class Player:
    """
    A recording's topics offered on a node, each with its recorded QoS, ready to play.

    `topics` None: default_topics(recording, outputs), the recording node's inputs (with
    `outputs`, its outputs too).
    The publishers exist from construction on, so a caller can make sure a subscriber has matched
    them (e.g. that a best-effort subscriber answered a probe sent through `publishers[topic]`)
    before `play`: DDS tells a writer only that it matched a reader, not that the reader has
    matched it, and a best-effort reader drops what comes before. Close it (or use `with`) to
    destroy the publishers.
    """

    def __init__(self, recording: Union[Recording, str, os.PathLike], node: Node,
                 topics: Optional[Iterable[str]] = None, outputs: bool = False) -> None:
        self.recording = (recording if isinstance(recording, Recording)
                          else open_recording(recording))
        selected = (default_topics(self.recording, outputs) if topics is None
                    else list(topics))
        for index, name in enumerate(selected):
            if name not in self.recording.topics:
                known = sorted(self.recording.topics)
                raise InvalidParameter(f'topics[{index}]', name,
                                       f'must be a recorded topic: {known}')
        self._node = node
        self.publishers = {name: _publisher(node, self.recording, name) for name in selected}

    def wait_for_subscribers(self, timeout: float, stop: Optional[threading.Event] = None) -> bool:
        """Wait up to `timeout` s (or until `stop`) for every topic to have a subscriber."""
        if timeout < 0:
            raise InvalidParameter('wait_for_subscribers', timeout, 'must be non-negative seconds')
        stop = stop or threading.Event()
        deadline = time.monotonic() + timeout
        while not self._subscribed():
            if time.monotonic() >= deadline or stop.wait(_POLL):
                return self._subscribed()
        return True

    def play(self, rate: Optional[float] = 1.0, loop: bool = False,
             on_message: Optional[Callable[[RecordedMessage], None]] = None,
             stop: Optional[threading.Event] = None,
             before_message: Optional[Callable[[int], None]] = None) -> int:
        """
        Publish the recorded wire bytes; return how many were published.

        Messages keep their log-time spacing divided by `rate` (None: as fast as possible);
        `loop` repeats until `stop` is set; `on_message` sees each published message and
        `before_message` the log time (ns) of each before it is published (e.g. a Schedule of
        calls; the time it takes delays the rest, so the recorded spacing is kept). Reliable
        publishers get ACK_TIMEOUT s at the end to have everything acknowledged.
        """
        _check_rate(rate)
        stop = stop or threading.Event()
        count = 0
        while not stop.is_set():
            published = _play_once(self.recording, self.publishers, rate, on_message, stop,
                                   before_message)
            count += published
            if not loop or not published:
                break
        for publisher in self.publishers.values():
            publisher.wait_for_all_acked(Duration(seconds=ACK_TIMEOUT))
        return count

    def close(self) -> None:
        """Destroy the publishers."""
        for publisher in self.publishers.values():
            self._node.destroy_publisher(publisher)
        self.publishers = {}

    def __enter__(self) -> 'Player':
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _subscribed(self) -> bool:
        return all(p.get_subscription_count() > 0 for p in self.publishers.values())


def default_topics(recording: Recording, outputs: bool = False) -> list[str]:
    """
    Return the topics a replay publishes unless told which: the recording node's inputs.

    Every recorded topic but those the recording node published itself (Recording.outputs; a
    recording that does not say has none left out), /parameter_events (--apply-parameters makes
    the changes) and the ~/engage calls (EngageRequest topics, made again as calls, never
    published); with `outputs`, all but the calls.
    """
    calls = set(engage_topics(recording))
    left = set() if outputs else {*(recording.outputs or ()), PARAMETER_EVENTS_TOPIC}
    return [name for name in recording.topics if name not in calls and name not in left]


def replay(recording: Union[Recording, str, os.PathLike], node: Node, *,
           rate: Optional[float] = 1.0, topics: Optional[Iterable[str]] = None,
           outputs: bool = False, loop: bool = False,
           on_message: Optional[Callable[[RecordedMessage], None]] = None,
           stop: Optional[threading.Event] = None, wait_for_subscribers: float = 0.0,
           before_message: Optional[Callable[[int], None]] = None) -> int:
    """
    Publish the recorded wire bytes of `topics` from `node`; return the count.

    `topics` None: default_topics(recording, outputs). A one-shot Player: `wait_for_subscribers`
    seconds are allowed for every topic to have a subscriber before the first message, then
    `Player.play` (see there). Blocks until done: run it in a thread to replay alongside other
    work.
    """
    _check_rate(rate)  # before any publisher exists or any waiting
    with Player(recording, node, topics, outputs) as player:
        player.wait_for_subscribers(wait_for_subscribers, stop)
        return player.play(rate, loop, on_message, stop, before_message)


def _check_rate(rate: Optional[float]) -> None:
    if rate is not None and not rate > 0:
        raise InvalidParameter('rate', rate, 'must be positive (or None: as fast as possible)')


def _publisher(node: Node, recording: Recording, name: str) -> Publisher:
    """Create the publisher of one recorded topic, offering its (first) recorded QoS."""
    info = recording.topics[name]
    qos = qos_from_dict(info.qos[0]) if info.qos else QoSProfile(depth=DEFAULT_DEPTH)
    return node.create_publisher(import_type(info.type), name, qos)


def _play_once(recording: Recording, publishers: dict[str, Publisher], rate: Optional[float],
               on_message: Optional[Callable[[RecordedMessage], None]],
               stop: threading.Event,
               before_message: Optional[Callable[[int], None]] = None) -> int:
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
        if before_message is not None:
            began = time.monotonic()
            before_message(message.log_time_ns)
            if origin is not None:  # the time it took (a service call) delays the rest alike
                origin = (origin[0] + time.monotonic() - began, origin[1])
        publishers[message.topic].publish(bytes(message.message))
        count += 1
        if on_message is not None:
            on_message(message)
    return count
