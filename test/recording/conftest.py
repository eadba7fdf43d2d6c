"""ROS fixtures for the recording tests: a private DDS domain per process, spun in a thread."""

from collections.abc import Callable, Iterator
from dataclasses import dataclass
import os
from pathlib import Path
import sys
import threading
import time

import pytest
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

import cam_ros.recording
from cam_ros.recording import PARAMETER_EVENTS, Recorder, TopicSpec

from .recording_support import (CONFIG_TEXT, joint_state, LATCHED_QOS, LATCHED_TOPIC,
                                PARAMETER_TOPIC, ReferenceRecording, STREAM_COUNT, STREAM_PERIOD,
                                STREAM_QOS, STREAM_TOPIC, trajectory, wait_until)


@dataclass
class RosGraph:
    """A private ROS context spun by a background executor; nodes made here are cleaned up."""

    context: Context
    executor: SingleThreadedExecutor

    def node(self, name: str, **options: object) -> Node:
        """Create a node in this context and add it to the executor."""
        node = rclpy.create_node(name, context=self.context, **options)
        self.executor.add_node(node)
        return node

    def drop(self, node: Node) -> None:
        """Remove a node from the executor and destroy it."""
        self.executor.remove_node(node)
        node.destroy_node()


@pytest.fixture(scope='session')
def ros(ros_domain: int, tmp_path_factory: pytest.TempPathFactory) -> Iterator[RosGraph]:
    """Yield a ROS graph on the domain id reserved for this test process (test/conftest.py)."""
    os.environ.setdefault('ROS_LOG_DIR', str(tmp_path_factory.mktemp('ros_log')))
    context = Context()
    rclpy.init(context=context, domain_id=ros_domain)
    executor = SingleThreadedExecutor(context=context)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield RosGraph(context, executor)
    finally:
        executor.shutdown()
        thread.join()
        rclpy.shutdown(context=context)


@pytest.fixture
def graph_nodes(ros: RosGraph) -> Iterator[Callable[..., Node]]:
    """Yield a node factory whose nodes are destroyed after the test."""
    nodes: list[Node] = []

    def make(name: str, **options: object) -> Node:
        nodes.append(ros.node(name, **options))
        return nodes[-1]

    yield make
    for node in nodes:
        ros.drop(node)


@pytest.fixture(scope='session')
def child_env() -> dict[str, str]:
    """Return the environment for helper subprocesses (cam_ros importable, local discovery)."""
    root = Path(cam_ros.recording.__file__).resolve().parents[2]
    entries = [str(root), *os.environ.get('PYTHONPATH', '').split(os.pathsep)]
    path = os.pathsep.join(dict.fromkeys(filter(None, entries)))
    return {**os.environ, 'PYTHONPATH': path, 'PYTHONUNBUFFERED': '1'}


@pytest.fixture(scope='session')
def python() -> str:
    """Return the interpreter for helper subprocesses (the venv's, which sets up the libraries)."""
    return sys.executable


@pytest.fixture(scope='session')
def reference(ros: RosGraph, tmp_path_factory: pytest.TempPathFactory) -> ReferenceRecording:
    """
    Record a 50 Hz JointState stream, a latched trajectory and a parameter change.

    The trajectory is published before the recorder exists (latched delivery), the stream only
    once the recorder's subscription is matched.
    """
    path = tmp_path_factory.mktemp('reference') / 'reference.mcap'
    source = ros.node('reference_source')
    recorder_node = ros.node('reference_recorder')
    try:
        source.declare_parameter('lift_m', 0.01)
        latched = source.create_publisher(JointTrajectory, LATCHED_TOPIC, LATCHED_QOS)
        stream_pub = source.create_publisher(JointState, STREAM_TOPIC, STREAM_QOS)
        latched.publish(trajectory())
        opened_ns = time.time_ns()
        with Recorder(recorder_node, path,
                      [TopicSpec(STREAM_TOPIC, JointState, STREAM_QOS),
                       TopicSpec(LATCHED_TOPIC, JointTrajectory, LATCHED_QOS), PARAMETER_EVENTS],
                      attachments={'cam_config.yaml': CONFIG_TEXT},
                      description={'law': 'cycloidal'}) as recorder:
            assert wait_until(lambda: stream_pub.get_subscription_count() == 1)
            assert wait_until(lambda: recorder.message_count == 1)  # the latched trajectory
            hashes = {topic: str(source.get_publishers_info_by_topic(topic)[0].topic_type_hash)
                      for topic in (STREAM_TOPIC, LATCHED_TOPIC, PARAMETER_TOPIC)}
            stream = [joint_state(i) for i in range(STREAM_COUNT)]
            for message in stream:
                stream_pub.publish(message)
                time.sleep(STREAM_PERIOD)
            source.set_parameters([Parameter('lift_m', value=0.02)])
            assert wait_until(lambda: recorder.message_count == STREAM_COUNT + 2)
        return ReferenceRecording(path, stream, trajectory(), hashes, opened_ns, 'lift_m')
    finally:
        ros.drop(source)
        ros.drop(recorder_node)
