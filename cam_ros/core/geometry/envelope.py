"""Vector maths of a follower's envelope: the cam-frame path of a point and a moving face line.

Vectors are arrays of shape (2, n) in the fixed frame's basis until Profile turns them into the
cam frame; sigma = +1 for a counter-clockwise cam, -1 for a clockwise one (see :mod:`.followers`).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

Array = np.ndarray


def perp(v: Array) -> Array:
    """Return J v, v turned by +90 degrees."""
    return np.array((-v[1], v[0]))


def dot(a: Array, b: Array) -> Array:
    """Return the dot product of a and b at each sample."""
    return a[0] * b[0] + a[1] * b[1]


def cross(a: Array, b: Array) -> Array:
    """Return the z component of a x b at each sample."""
    return a[0] * b[1] - a[1] * b[0]


def to_cam_frame(theta: Array, sigma: int, v: Array) -> Array:
    """Return fixed-frame points v at cam angles theta in the cam frame: Rot(-sigma*theta) v."""
    c, s = np.cos(theta), np.sin(sigma * theta)
    return np.array((c * v[0] + s * v[1], -s * v[0] + c * v[1]))


def relative_motion(sigma: int, point: Array, d_point: Array,
                    d2_point: Array) -> tuple[Array, Array]:
    """Return tangent d/dtheta and signed curvature (1/m, convex > 0) of a point's cam-frame path.

    point, d_point, d2_point give the point and its theta-derivatives in the fixed frame; the
    returned tangent is in the fixed frame's basis (rotate it like the point).
    """
    tangent = d_point - sigma * perp(point)
    second = d2_point - 2 * sigma * perp(d_point) - point
    speed = np.hypot(tangent[0], tangent[1])
    return tangent, -sigma * cross(tangent, second) / speed ** 3


def pressure_angle(sigma: int, motion: Array, normal: Array) -> Array:
    """Return the angle (rad) from motion to normal, positive in the cam's sense of rotation."""
    return sigma * np.arctan2(cross(motion, normal), dot(motion, normal))


def flat_envelope(distance: Array, d_distance: Array, d2_distance: Array, normal: Array,
                  rate: Array, d_rate: Array) -> tuple[Array, Array]:
    """Return the contact point and radius of curvature of the envelope of a moving face line.

    The face is the line {p: normal . p = distance} (unit normal pointing away from the cam); in
    the cam frame the normal turns at rate (rad per rad of cam angle) with derivative d_rate.
    """
    contact = distance * normal + (d_distance / rate) * perp(normal)
    radius = distance + (d2_distance * rate - d_distance * d_rate) / rate ** 3
    return contact, radius


def roller_profile(theta: Array, sigma: int, centre: Array, d_centre: Array, d2_centre: Array,
                   motion: Array, roller_radius: float) -> Profile:
    """Return the profile of a roller whose centre and its derivatives are given (fixed frame)."""
    tangent, curvature = relative_motion(sigma, centre, d_centre, d2_centre)
    normal = sigma * perp(tangent) / np.hypot(tangent[0], tangent[1])
    with np.errstate(divide='ignore'):
        pitch_radius = 1.0 / curvature
    return Profile(theta, sigma, centre, centre - roller_radius * normal,
                   pressure_angle(sigma, motion, normal), curvature,
                   pitch_radius - roller_radius, None, normal)


class Profile:
    """Raw fixed-frame results of one follower, turned into the cam frame on demand.

    normal is the unit normal of the cam surface at the contact, from the cam to the follower
    (fixed frame). ds is the motion's ds/dtheta, set by a caller that splits the pressure angle
    into rise and return (see check.py); None until then.
    """

    def __init__(self, theta: Array, sigma: int, pitch: Array, contact: Array, angle: Array,
                 pitch_curvature: Array, surface_radius: Array, offset: Optional[Array],
                 normal: Array):
        self._theta, self._sigma = theta, sigma
        self._pitch, self._contact, self._normal = pitch, contact, normal
        self.pressure_angle = angle
        self.pitch_curvature = pitch_curvature
        self.surface_radius = surface_radius
        self.contact_offset = offset
        self.ds: Optional[Array] = None

    @property
    def pitch(self) -> Array:
        """Return the pitch curve in the cam frame."""
        return to_cam_frame(self._theta, self._sigma, self._pitch)

    @property
    def surface(self) -> Array:
        """Return the cam surface (contact points) in the cam frame."""
        return to_cam_frame(self._theta, self._sigma, self._contact)

    @property
    def surface_normal(self) -> Array:
        """Return the surface's outward unit normal (cam to follower) in the cam frame."""
        return to_cam_frame(self._theta, self._sigma, self._normal)
