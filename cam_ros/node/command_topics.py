"""
What the electronic cam sends its drives, for a master sample or a hold.

~/commands (std_msgs/Float64MultiArray: position or velocity of every axis joint, in the axes'
order, what a forward_command_controller with joints: [axes] takes), ~/joint_states (the master
joint and every axis joint) and, with command.trajectory_horizon > 0, ~/joint_trajectory (every
axis joint, for a joint_trajectory_controller). The command goes out first: its latency is the
one that matters.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.core.ecam.axes import Commands, SlaveAxes
from cam_ros.core.ecam.master import MasterConfig
from cam_ros.core.ecam.master_tracker import MasterState
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
        self.commands = publisher(node, Float64MultiArray, '~/commands', COMMAND_QOS)
        self.trajectory = publisher(node, JointTrajectory, '~/joint_trajectory', COMMAND_QOS)

    def sample(self, header: Any, state: MasterState, commands: Commands) -> None:
        """Send every axis's command for a master sample, then its joint states (the master
        message's header) and trajectory."""
        axes = self._axes
        self.commands.publish(Float64MultiArray(data=axes.values(commands)))
        joints = JointState(name=[CAM_JOINT, *axes.names],
                            position=[state.position, *commands.position],
                            velocity=[state.omega, *commands.velocity])
        joints.header = header
        self._joint_pub.publish(joints)
        horizon, count = self.config.trajectory_horizon, self.config.trajectory_points
        if horizon > 0.0:
            times = horizon / count * np.arange(1, count + 1)
            ahead = axes.ahead(state, times)
            self.trajectory.publish(self._trajectory(times, *(
                np.array([getattr(point, field) for point in ahead])
                for field in ('position', 'velocity', 'acceleration'))))

    def hold(self, values: list[float], held: list[float], master: float, stamp: Any) -> None:
        """Send the hold commands (values, one per axis), every axis at rest at its held
        position, the master joint at master (rad), stamped stamp."""
        self.commands.publish(Float64MultiArray(data=values))
        joints = JointState(name=[CAM_JOINT, *self._axes.names], velocity=[0.0] * (len(held) + 1),
                            position=[master, *held])
        joints.header.stamp = stamp
        self._joint_pub.publish(joints)
        horizon = self.config.trajectory_horizon
        if horizon > 0.0:
            rest = np.zeros((len(held), 1))
            self.trajectory.publish(self._trajectory(np.array([horizon]),
                                                     np.array(held)[:, np.newaxis], rest, rest))

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
