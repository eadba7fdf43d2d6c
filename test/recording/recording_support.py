"""Constants, reference messages and helpers shared by the recording tests."""

from collections.abc import Callable
from dataclasses import dataclass
import json
from pathlib import Path
import signal
import subprocess
import time
from types import SimpleNamespace
from typing import Any, Optional

from cam_ros_interfaces.msg import EngageRequest
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.recording import RecordedMessage
from cam_ros.recording.parameter_replay import (CHANGED_AFTER_KEY, DESIGN_CHANGES_KEY,
                                                MASTER_TOPIC_KEY)

#: Seconds any graph event (discovery, delivery) may take before a test fails.
GRAPH_TIMEOUT = 5.0
#: Seconds between stream messages of the reference recording (50 Hz).
STREAM_PERIOD = 0.02
STREAM_COUNT = 30
JOINTS = ['cam', 'follower']
STREAM_TOPIC = '/joint_states'
LATCHED_TOPIC = '/cam_trajectory'
PARAMETER_TOPIC = '/parameter_events'
STREAM_QOS = QoSProfile(depth=10)
LATCHED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                         reliability=ReliabilityPolicy.RELIABLE)
CONFIG_TEXT = 'law: cycloidal\nlift_m: 0.02  # metres\n'
CHILD = Path(__file__).with_name('recorder_child.py')
#: Seconds the recording child may take to start, record or finish.
CHILD_TIMEOUT = 15.0
CHUNK_SIZE = 512
#: Messages the child records before it is killed.
KILL_AFTER = 60


def wait_until(predicate: Callable[[], bool], timeout: float = GRAPH_TIMEOUT) -> bool:
    """Poll `predicate` until it holds or `timeout` seconds pass; return its last value."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            return predicate()
        time.sleep(0.005)
    return True


def joint_state(index: int) -> JointState:
    """Return the index-th message of the reference stream (distinct, exactly representable)."""
    message = JointState(name=JOINTS, position=[index * 0.25, -index * 0.5],
                         velocity=[float(index), 2.0], effort=[])
    message.header.frame_id = 'cam_frame'
    message.header.stamp.sec = 1000 + index
    message.header.stamp.nanosec = 125 * index
    return message


def trajectory() -> JointTrajectory:
    """Return the latched reference trajectory."""
    message = JointTrajectory(joint_names=['cam'])
    message.header.frame_id = 'cam_frame'
    message.points = [
        JointTrajectoryPoint(positions=[0.001 * k], velocities=[0.5], accelerations=[-0.25])
        for k in range(4)]
    for k, point in enumerate(message.points):
        point.time_from_start.nanosec = 250_000_000 * k
    return message


@dataclass(frozen=True)
class ReferenceRecording:
    """The file recorded from a known publisher, with what the graph said during recording."""

    path: Path
    stream: list[JointState]
    trajectory: JointTrajectory
    graph_hashes: dict[str, str]
    opened_ns: int
    parameter_name: str


def start_child(python: str, env: dict[str, str], *args: object) -> subprocess.Popen:
    """Start the recording child process (recorder_child.py) with arguments."""
    return subprocess.Popen([python, str(CHILD), *map(str, args)], env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def record_then_kill(python: str, env: dict[str, str], path: Path) -> int:
    """Record in a child process, SIGKILL it after KILL_AFTER messages; return the count."""
    child = start_child(python, env, path, CHUNK_SIZE)
    try:
        written = 0
        for line in child.stdout or ():
            written = json.loads(line)['written']
            if written >= KILL_AFTER:
                break
        child.send_signal(signal.SIGKILL)
        assert child.wait(CHILD_TIMEOUT) == -signal.SIGKILL
    finally:
        child.kill()
        child.communicate(timeout=CHILD_TIMEOUT)
    return written


class StubRecording:
    """Decoded messages by topic, as Recording.topics/messages/outputs give them."""

    def __init__(self, messages: list[RecordedMessage],
                 outputs: Optional[frozenset[str]] = None):
        self._messages = sorted(messages, key=lambda m: m.log_time_ns)
        types = {m.topic: type(m.message) for m in self._messages}
        self.topics = {name: SimpleNamespace(type=_TYPES[kind]) for name, kind in types.items()}
        self.outputs = outputs

    def messages(self, topics):
        return (m for m in self._messages if m.topic in set(topics))


_TYPES = {JointState: 'sensor_msgs/msg/JointState',
          DiagnosticStatus: 'diagnostic_msgs/msg/DiagnosticStatus',
          EngageRequest: 'cam_ros_interfaces/msg/EngageRequest'}


def stamped(message: Any, stamp_ns: int) -> Any:
    """Set a message's header stamp (ns) and return it."""
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(stamp_ns, 10 ** 9)
    return message


def master(log_ns: int, stamp_ns: int, topic: str = '/cam/master') -> RecordedMessage:
    """Return a recorded master JointState stamped stamp_ns, logged at log_ns."""
    message = stamped(JointState(name=['master'], position=[0.0]), stamp_ns)
    return RecordedMessage(topic, message, log_ns, log_ns)


def state(log_ns: int, changes: int, after: Any, node: str = '/cam',
          topic: str = '/cam/master') -> RecordedMessage:
    """Return a recorded e-cam ~/state naming its master topic and design changes."""
    values = {MASTER_TOPIC_KEY: topic, DESIGN_CHANGES_KEY: changes, CHANGED_AFTER_KEY: after,
              'switches': 0}
    message = DiagnosticStatus(hardware_id=node, values=[
        KeyValue(key=key, value=str(value)) for key, value in values.items()])
    return RecordedMessage(f'{node}/state', message, log_ns, log_ns)
