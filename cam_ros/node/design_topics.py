"""
The latched topics of one served design: its profile, pressure angle, markers and forces.

A single cam publishes them on ~/profile, ~/pressure_angle, ~/markers and ~/dynamics; each axis
of a machine on the same names under its own, ~/<axis>/profile and so on. Every number comes
from the design (cam_ros.core); this module only converts it to messages.
"""
from __future__ import annotations

import array
from typing import Any, Sequence

import numpy as np
from builtin_interfaces.msg import Duration
from geometry_msgs.msg import Point
from rclpy.node import Node
from rclpy.publisher import Publisher
from std_msgs.msg import Float64MultiArray, MultiArrayDimension
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from cam_ros.core import CamDesign
from cam_ros.node.joints import joint_coordinates
from cam_ros.node.qos_events import LATCHED, publisher

CAM_FRAME = 'cam'
#: Rows of the latched ~/dynamics array (empty for a design without dynamics).
DYNAMICS_ROWS = ('cam_angle_rad', 'contact_force_N', 'camshaft_torque_Nm', 'contact_stress_Pa')


def as_float64(values: np.ndarray) -> array.array:
    """Convert a float64 array to the message field type without a per-element loop."""
    return array.array('d', np.ascontiguousarray(values, dtype=np.float64).tobytes())


def labelled_rows(labels: Sequence[str], rows: Sequence[np.ndarray]) -> Float64MultiArray:
    """Return rows of equal length as a Float64MultiArray whose first dim names them."""
    count = rows[0].size if rows else 0
    message = Float64MultiArray()
    message.layout.dim = [
        MultiArrayDimension(label=','.join(labels), size=len(rows), stride=len(rows) * count),
        MultiArrayDimension(label='sample', size=count, stride=count)]
    message.data = as_float64(np.concatenate(rows) if rows else np.empty(0))
    return message


def duration(seconds: float) -> Duration:
    """Build a builtin_interfaces/Duration from seconds."""
    nanoseconds = int(round(seconds * 1e9))
    return Duration(sec=nanoseconds // 1_000_000_000, nanosec=nanoseconds % 1_000_000_000)


class DesignTopics:
    """The latched topics of one design: joint is its follower joint, prefix '~/' or '~/axis/'."""

    def __init__(self, node: Node, joint: str, prefix: str):
        self._node, self._joint = node, joint
        self.profile = publisher(node, JointTrajectory, f'{prefix}profile', LATCHED)
        self.pressure = publisher(node, Float64MultiArray, f'{prefix}pressure_angle', LATCHED)
        self.markers = publisher(node, MarkerArray, f'{prefix}markers', LATCHED)
        self.dynamics = publisher(node, Float64MultiArray, f'{prefix}dynamics', LATCHED)

    @property
    def publishers(self) -> tuple[Publisher, ...]:
        """Return the topics' publishers, for the recorder."""
        return self.profile, self.pressure, self.markers, self.dynamics

    def publish(self, design: CamDesign) -> None:
        """Publish the design's profile, pressure angle, forces and markers."""
        profile = design.profile(design.config.sample_count)
        stamp = self._node.get_clock().now().to_msg()
        trajectory = JointTrajectory(joint_names=[self._joint])
        trajectory.header.stamp = stamp
        trajectory.header.frame_id = CAM_FRAME
        omega = design.config.cam_speed
        _, offset, sign = joint_coordinates(design)
        trajectory.points = [
            JointTrajectoryPoint(positions=[offset + sign * s], velocities=[sign * v],
                                 accelerations=[sign * a], time_from_start=duration(theta / omega))
            for theta, s, v, a in zip(profile.angle.tolist(), profile.position.tolist(),
                                      profile.velocity.tolist(), profile.acceleration.tolist())]
        self.profile.publish(trajectory)
        self.pressure.publish(labelled_rows(('cam_angle_rad', 'pressure_angle_rad'),
                                            (profile.angle, profile.pressure_angle)))
        forces = profile.dynamics  # none: an empty array, so a previous design's is not kept
        self.dynamics.publish(labelled_rows(
            DYNAMICS_ROWS, () if forces is None else (
                profile.angle, forces.contact_force, forces.camshaft_torque,
                forces.contact_stress)))
        self.markers.publish(_markers(design, stamp))


def _markers(design: CamDesign, stamp: Any) -> MarkerArray:
    """Return the cam's surface, pitch curve and base circle (a motion-only design: none)."""
    if design.follower is None:  # motion only: no cam to draw, clear an earlier one's
        return MarkerArray(markers=[Marker(action=Marker.DELETEALL)])
    shape = design.geometry(design.config.sample_count)
    circle = design.follower.base_radius * np.stack((np.cos(shape.theta), np.sin(shape.theta)))
    curves = (('cam_surface', shape.surface_x, shape.surface_y, (0.2, 0.4, 0.9)),
              ('pitch_curve', shape.pitch_x, shape.pitch_y, (0.9, 0.5, 0.1)),
              ('base_circle', circle[0], circle[1], (0.5, 0.5, 0.5)))
    markers = MarkerArray()
    for index, (namespace, x, y, rgb) in enumerate(curves):
        marker = Marker(ns=namespace, id=index, type=Marker.LINE_STRIP, action=Marker.ADD)
        marker.header.stamp = stamp
        marker.header.frame_id = CAM_FRAME
        marker.pose.orientation.w = 1.0
        marker.scale.x = 0.0005
        marker.color.r, marker.color.g, marker.color.b = rgb
        marker.color.a = 1.0
        marker.points = [Point(x=px, y=py) for px, py in zip(x.tolist(), y.tolist())]
        marker.points.append(marker.points[0])
        markers.markers.append(marker)
    return markers
