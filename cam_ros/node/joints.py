"""The joints a robot model animates from ~/joint_states and ~/profile (REP 103).

`cam`: a revolute joint about +z at the cam centre, parent the fixed frame, child the `cam` frame
of ~/markers. Its position is the cam's rotation about +z, sigma * theta (sigma = -1 for a
clockwise cam, whose joint therefore falls), so a URDF joint with axis 0 0 1 turns the markers
the way the cam turns; the design's cam angle (what ~/evaluate takes) is theta = sigma * q.

`follower`: a translating follower's travel s along +y (prismatic, axis 0 1 0, through x = e);
an oscillating follower's absolute arm angle about +z at the pivot (0, C), measured from the
direction pivot -> cam centre (-y): lam * (psi0 + s), lam = +1 when the arm turns
counter-clockwise while rising (lam = sigma if arm_turns_with_cam, else -sigma).
"""
from __future__ import annotations

from typing import NamedTuple

from cam_ros.core import CamDesign

#: The joint names of ~/joint_states (in this order); ~/commands and ~/joint_trajectory drive the
#: follower joint only.
CAM_JOINT = 'cam'
FOLLOWER_JOINT = 'follower'
JOINT_NAMES = (CAM_JOINT, FOLLOWER_JOINT)


class JointCoordinates(NamedTuple):
    """Map design values to joints: cam q = cam_sign * theta, follower = offset + sign * s."""

    cam_sign: float
    follower_offset: float
    follower_sign: float


def joint_coordinates(design: CamDesign) -> JointCoordinates:
    """Return how the design's cam angle and follower motion map to the published joints."""
    sigma = -1.0 if design.clockwise else 1.0
    follower = design.config.follower
    if not design.config.oscillating:
        return JointCoordinates(sigma, 0.0, 1.0)
    lam = sigma if follower.arm_turns_with_cam else -sigma
    psi0 = design.follower.initial_arm_angle  # type: ignore[union-attr]
    return JointCoordinates(sigma, lam * psi0, lam)
