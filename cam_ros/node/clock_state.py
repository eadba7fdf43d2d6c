"""cam_node's state when the clock drives the master (master.source clock): ~/joint_states and
~/state_extras at state_rate_hz, while the node is active.

The master turns at the speed of cam_speed from the moment configure made the node; every
number comes from the served machine's designs (cam_ros.core).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
from geometry_msgs.msg import Vector3Stamped
from rclpy.node import Node
from rclpy.publisher import Publisher
from sensor_msgs.msg import JointState

from cam_ros.core.machine import Machine
from cam_ros.node.design_topics import CAM_FRAME
from cam_ros.node.joints import CAM_JOINT, joint_coordinates


class ClockState:
    """Publish every axis's state at the machine angle the clock says, at state_rate_hz.

    machine() returns the machine served now; single: a single cam (joint follower), which
    also publishes on extras_pub (~/state_extras). The timer runs only between start() and
    stop().
    """

    def __init__(self, node: Node, machine: Callable[[], Machine], single: bool,
                 joint_pub: Publisher, extras_pub: Publisher):
        """Take the node's ~/joint_states and ~/state_extras; make the (stopped) timer."""
        self._node, self._machine, self._single = node, machine, single
        self._joint_pub, self._extras_pub = joint_pub, extras_pub
        self._start_ns = node.get_clock().now().nanoseconds
        self._timer = node.create_timer(self._period(), self.publish, autostart=False)

    def _period(self) -> float:
        return 1.0 / self._machine().axes[0].design.config.state_rate_hz

    def start(self) -> None:
        """Publish at state_rate_hz (the node is active)."""
        self._timer.reset()

    def stop(self) -> None:
        """Stop publishing (the node is inactive)."""
        self._timer.cancel()

    def follow_rate(self) -> None:
        """Take the served machine's state_rate_hz (after a parameter update)."""
        self._timer.timer_period_ns = int(self._period() * 1e9)

    def publish(self) -> None:
        """Publish every axis's state at the machine angle the clock says now.

        Each axis's cam angle follows the master through its master offset and scaling (a
        single cam's, with neither, turns at cam_speed from 0).
        """
        machine = self._machine()
        design = machine.axes[0].design
        now = self._node.get_clock().now()
        master = machine.axes[0].cam.mapping
        speed = design.config.cam_speed * master.master_scaling  # master speed
        machine_angle = master.master_offset + speed * (now.nanoseconds - self._start_ns) * 1e-9
        positions, velocities, states = [], [], []
        for axis in machine.axes:
            turned = float(axis.cam.mapping.turns(machine_angle))
            state = axis.design.evaluate(np.array([turned]))  # an advancing one counts turns
            _, offset, sign = joint_coordinates(axis.design)
            positions.append(offset + sign * float(state.position[0]))
            velocities.append(sign * float(state.velocity[0]))
            states.append(state)
        sigma = joint_coordinates(design)[0] if self._single else 1.0
        cam = math.fmod(float(master.turns(machine_angle)) if self._single else machine_angle,
                        2 * math.pi)
        joints = JointState(name=[CAM_JOINT, *machine.config.names],
                            position=[sigma * cam, *positions],
                            velocity=[sigma * (design.config.cam_speed if self._single
                                               else speed), *velocities])
        joints.header.stamp = now.to_msg()
        joints.header.frame_id = CAM_FRAME
        dynamics = states[0].dynamics
        if self._single and dynamics is not None:  # camshaft torque about +z; contact force
            torque = float(dynamics.camshaft_torque[0])
            joints.effort = [-torque if design.clockwise else torque,
                             float(dynamics.contact_force[0])]
        self._joint_pub.publish(joints)
        if self._single:  # one axis's acceleration, jerk and pressure angle
            extras = Vector3Stamped()
            extras.header = joints.header
            extras.vector.x = float(states[0].acceleration[0])
            extras.vector.y = float(states[0].jerk[0])
            extras.vector.z = float(states[0].pressure_angle[0])
            self._extras_pub.publish(extras)
