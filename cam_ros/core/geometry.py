"""Disk-cam geometry for four followers: profiles, pressure angle and radius of curvature.

Conventions (one set for every follower):

* Frames. The cam centre is the origin; the follower sits on the +y side. The fixed frame does not
  turn; the cam frame turns with the cam and equals the fixed frame at cam angle theta = 0. A point
  fixed to the cam is at Rot(sigma*theta) p_cam in the fixed frame, sigma = +1 for a
  counter-clockwise cam, -1 for a clockwise one (seen from +z). Pitch curve, cam surface and
  contact points are returned in the cam frame (m).
* Translating followers move along +y; s (m) grows away from the cam. A roller travels on the line
  x = e (offset e, positive on the +x side) with its centre at (e, d + s), d = sqrt(Rp^2 - e^2),
  prime radius Rp = Rb + Rr. A flat face is the line y = Rb + s, perpendicular to the travel.
* Oscillating followers pivot at (0, C), C = pivot_distance. The arm angle psi is measured at the
  pivot from the direction pivot -> cam centre (-y) to the arm; psi = psi0 + s with s in rad, so a
  rise (s growing) turns the arm away from the cam. Arm unit vector u = (lam sin psi, -cos psi):
  the arm turns counter-clockwise while rising if lam = +1; lam = sigma if arm_turns_with_cam
  else -sigma. Roller: centre (0, C) + L u, cos psi0 = (C^2 + L^2 - Rp^2) / (2 C L). Flat face: the
  line parallel to the arm at distance f = face_offset from the pivot (f > 0: on the cam's side of
  the pivot), sin psi0 = (Rb + f) / C with 0 < psi0 < pi/2.
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

import math
from dataclasses import dataclass
from typing import Callable, Optional, Union

import numpy as np

from .errors import InvalidParameter

Array = np.ndarray


def _frozen(values: Array) -> Array:
    """Return a read-only float copy of values."""
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


def _real(name: str, value: object, ok: Callable[[float], bool], rule: str) -> float:
    """Return value as a float after checking it is a finite real number for which ok holds."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise InvalidParameter(name, value, f'must be a real number {rule}')
    number = float(value)
    if not (math.isfinite(number) and ok(number)):
        raise InvalidParameter(name, value, f'must be {rule}')
    return number


def _set_lengths(follower: object, *names: str, signed: tuple[str, ...] = ()) -> None:
    """Check and store (as floats) the length fields of a frozen follower."""
    for name in names:
        if name in signed:
            value = _real(name, getattr(follower, name), lambda x: True, 'finite (m)')
        else:
            value = _real(name, getattr(follower, name), lambda x: x > 0.0, '> 0 (m)')
        object.__setattr__(follower, name, value)


def _set_flag(follower: object, name: str) -> None:
    """Check a boolean field of a frozen follower."""
    value = getattr(follower, name)
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidParameter(name, value, 'must be a bool')
    object.__setattr__(follower, name, bool(value))


def _first_bad(name: str, values: Array, bad: Array, rule: str) -> Optional[InvalidParameter]:
    """Return an InvalidParameter naming the first sample where bad holds, else None."""
    if not np.any(bad):
        return None
    index = int(np.argmax(bad))
    return InvalidParameter(f'{name}[{index}]', float(values[index]), rule)


# ---------------------------------------------------------------- followers

@dataclass(frozen=True)
class TranslatingRoller:
    """Roller follower translating along +y at offset x = offset (m)."""

    base_radius: float
    roller_radius: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        """Check the lengths and that the line of travel meets the prime circle."""
        _set_lengths(self, 'base_radius', 'roller_radius', 'offset', signed=('offset',))
        if abs(self.offset) >= self.prime_radius:
            raise InvalidParameter('offset', self.offset, 'needs |offset| < base_radius + '
                                   f'roller_radius = {self.prime_radius:g} m')

    @property
    def prime_radius(self) -> float:
        """Return the prime circle radius Rb + Rr (m)."""
        return self.base_radius + self.roller_radius

    def _base_radius_bounds(self) -> tuple[float, float]:
        return max(0.0, abs(self.offset) - self.roller_radius), math.inf

    @property
    def prime_height(self) -> float:
        """Return d = sqrt(Rp^2 - e^2) (m), the roller centre's height on the prime circle."""
        return math.sqrt((self.prime_radius - self.offset) * (self.prime_radius + self.offset))

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        return _first_bad('s', s, self.prime_height + s <= 0.0, 'roller centre must stay above '
                          f'the cam centre (s > {-self.prime_height:g} m)')

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> _Profile:
        zero, one = np.zeros_like(s), np.ones_like(s)
        centre = np.array((self.offset + zero, self.prime_height + s))
        return _roller_profile(theta, sigma, centre, np.array((zero, ds)),
                               np.array((zero, d2s)), np.array((zero, one)), self.roller_radius)


@dataclass(frozen=True)
class TranslatingFlat:
    """Flat-faced follower translating along +y, face perpendicular to the travel."""

    base_radius: float

    def __post_init__(self) -> None:
        """Check the base radius."""
        _set_lengths(self, 'base_radius')

    def _base_radius_bounds(self) -> tuple[float, float]:
        return 0.0, math.inf

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        return _first_bad('s', s, self.base_radius + s <= 0.0,
                          f'face must stay above the cam centre (s > {-self.base_radius:g} m)')

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> _Profile:
        zero, one = np.zeros_like(s), np.ones_like(s)
        distance = self.base_radius + s
        contact, radius = _flat_envelope(distance, ds, d2s, np.array((zero, one)),
                                         -sigma + zero, zero)
        trace = np.array((zero, distance))
        _, trace_curvature = _relative_motion(sigma, trace, np.array((zero, ds)),
                                              np.array((zero, d2s)))
        return _Profile(theta, sigma, trace, contact, zero, trace_curvature, radius, ds)


def _arm_vectors(sigma: int, with_cam: bool, psi: Array) -> tuple[int, Array, Array]:
    """Return lambda, the arm unit vector u and w = du/dpsi (fixed frame) of an oscillating arm."""
    lam = sigma if with_cam else -sigma
    u = np.array((lam * np.sin(psi), -np.cos(psi)))
    w = np.array((lam * np.cos(psi), np.sin(psi)))
    return lam, u, w


def _arm_angle_problem(psi0: float, s: Array) -> Optional[InvalidParameter]:
    """Return an error if the arm angle psi0 + s leaves (0, pi)."""
    psi = psi0 + s
    return _first_bad('s', s, (psi <= 0.0) | (psi >= math.pi),
                      f'arm angle psi0 + s must stay in (0, pi) rad; psi0 = {psi0:g} rad')


@dataclass(frozen=True)
class OscillatingRoller:
    """Roller on an arm of length arm_length (m) pivoting at (0, pivot_distance)."""

    base_radius: float
    roller_radius: float
    pivot_distance: float
    arm_length: float
    arm_turns_with_cam: bool

    def __post_init__(self) -> None:
        """Check the lengths and that the roller can reach the prime circle."""
        _set_lengths(self, 'base_radius', 'roller_radius', 'pivot_distance', 'arm_length')
        _set_flag(self, 'arm_turns_with_cam')
        low = abs(self.pivot_distance - self.arm_length)
        high = self.pivot_distance + self.arm_length
        if not low < self.prime_radius < high:
            raise InvalidParameter(
                'base_radius', self.base_radius,
                f'the prime radius base_radius + roller_radius = {self.prime_radius:g} m must lie '
                f'in (|pivot_distance - arm_length|, pivot_distance + arm_length) = '
                f'({low:g}, {high:g}) m so that the roller reaches the cam')

    @property
    def prime_radius(self) -> float:
        """Return the prime circle radius Rb + Rr (m)."""
        return self.base_radius + self.roller_radius

    @property
    def initial_arm_angle(self) -> float:
        """Return psi0 (rad), the arm angle with the roller on the prime circle."""
        c, arm = self.pivot_distance, self.arm_length
        return math.acos((c * c + arm * arm - self.prime_radius ** 2) / (2.0 * c * arm))

    def _base_radius_bounds(self) -> tuple[float, float]:
        low = abs(self.pivot_distance - self.arm_length) - self.roller_radius
        return max(0.0, low), self.pivot_distance + self.arm_length - self.roller_radius

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        return _arm_angle_problem(self.initial_arm_angle, s)

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> _Profile:
        _, u, w = _arm_vectors(sigma, self.arm_turns_with_cam, self.initial_arm_angle + s)
        arm = self.arm_length
        centre = np.array((arm * u[0], self.pivot_distance + arm * u[1]))
        return _roller_profile(theta, sigma, centre, arm * ds * w, arm * (d2s * w - ds ** 2 * u),
                               w, self.roller_radius)


@dataclass(frozen=True)
class OscillatingFlat:
    """Flat-faced arm pivoting at (0, pivot_distance) (m).

    The face is parallel to the arm at face_offset (m) from the pivot, > 0 on the cam's side.
    """

    base_radius: float
    pivot_distance: float
    face_offset: float
    arm_turns_with_cam: bool

    def __post_init__(self) -> None:
        """Check the lengths and that the face can touch the base circle."""
        _set_lengths(self, 'base_radius', 'pivot_distance', 'face_offset',
                     signed=('face_offset',))
        _set_flag(self, 'arm_turns_with_cam')
        reach = self.base_radius + self.face_offset
        if not 0.0 < reach < self.pivot_distance:
            raise InvalidParameter(
                'face_offset', self.face_offset,
                f'base_radius + face_offset = {reach:g} m must lie in (0, pivot_distance = '
                f'{self.pivot_distance:g} m) so that the face touches the base circle')

    @property
    def initial_arm_angle(self) -> float:
        """Return psi0 (rad), the arm angle with the face tangent to the base circle."""
        return math.asin((self.base_radius + self.face_offset) / self.pivot_distance)

    def _base_radius_bounds(self) -> tuple[float, float]:
        return max(0.0, -self.face_offset), self.pivot_distance - self.face_offset

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        psi = self.initial_arm_angle + s
        mu = 1.0 if self.arm_turns_with_cam else -1.0
        return (_arm_angle_problem(self.initial_arm_angle, s)
                or _first_bad('s', s, self.pivot_distance * np.sin(psi) <= self.face_offset,
                              'the face must stay clear of the cam centre')
                or _first_bad('ds', ds, 1.0 - mu * ds <= 0.0,
                              'the arm must turn slower than the cam in the cam\'s sense '
                              '(1 - mu*ds/dtheta > 0)'))

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> _Profile:
        c, f = self.pivot_distance, self.face_offset
        psi = self.initial_arm_angle + s
        lam, u, w = _arm_vectors(sigma, self.arm_turns_with_cam, psi)
        distance = c * np.sin(psi) - f
        d_distance = c * np.cos(psi) * ds
        d2_distance = c * (np.cos(psi) * d2s - np.sin(psi) * ds ** 2)
        contact, radius = _flat_envelope(distance, d_distance, d2_distance, w,
                                         lam * ds - sigma, lam * d2s)
        foot = np.array((-f * w[0], c - f * w[1]))
        along = _dot(contact - foot, u)
        angle = _pressure_angle(sigma, along * w + f * u, w)
        _, foot_curvature = _relative_motion(sigma, foot, f * ds * u, f * (d2s * u + ds ** 2 * w))
        return _Profile(theta, sigma, foot, contact, angle, foot_curvature, radius, along)


Follower = Union[TranslatingRoller, TranslatingFlat, OscillatingRoller, OscillatingFlat]
FOLLOWER_TYPES = (TranslatingRoller, TranslatingFlat, OscillatingRoller, OscillatingFlat)
ROLLERS = (TranslatingRoller, OscillatingRoller)


# ---------------------------------------------------------------- pure array functions
# Vectors are arrays of shape (2, n) in the fixed frame's basis until _Profile turns them.

def _perp(v: Array) -> Array:
    """Return J v, v turned by +90 degrees."""
    return np.array((-v[1], v[0]))


def _dot(a: Array, b: Array) -> Array:
    return a[0] * b[0] + a[1] * b[1]


def _cross(a: Array, b: Array) -> Array:
    return a[0] * b[1] - a[1] * b[0]


def _to_cam_frame(theta: Array, sigma: int, v: Array) -> Array:
    """Return fixed-frame points v at cam angles theta in the cam frame: Rot(-sigma*theta) v."""
    c, s = np.cos(theta), np.sin(sigma * theta)
    return np.array((c * v[0] + s * v[1], -s * v[0] + c * v[1]))


def _relative_motion(sigma: int, point: Array, d_point: Array,
                     d2_point: Array) -> tuple[Array, Array]:
    """Return tangent d/dtheta and signed curvature (1/m, convex > 0) of a point's cam-frame path.

    point, d_point, d2_point give the point and its theta-derivatives in the fixed frame; the
    returned tangent is in the fixed frame's basis (rotate it like the point).
    """
    tangent = d_point - sigma * _perp(point)
    second = d2_point - 2 * sigma * _perp(d_point) - point
    speed = np.hypot(tangent[0], tangent[1])
    return tangent, -sigma * _cross(tangent, second) / speed ** 3


def _pressure_angle(sigma: int, motion: Array, normal: Array) -> Array:
    """Return the angle (rad) from motion to normal, positive in the cam's sense of rotation."""
    return sigma * np.arctan2(_cross(motion, normal), _dot(motion, normal))


def _flat_envelope(distance: Array, d_distance: Array, d2_distance: Array, normal: Array,
                   rate: Array, d_rate: Array) -> tuple[Array, Array]:
    """Return the contact point and radius of curvature of the envelope of a moving face line.

    The face is the line {p: normal . p = distance} (unit normal pointing away from the cam); in
    the cam frame the normal turns at rate (rad per rad of cam angle) with derivative d_rate.
    """
    contact = distance * normal + (d_distance / rate) * _perp(normal)
    radius = distance + (d2_distance * rate - d_distance * d_rate) / rate ** 3
    return contact, radius


def _roller_profile(theta: Array, sigma: int, centre: Array, d_centre: Array, d2_centre: Array,
                    motion: Array, roller_radius: float) -> _Profile:
    """Return the profile of a roller whose centre and its derivatives are given (fixed frame)."""
    tangent, curvature = _relative_motion(sigma, centre, d_centre, d2_centre)
    normal = sigma * _perp(tangent) / np.hypot(tangent[0], tangent[1])
    with np.errstate(divide='ignore'):
        pitch_radius = 1.0 / curvature
    return _Profile(theta, sigma, centre, centre - roller_radius * normal,
                    _pressure_angle(sigma, motion, normal), curvature,
                    pitch_radius - roller_radius, None)


class _Profile:
    """Raw fixed-frame results of one follower, turned into the cam frame on demand."""

    def __init__(self, theta: Array, sigma: int, pitch: Array, contact: Array, angle: Array,
                 pitch_curvature: Array, surface_radius: Array, offset: Optional[Array]):
        self._theta, self._sigma = theta, sigma
        self._pitch, self._contact = pitch, contact
        self.pressure_angle = angle
        self.pitch_curvature = pitch_curvature
        self.surface_radius = surface_radius
        self.contact_offset = offset

    @property
    def pitch(self) -> Array:
        """Return the pitch curve in the cam frame."""
        return _to_cam_frame(self._theta, self._sigma, self._pitch)

    @property
    def surface(self) -> Array:
        """Return the cam surface (contact points) in the cam frame."""
        return _to_cam_frame(self._theta, self._sigma, self._contact)


# ---------------------------------------------------------------- public geometry

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

    @property
    def pitch_curvature(self) -> Array:
        """Return the signed curvature 1/pitch_radius (1/m), finite at inflections."""
        return 1.0 / self.pitch_radius


def _check_motion(theta: object, s: object, ds: object, d2s: object) -> tuple[Array, ...]:
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
        bad = _first_bad(name, array, ~np.isfinite(array), 'must be finite')
        if bad:
            raise bad
        if arrays and array.shape != arrays[0].shape:
            raise InvalidParameter(name, f'array of shape {array.shape}',
                                   f'must have the shape of theta {arrays[0].shape}')
        arrays.append(array)
    return tuple(arrays)


def _check_follower(follower: object) -> None:
    if not isinstance(follower, FOLLOWER_TYPES):
        raise InvalidParameter('follower', follower, 'must be one of ' +
                               ', '.join(kind.__name__ for kind in FOLLOWER_TYPES))


def _geometry(follower: Follower, theta: Array, s: Array, ds: Array, d2s: Array,
              clockwise: bool) -> CamGeometry:
    """Build the geometry from checked inputs (no validation)."""
    sigma = -1 if clockwise else 1
    raw = follower._geometry(theta, sigma, s, ds, d2s)
    with np.errstate(divide='ignore'):
        pitch_radius = 1.0 / raw.pitch_curvature
    offset = None if raw.contact_offset is None else _frozen(raw.contact_offset)
    return CamGeometry(follower, clockwise, _frozen(theta), _frozen(raw.pitch[0]),
                       _frozen(raw.pitch[1]), _frozen(raw.surface[0]), _frozen(raw.surface[1]),
                       _frozen(raw.pressure_angle), _frozen(pitch_radius),
                       _frozen(raw.surface_radius), offset)


def cam_geometry(follower: Follower, theta: object, s: object, ds: object, d2s: object, *,
                 clockwise: bool = False) -> CamGeometry:
    """Compute the cam profile for a follower motion sampled at cam angles theta (rad).

    s is the follower position (m; arm angle increment in rad for oscillating followers), ds and
    d2s its first and second derivatives with respect to theta. Raises InvalidParameter when the
    input is malformed or the motion leaves the follower's geometric range.
    """
    _check_follower(follower)
    theta_a, s_a, ds_a, d2s_a = _check_motion(theta, s, ds, d2s)
    problem = follower._motion_problem(s_a, ds_a)
    if problem:
        raise problem
    return _geometry(follower, theta_a, s_a, ds_a, d2s_a, bool(clockwise))


def contact_measures(follower: Follower, theta: Array, s: Array, ds: Array, d2s: Array, *,
                     clockwise: bool = False) -> tuple[Array, Array]:
    """Return (pressure angle, surface radius of curvature) only, without input checks.

    The per-request path of a validated design: same formulas as cam_geometry, none of its
    checks or cam-frame coordinates. Inputs must be equal-length 1-D float arrays.
    """
    raw = follower._geometry(theta, -1 if clockwise else 1, s, ds, d2s)
    return raw.pressure_angle, raw.surface_radius
