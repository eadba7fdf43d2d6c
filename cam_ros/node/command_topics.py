"""
What the electronic cam sends its drives at each step of its line shaft.

~/commands (std_msgs/Float64MultiArray: position or velocity of every axis joint, in the axes'
order, what a forward_command_controller with joints: [axes] takes), ~/joint_states (the master
joint and every axis joint) and, with command.trajectory_horizon > 0, ~/joint_trajectory (every
axis joint, for a joint_trajectory_controller). The command goes out first: its latency is the
one that matters.
"""
from __future__ import annotations

import numpy as np
from builtin_interfaces.msg import Time
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.core.ecam.axes import Commands, SlaveAxes
from cam_ros.core.ecam.master import MasterConfig
from cam_ros.node.joints import CAM_JOINT
from cam_ros.node.qos_events import publisher

COMMAND_QOS = QoSProfile(depth=10)


class CommandTopics:
    """The command, joint state and trajectory publishers of a node's axes.

    joint_pub: the node's ~/joint_states; config: the master.* and command.* parameters in force
    (a design change sets a new one).
    """

    def __init__(self, node: Node, axes: SlaveAxes, joint_pub: Publisher, config: MasterConfig):
        """Create ~/commands and ~/joint_trajectory."""
        self._axes, self._joint_pub, self.config = axes, joint_pub, config
        self.stamp_ns = 0  # the last stamp sent
        self.commands = publisher(node, Float64MultiArray, '~/commands', COMMAND_QOS)
        self.trajectory = publisher(node, JointTrajectory, '~/joint_trajectory', COMMAND_QOS)

    def sample(self, stamp_ns: int, master: float, speed: float, commands: Commands) -> None:
        """Send every axis's command, then the joint states (the master joint at position
        master, speed speed) and trajectory, stamped stamp_ns or, if that is not after the last
        stamp sent, 1 ns after it: every stamp sent is later than the one before."""
        axes = self._axes
        self.commands.publish(Float64MultiArray(data=axes.values(commands)))
        self.stamp_ns = max(stamp_ns, self.stamp_ns + 1)
        joints = JointState(name=[CAM_JOINT, *axes.names],
                            position=[master, *commands.position],
                            velocity=[speed, *commands.velocity])
        joints.header.stamp = Time(sec=self.stamp_ns // 10 ** 9, nanosec=self.stamp_ns % 10 ** 9)
        self._joint_pub.publish(joints)
        horizon, count = self.config.trajectory_horizon, self.config.trajectory_points
        if horizon > 0.0:
            times = horizon / count * np.arange(1, count + 1)
            ahead = axes.ahead(times)
            self.trajectory.publish(self._trajectory(times, *(
                np.array([getattr(point, field) for point in ahead])
                for field in ('position', 'velocity', 'acceleration'))))

    def _trajectory(self, times: np.ndarray, positions: np.ndarray, velocities: np.ndarray,
                    accelerations: np.ndarray) -> JointTrajectory:
        """Build the axes' trajectory starting now (stamp 0): rows per axis, points at times
        (s)."""
        trajectory = JointTrajectory(joint_names=list(self._axes.names))
        trajectory.points = [
            JointTrajectoryPoint(positions=p, velocities=v, accelerations=a,
                                 time_from_start=Duration(nanoseconds=round(t * 1e9)).to_msg())
            for t, p, v, a in zip(times.tolist(), positions.T.tolist(), velocities.T.tolist(),
                                  accelerations.T.tolist())]
        return trajectory
