"""
What the driven axes report (slave.state_topic): where they are, and how far they lag.

Each report (sensor_msgs/JointState, joints named as the axes) gives the axes it names their
present position, where a first engagement starts. For every report stamped within the commands
the node keeps (cam_ros.core.ecam.following_error), ~/controller_state says the command at the
report's stamp (reference), the report (feedback) and their difference (error), and each axis's
ErrorWatch decides whether its following error has stayed over slave.following_error_limit for
slave.following_error_time: then the machine faults as one (MasterFollower holds every axis).
A report without an axis joint or with a non-finite value is dropped and counted; one stamped
before the first command kept still gives the present positions, but no error, and is counted
as unmatched.
"""
from __future__ import annotations

import math
import threading
from typing import Any, Callable, Sequence

from cam_ros_interfaces.msg import ControllerState
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from cam_ros.core import CamDesign
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.following_error import CommandHistory, ErrorWatch
from cam_ros.core.ecam.master_tracker import BadMaster, NO_JOINT, read_master
from cam_ros.core.ecam.slave_limits import AxisUnit
from cam_ros.node.master_intake import stamp_ns
from cam_ros.node.qos_events import publisher

#: The slave's state: best effort matches the broadcaster whatever its reliability.
SLAVE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
STATE_QOS = QoSProfile(depth=100)
#: Fault(axis name, error, limit (SI), report stamp ns), called with the lock held.
Fault = Callable[[str, float, float, int], None]


def watches(axes: Sequence[tuple[str, CamDesign]]) -> list[ErrorWatch]:
    """Return each axis's ErrorWatch from its slave.following_error_* (SI)."""
    result = []
    for _, design in axes:
        values, unit = design.config.parameters, AxisUnit.of(design.config)
        result.append(ErrorWatch(values['slave.following_error_limit'] / unit.per_si,
                                 round(values['slave.following_error_time'] * 1e9)))
    return result


class SlaveFeedback:
    """Take the axes' reports; publish ~/controller_state; fault on a lasting following error."""

    def __init__(self, node: Node, axes: SlaveAxes, topics: Sequence[str],
                 history: CommandHistory, watch: list[ErrorWatch], lock: threading.Lock,
                 fault: Fault):
        self._node, self._axes, self._history = node, axes, history
        self.watches, self._lock, self._fault = watch, lock, fault
        self.dropped = self.unmatched = 0
        self.errors: dict[int, float] = {}  # each reported axis's latest following error
        self._state_pub = publisher(node, ControllerState, '~/controller_state', STATE_QOS)
        for topic in topics:
            node.create_subscription(JointState, topic, self._on_report, SLAVE_QOS)

    @property
    def publisher(self) -> Any:
        """Return the ~/controller_state publisher, for the recorder."""
        return self._state_pub

    def _on_report(self, message: JointState) -> None:
        found = []
        for index, name in enumerate(self._axes.names):
            if name not in message.name:
                continue
            try:
                position, velocity = read_master(name, message.name, message.position,
                                                 message.velocity, message.effort)
            except BadMaster as bad:
                self._drop(bad.reason)
                return
            found.append((index, position, velocity))
        if not found:
            self._drop(NO_JOINT)
            return
        stamp = stamp_ns(message.header.stamp)
        with self._lock:
            for index, position, _ in found:
                self._axes.followers[index].present = position
            references = [self._history.reference(index, stamp) for index, _, _ in found]
            if any(reference is None for reference in references):
                self.unmatched += 1
                return
            self._publish(message, found, references)  # type: ignore[arg-type]
            for (index, position, _), reference in zip(found, references):
                error = reference.position - position  # type: ignore[union-attr]
                self.errors[index] = error
                watch = self.watches[index]
                if watch.update(stamp, error):
                    watch.reset()
                    self._fault(self._axes.names[index], error, watch.limit, stamp)
                    return

    def over_limit(self, units: Sequence[AxisUnit]) -> str:
        """Say which axes' latest following error is over slave.following_error_limit ('' if
        none): a fault must not be cleared while its cause is there."""
        return '; '.join(
            f'following error of {self._axes.names[index]} {units[index].say(error)} over '
            f'slave.following_error_limit {units[index].say(self.watches[index].limit)}'
            for index, error in sorted(self.errors.items())
            if self.watches[index].limit and abs(error) > self.watches[index].limit)

    def _publish(self, message: JointState, found: list[tuple[int, float, float | None]],
                 references: list[Any]) -> None:
        """Publish the reference, feedback and error of the reported axes."""
        state = ControllerState(joint_names=[self._axes.names[index] for index, _, _ in found])
        state.header = message.header
        state.reference = JointTrajectoryPoint(
            positions=[ref.position for ref in references],
            velocities=[ref.velocity for ref in references])
        state.feedback = JointTrajectoryPoint(positions=[position for _, position, _ in found])
        state.error = JointTrajectoryPoint(positions=[
            ref.position - position for ref, (_, position, _) in zip(references, found)])
        speeds = [velocity for _, _, velocity in found]
        if all(speed is not None and math.isfinite(speed) for speed in speeds):
            state.feedback.velocities = speeds
            state.error.velocities = [ref.velocity - speed
                                      for ref, speed in zip(references, speeds)]
        self._state_pub.publish(state)

    def _drop(self, reason: str) -> None:
        """Count and say a dropped report."""
        with self._lock:
            self.dropped += 1
        self._node.get_logger().warning(
            f'dropped a slave state message: {reason} ({self.dropped} so far)',
            throttle_duration_sec=5.0)
