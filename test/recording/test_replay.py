"""Replaying a recording onto a live graph: same messages, same order, scaled timing."""

import threading
import time

import pytest
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

from cam_ros.core.errors import InvalidParameter
from cam_ros.recording import open_recording, replay

from .recording_support import (LATCHED_QOS, LATCHED_TOPIC, STREAM_COUNT, STREAM_TOPIC, wait_until)

#: Deep enough that a burst is never dropped by the receiving queue.
RECEIVER_QOS = QoSProfile(depth=1000)
#: Seconds allowed for replay publishers and the test's subscribers to find each other.
MATCH_TIMEOUT = 2.0
#: Loose timing check: |replayed span - recorded span / rate| within this fraction + slack.
TIMING_FRACTION = 0.3
TIMING_SLACK_S = 0.05


class Receiver:
    """Collect messages of one topic with their monotonic arrival times."""

    def __init__(self, node, msg_type, topic, qos):
        self.messages: list = []
        self.times: list[float] = []
        node.create_subscription(msg_type, topic, self._take, qos)

    def _take(self, message):
        self.times.append(time.monotonic())
        self.messages.append(message)


@pytest.mark.parametrize('rate', [1.0, 2.0])
def test_replay_delivers_the_same_messages_in_order_with_scaled_timing(reference, graph_nodes,
                                                                       rate):
    recording = open_recording(reference.path)
    listener = graph_nodes('replay_listener')
    stream = Receiver(listener, JointState, STREAM_TOPIC, RECEIVER_QOS)
    latched = Receiver(listener, JointTrajectory, LATCHED_TOPIC, LATCHED_QOS)
    count = replay(recording, graph_nodes('replayer'), rate=rate,
                   topics=[STREAM_TOPIC, LATCHED_TOPIC], wait_for_subscribers=MATCH_TIMEOUT)
    assert count == STREAM_COUNT + 1
    assert wait_until(lambda: len(stream.messages) == STREAM_COUNT and latched.messages)
    assert stream.messages == reference.stream
    assert latched.messages == [reference.trajectory]
    recorded = [m.log_time_ns for m in recording.messages([STREAM_TOPIC], raw=True)]
    expected_span = (recorded[-1] - recorded[0]) / 1e9 / rate
    replayed_span = stream.times[-1] - stream.times[0]
    assert abs(replayed_span - expected_span) <= TIMING_FRACTION * expected_span + \
        TIMING_SLACK_S


def test_replay_as_fast_as_possible(reference, graph_nodes):
    seen = []
    recording = open_recording(reference.path)
    start = time.monotonic()
    count = replay(recording, graph_nodes('replayer'), rate=None, on_message=seen.append)
    elapsed = time.monotonic() - start
    # By default all but the parameter events (the recorder's node published none of them).
    inputs = [STREAM_TOPIC, LATCHED_TOPIC]
    assert count == len(seen) == STREAM_COUNT + 1
    assert [tuple(m) for m in seen] == [tuple(m) for m in recording.messages(inputs, raw=True)]
    assert elapsed < recording.duration_ns / 1e9 / 3
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
