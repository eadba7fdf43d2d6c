"""Replaying a recording onto a live graph: same messages, same order, scaled timing."""

import threading
import time

import numpy as np
import pytest
from rclpy.qos import QoSProfile
from scipy.stats import theilslopes
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

from cam_ros.core.errors import InvalidParameter
from cam_ros.recording import open_recording, replay

from .recording_support import (LATCHED_QOS, LATCHED_TOPIC, STREAM_COUNT, STREAM_TOPIC, wait_until)

#: Deep enough that a burst is never dropped by the receiving queue.
RECEIVER_QOS = QoSProfile(depth=1000)
#: Seconds allowed for replay publishers and the test's subscribers to find each other.
MATCH_TIMEOUT = 2.0
#: A message may go out this much before its time (the clock's resolution; never a period).
EARLY_S = 1e-3
#: The replay's pace, the slope of publish times over the recorded log times (Theil-Sen: the
#: median of the pairwise slopes, which a few late wake-ups on a loaded machine do not move),
#: is 1/rate within this fraction.
PACE_TOLERANCE = 0.1
#: Unpaced, at least this share of the messages go out before their recorded time (a paced
#: replay sends none early).
UNPACED_SHARE = 0.5


class Receiver:
    """Collect messages of one topic."""

    def __init__(self, node, msg_type, topic, qos):
        self.messages: list = []
        node.create_subscription(msg_type, topic, self.messages.append, qos)


class Published:
    """The replay's own account: the log time of each message and when it was published."""

    def __init__(self):
        self.messages: list = []
        self.times: list[float] = []

    def __call__(self, message) -> None:
        self.times.append(time.monotonic())
        self.messages.append(message)

    @property
    def log_times_s(self) -> list[float]:
        """Return the recorded log time (s) of each message published."""
        return [message.log_time_ns * 1e-9 for message in self.messages]

    def lateness(self, rate: float) -> np.ndarray:
        """Return how late (s) each message went out, on the schedule of the first at rate."""
        log, sent = np.array(self.log_times_s), np.array(self.times)
        return (sent - sent[0]) - (log - log[0]) / rate


@pytest.mark.parametrize('rate', [1.0, 2.0])
def test_replay_delivers_the_same_messages_in_order_with_scaled_timing(reference, graph_nodes,
                                                                       rate):
    recording = open_recording(reference.path)
    listener = graph_nodes('replay_listener')
    stream = Receiver(listener, JointState, STREAM_TOPIC, RECEIVER_QOS)
    latched = Receiver(listener, JointTrajectory, LATCHED_TOPIC, LATCHED_QOS)
    published = Published()
    count = replay(recording, graph_nodes('replayer'), rate=rate,
                   topics=[STREAM_TOPIC, LATCHED_TOPIC], wait_for_subscribers=MATCH_TIMEOUT,
                   on_message=published)
    assert count == STREAM_COUNT + 1
    assert wait_until(lambda: len(stream.messages) == STREAM_COUNT and latched.messages)
    assert stream.messages == reference.stream
    assert latched.messages == [reference.trajectory]
    # Timing from the recorded stamps (log times) against the replay's own publish times: never
    # early (a loaded machine can only make a message late), and paced at 1/rate.
    assert published.lateness(rate).min() >= -EARLY_S, published.lateness(rate)
    pace = theilslopes(published.times, published.log_times_s).slope
    assert pace == pytest.approx(1.0 / rate, rel=PACE_TOLERANCE), published.lateness(rate)


def test_replay_as_fast_as_possible(reference, graph_nodes):
    seen = Published()
    recording = open_recording(reference.path)
    count = replay(recording, graph_nodes('replayer'), rate=None, on_message=seen)
    # By default all but the parameter events (the recorder's node published none of them).
    inputs = [STREAM_TOPIC, LATCHED_TOPIC]
    assert count == len(seen.messages) == STREAM_COUNT + 1
    assert [tuple(m) for m in seen.messages] == [tuple(m) for m in
                                                 recording.messages(inputs, raw=True)]
    # Unpaced: a paced replay never sends a message early, this one sends nearly all of them
    # before their time (from the recorded stamps; a loaded machine only delays a paced one).
    assert np.mean(seen.lateness(1.0)[1:] < 0) >= UNPACED_SHARE, seen.lateness(1.0)
    everything = []
    assert replay(recording, graph_nodes('replayer_all'), rate=None, outputs=True,
                  on_message=everything.append) == recording.message_count


def test_stop_event_ends_replay_early(reference, graph_nodes):
    stop = threading.Event()
    seen = []

    def on_message(message):
        seen.append(message)
        if len(seen) == 5:
            stop.set()

    count = replay(reference.path, graph_nodes('replayer'), on_message=on_message, stop=stop)
    assert count == len(seen) == 5


def test_loop_repeats_until_stopped(reference, graph_nodes):
    stop = threading.Event()
    seen = []
    total = STREAM_COUNT + 1  # the parameter event is not replayed

    def on_message(message):
        seen.append(message.log_time_ns)
        if len(seen) == total + 3:
            stop.set()

    count = replay(reference.path, graph_nodes('replayer'), rate=None, loop=True,
                   on_message=on_message, stop=stop)
    assert count == total + 3
    assert seen[total:] == seen[:3]


@pytest.mark.parametrize('options, parameter', [
    ({'rate': 0.0}, 'rate'), ({'rate': -1.0}, 'rate'),
    ({'wait_for_subscribers': -1.0}, 'wait_for_subscribers'),
    ({'topics': [STREAM_TOPIC, '/not_recorded']}, 'topics[1]')])
def test_bad_options_name_the_parameter(reference, graph_nodes, options, parameter):
    with pytest.raises(InvalidParameter) as error:
        replay(reference.path, graph_nodes('replayer'), **options)
    assert error.value.parameter == parameter
