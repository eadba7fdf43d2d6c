"""The recorder's intake: its own thread takes the messages in batches, never the executor."""

import time

import rclpy
from rclpy.qos import QoSProfile
from rosbags.highlevel import AnyReader
from sensor_msgs.msg import JointState

from cam_ros.recording import open_recording, Recorder, TopicSpec
from cam_ros.recording.intake import MAX_BATCH, RawIntake, Taken

from .recording_support import joint_state, STREAM_QOS, wait_until


def positions(path) -> list[float]:
    """Return position[0] of every message of a recording, in log-time order."""
    return [m.message.position[0] for m in open_recording(path).messages()]


def test_a_node_no_executor_spins_is_recorded_and_flushed(ros, tmp_path):
    node = rclpy.create_node('unspun_recorder', context=ros.context)
    path = tmp_path / 'unspun.mcap'
    try:
        publisher = node.create_publisher(JointState, '/unspun', STREAM_QOS)
        with Recorder(node, path, [TopicSpec('/unspun', JointState, STREAM_QOS)],
                      chunk_size=1 << 20, flush_period=0.1) as recorder:
            assert wait_until(lambda: publisher.get_subscription_count() == 1)
            publisher.publish(joint_state(7))
            assert wait_until(lambda: recorder.message_count == 1)
            assert wait_until(lambda: open_recording(path).message_count == 1, timeout=1.0)
    finally:
        node.destroy_node()
    assert positions(path) == [joint_state(7).position[0]]


def test_a_burst_of_several_batches_is_recorded_whole_and_in_order(graph_nodes, tmp_path):
    """
    A queue as deep as the offered one holds a burst published faster than it is taken.

    This publisher, in the recorder's process, holds the GIL while it publishes, so the intake
    takes its turns only every few ms (sys.getswitchinterval()).
    """
    node = graph_nodes('burst')
    count = 3 * MAX_BATCH
    qos = QoSProfile(depth=count)
    publisher = node.create_publisher(JointState, '/burst', qos)
    path = tmp_path / 'burst.mcap'
    with Recorder(node, path, [TopicSpec('/burst', JointState, qos)]) as recorder:
        assert wait_until(lambda: publisher.get_subscription_count() == 1)
        for index in range(count):
            publisher.publish(JointState(position=[float(index)]))
        assert wait_until(lambda: recorder.message_count == count)
    assert positions(path) == [float(index) for index in range(count)]
    log_times = [m.log_time_ns for m in open_recording(path).messages()]
    assert log_times == sorted(log_times)


def test_close_writes_what_was_received(graph_nodes, tmp_path):
    """A local publisher's messages are in the queue when publish returns: none may be lost."""
    node = graph_nodes('close_drains')
    publisher = node.create_publisher(JointState, '/drained', STREAM_QOS)
    path = tmp_path / 'drained.mcap'
    recorder = Recorder(node, path, [TopicSpec('/drained', JointState, STREAM_QOS)])
    assert wait_until(lambda: publisher.get_subscription_count() == 1)
    for index in range(50):
        publisher.publish(JointState(position=[float(index)]))
    recorder.close()
    assert recorder.message_count == 50
    assert positions(path) == [float(index) for index in range(50)]


def test_stop_ends_the_thread_and_destroys_the_subscriptions(graph_nodes):
    node = graph_nodes('intake_stop')
    publisher = node.create_publisher(JointState, '/taken', STREAM_QOS)
    batches: list[list[Taken]] = []
    intake = RawIntake(node, [('/taken', JointState, STREAM_QOS)],
                       lambda index, batch: batches.append(batch))
    assert len(intake.subscriptions) == 1
    assert wait_until(lambda: publisher.get_subscription_count() == 1)
    publisher.publish(JointState(position=[1.0]))
    intake.stop()
    intake.stop()
    assert [len(batch) for batch in batches] == [1]
    assert intake.subscriptions == () and list(node.subscriptions) == []
    assert wait_until(lambda: publisher.get_subscription_count() == 0)


def test_a_paced_2_khz_stream_is_recorded_whole_and_opens_in_rosbags(graph_nodes, tmp_path):
    """Issue 28: at 2 kHz for a second the recorder loses nothing; rosbags reads every message."""
    node = graph_nodes('paced')
    publisher = node.create_publisher(JointState, '/paced', STREAM_QOS)
    path, count, period = tmp_path / 'paced.mcap', 2000, 1.0 / 2000
    with Recorder(node, path, [TopicSpec('/paced', JointState, STREAM_QOS)]) as recorder:
        assert wait_until(lambda: publisher.get_subscription_count() == 1)
        start = time.perf_counter()
        for index in range(count):
            time.sleep(max(0.0, start + index * period - time.perf_counter()))
            publisher.publish(JointState(position=[float(index)]))
        assert wait_until(lambda: recorder.message_count == count)
    with AnyReader([path]) as reader:
        read = [reader.deserialize(data, connection.msgtype).position[0]
                for connection, _, data in reader.messages()]
    assert read == [float(index) for index in range(count)]
