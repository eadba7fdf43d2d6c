"""Disk-cam geometry: the profile, pressure angle and radius of curvature of a follower motion.

Conventions (frames and follower placement: :mod:`.followers`):

* Pressure angle phi (rad): the angle from the direction of motion of the follower's contact point
  (of the roller centre for rollers) to the common normal (pointing from cam to follower), positive
  in the cam's sense of rotation; so phi > 0 on the rise of a zero-offset translating roller.
  Translating roller: tan phi = (ds/dtheta - sigma e) / (d + s): an offset with sigma e > 0 lowers
  the pressure angle on the rise. Translating flat face: phi = 0.
* Radius of curvature (m): signed, positive where the curve is convex (centre of curvature on the
  cam's side), negative where concave, infinite at an inflection. Roller surface:
  rho = rho_pitch - Rr. Flat face at distance D from the cam centre, its normal at angle phi_n:
  rho = D + d2D/dphi_n^2; translating: rho = Rb + s + d2s/dtheta2.
* Flat faces: the pitch curve is the cam-frame trace of the face's reference point (where the face
  meets the line of travel; oscillating: the foot of the perpendicular from the pivot to the face).
  The contact offset t (m) along the face is measured from that point. Translating: t = ds/dtheta,
  positive on the side where the cam surface moves in the direction of rise (contact at
  x = sigma t). Oscillating: t = C cos psi / (1 - mu ds/dtheta), mu = +1 if the arm turns with the
  cam else -1, positive toward the foot of the perpendicular from the cam centre.
* Mirror rule: a clockwise cam is the mirror image (x -> -x) of the counter-clockwise cam with the
  offset e negated (other followers: the same parameters); pressure angles, radii of curvature and
  contact offsets are unchanged.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..arrays import BLOCK
from ..errors import InvalidParameter
from .followers import check_follower, first_bad, Follower

Array = np.ndarray


def read_only(values: Array) -> Array:
    """Return a read-only float copy of values."""
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class CamGeometry:
    """Cam profile and its kinematic measures at each sampled cam angle (read-only arrays).

    surface_x/surface_y is also the contact point at each angle (cam frame). contact_offset is the
    contact's offset t along a flat face (m), None for rollers.
    """

    follower: Follower
    clockwise: bool
    theta: Array
    pitch_x: Array
    pitch_y: Array
    surface_x: Array
    surface_y: Array
    pressure_angle: Array
    pitch_radius: Array
    surface_radius: Array
    contact_offset: Optional[Array]
    ds: Optional[Array] = None  # the motion's ds/dtheta: its sign tells rise from return

    @property
    def pitch_curvature(self) -> Array:
        """Return the signed curvature 1/pitch_radius (1/m), finite at inflections."""
        return 1.0 / self.pitch_radius


def check_motion(theta: object, s: object, ds: object, d2s: object) -> tuple[Array, ...]:
    """Return the motion as float arrays after checking shapes and finiteness (any order)."""
    arrays: list[Array] = []
    for name, value in (('theta', theta), ('s', s), ('ds', ds), ('d2s', d2s)):
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError) as err:
            raise InvalidParameter(name, value, 'must be an array of numbers') from err
        if array.ndim != 1 or array.size < 1:
            raise InvalidParameter(name, f'array of shape {array.shape}',
                                   'must be 1-D with at least 1 sample')
        bad = first_bad(name, array, ~np.isfinite(array), 'must be finite')
        if bad:
            raise bad
        if arrays and array.shape != arrays[0].shape:
            raise InvalidParameter(name, f'array of shape {array.shape}',
                                   f'must have the shape of theta {arrays[0].shape}')
        arrays.append(array)
    return tuple(arrays)


def _geometry(follower: Follower, theta: Array, s: Array, ds: Array, d2s: Array,
              clockwise: bool) -> CamGeometry:
    """Build the geometry from checked inputs (no validation)."""
    sigma = -1 if clockwise else 1
    raw = follower._geometry(theta, sigma, s, ds, d2s)
    with np.errstate(divide='ignore'):
        pitch_radius = 1.0 / raw.pitch_curvature
    offset = None if raw.contact_offset is None else read_only(raw.contact_offset)
    return CamGeometry(follower, clockwise, read_only(theta), read_only(raw.pitch[0]),
                       read_only(raw.pitch[1]), read_only(raw.surface[0]),
                       read_only(raw.surface[1]),
                       read_only(raw.pressure_angle), read_only(pitch_radius),
                       read_only(raw.surface_radius), offset, read_only(ds))


def cam_geometry(follower: Follower, theta: object, s: object, ds: object, d2s: object, *,
                 clockwise: bool = False) -> CamGeometry:
    """Compute the cam profile for a follower motion sampled at cam angles theta (rad).

    s is the follower position (m; arm angle increment in rad for oscillating followers), ds and
    d2s its first and second derivatives with respect to theta. Raises InvalidParameter when the
    input is malformed or the motion leaves the follower's geometric range.
    """
    check_follower(follower)
    theta_a, s_a, ds_a, d2s_a = check_motion(theta, s, ds, d2s)
    problem = follower._motion_problem(s_a, ds_a)
    if problem:
        raise problem
    return _geometry(follower, theta_a, s_a, ds_a, d2s_a, bool(clockwise))


def contact_measures(follower: Follower, theta: Array, s: Array, ds: Array, d2s: Array, *,
                     clockwise: bool = False) -> tuple[Array, Array]:
    """Return (pressure angle, surface radius of curvature) only, without input checks.

    The per-request path of a validated design: the measures of cam_geometry (in closed form
    for translating followers), none of its checks or cam-frame coordinates, computed in blocks
    of BLOCK samples so that temporaries stay in cache. Inputs: equal-length 1-D float arrays.
    """
    sigma = -1 if clockwise else 1
    angle, radius = np.empty(s.shape), np.empty(s.shape)
    for start in range(0, s.size, BLOCK):
        part = slice(start, start + BLOCK)
        follower._contact(theta[part], sigma, s[part], ds[part], d2s[part],
                          out=(angle[part], radius[part]))
    return angle, radius


def contact_at(follower: Follower, theta: float, s: float, ds: float, d2s: float, *,
               clockwise: bool = False) -> tuple[float, float]:
    """Return contact_measures at one angle, as floats (the path of a one-angle request)."""
    angle, radius = follower._contact(theta, -1 if clockwise else 1, s, ds, d2s)
    return float(angle), float(radius)
