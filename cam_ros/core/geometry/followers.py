"""The four disk-cam followers: their parameters, checks and placement relative to the cam.

Conventions (one set for every follower; the measures they yield: :mod:`.geometry`):

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
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional, Union

import numpy as np

from ..arrays import Values
from .envelope import dot, flat_envelope, pressure_angle, Profile, relative_motion, roller_profile
from ..errors import InvalidParameter

Array = np.ndarray
#: Output arrays for the pressure angle and the radius of curvature of a block of samples.
Measures = tuple[Array, Array]


def checked_real(name: str, value: object, ok: Callable[[float], bool], rule: str) -> float:
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
            value = checked_real(name, getattr(follower, name), lambda x: True, 'finite (m)')
        else:
            value = checked_real(name, getattr(follower, name), lambda x: x > 0.0, '> 0 (m)')
        object.__setattr__(follower, name, value)


def _set_flag(follower: object, name: str) -> None:
    """Check a boolean field of a frozen follower."""
    value = getattr(follower, name)
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidParameter(name, value, 'must be a bool')
    object.__setattr__(follower, name, bool(value))


def first_bad(name: str, values: Array, bad: Array, rule: str) -> Optional[InvalidParameter]:
    """Return an InvalidParameter naming the first sample where bad holds, else None."""
    if not np.any(bad):
        return None
    index = int(np.argmax(bad))
    return InvalidParameter(f'{name}[{index}]', float(values[index]), rule)


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
        return first_bad('s', s, self.prime_height + s <= 0.0, 'roller centre must stay above '
                         f'the cam centre (s > {-self.prime_height:g} m)')

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> Profile:
        zero, one = np.zeros_like(s), np.ones_like(s)
        centre = np.array((self.offset + zero, self.prime_height + s))
        return roller_profile(theta, sigma, centre, np.array((zero, ds)),
                              np.array((zero, d2s)), np.array((zero, one)), self.roller_radius)

    def _contact(self, theta: Values, sigma: int, s: Values, ds: Values, d2s: Values,
                 out: Measures | None = None) -> tuple[Values, Values]:
        # _geometry's measures in closed form, on floats (one angle) or arrays: with p = d + s,
        # q = ds - sigma e (the pitch tangent is (sigma p, q)), tan phi = q / p and
        # rho_pitch = (p^2 + q^2)^1.5 / (p^2 + q^2 + q ds - p d2s).
        # Augmented assignments work in place on arrays (few temporaries) and on floats alike.
        angle_out, radius_out = out or (None, None)
        p = s + self.prime_height
        q = ds - sigma * self.offset
        angle = np.arctan2(q, p, out=angle_out)
        speed2 = p * p
        speed2 += q * q
        q *= ds  # q and p are spent: q becomes the denominator
        q += speed2
        p *= d2s
        q -= p
        radius = np.sqrt(speed2, out=radius_out)
        radius *= speed2
        with np.errstate(divide='ignore'):  # an inflection of the pitch curve: infinite
            radius /= q
        radius -= self.roller_radius
        return angle, radius


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
        return first_bad('s', s, self.base_radius + s <= 0.0,
                         f'face must stay above the cam centre (s > {-self.base_radius:g} m)')

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> Profile:
        zero, one = np.zeros_like(s), np.ones_like(s)
        distance = self.base_radius + s
        contact, radius = flat_envelope(distance, ds, d2s, np.array((zero, one)),
                                        -sigma + zero, zero)
        trace = np.array((zero, distance))
        _, trace_curvature = relative_motion(sigma, trace, np.array((zero, ds)),
                                             np.array((zero, d2s)))
        return Profile(theta, sigma, trace, contact, zero, trace_curvature, radius, ds,
                       np.array((zero, one)))

    def _contact(self, theta: Values, sigma: int, s: Values, ds: Values, d2s: Values,
                 out: Measures | None = None) -> tuple[Array, Values]:
        # _geometry's measures in closed form, on floats or arrays: phi = 0 (an array, 0-d for
        # one angle), rho = Rb + s + d2s.
        angle, radius_out = out or (np.empty_like(ds), None)
        angle.fill(0.0)
        radius = np.add(s, self.base_radius, out=radius_out)
        radius += d2s
        return angle, radius


def contact_from_geometry(follower: 'Follower', theta: Values, sigma: int, s: Values,
                          ds: Values, d2s: Values,
                          out: Measures | None = None) -> tuple[Values, Values]:
    """Return the pressure angle and surface radius of the follower's full _geometry (into out
    if given): the _contact of a follower without a closed form (one angle: an array of one)."""
    theta_, s_, ds_, d2s_ = [np.atleast_1d(value) for value in (theta, s, ds, d2s)]
    profile = follower._geometry(theta_, sigma, s_, ds_, d2s_)
    if isinstance(theta, float):
        return float(profile.pressure_angle[0]), float(profile.surface_radius[0])
    if out is None:
        return profile.pressure_angle, profile.surface_radius
    np.copyto(out[0], profile.pressure_angle)
    np.copyto(out[1], profile.surface_radius)
    return out


def arm_vectors(sigma: int, with_cam: bool, psi: Array) -> tuple[int, Array, Array]:
    """Return lambda, the arm unit vector u and w = du/dpsi (fixed frame) of an oscillating arm."""
    lam = sigma if with_cam else -sigma
    u = np.array((lam * np.sin(psi), -np.cos(psi)))
    w = np.array((lam * np.cos(psi), np.sin(psi)))
    return lam, u, w


def arm_angle_problem(psi0: float, s: Array) -> Optional[InvalidParameter]:
    """Return an error if the arm angle psi0 + s leaves (0, pi)."""
    psi = psi0 + s
    return first_bad('s', s, (psi <= 0.0) | (psi >= math.pi),
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
        return arm_angle_problem(self.initial_arm_angle, s)

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> Profile:
        _, u, w = arm_vectors(sigma, self.arm_turns_with_cam, self.initial_arm_angle + s)
        arm = self.arm_length
        centre = np.array((arm * u[0], self.pivot_distance + arm * u[1]))
        return roller_profile(theta, sigma, centre, arm * ds * w, arm * (d2s * w - ds ** 2 * u),
                              w, self.roller_radius)

    _contact = contact_from_geometry


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
        return (arm_angle_problem(self.initial_arm_angle, s)
                or first_bad('s', s, self.pivot_distance * np.sin(psi) <= self.face_offset,
                             'the face must stay clear of the cam centre')
                or first_bad('ds', ds, 1.0 - mu * ds <= 0.0,
                             'the arm must turn slower than the cam in the cam\'s sense '
                             '(1 - mu*ds/dtheta > 0)'))

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array,
                  d2s: Array) -> Profile:
        c, f = self.pivot_distance, self.face_offset
        psi = self.initial_arm_angle + s
        lam, u, w = arm_vectors(sigma, self.arm_turns_with_cam, psi)
        distance = c * np.sin(psi) - f
        d_distance = c * np.cos(psi) * ds
        d2_distance = c * (np.cos(psi) * d2s - np.sin(psi) * ds ** 2)
        contact, radius = flat_envelope(distance, d_distance, d2_distance, w,
                                        lam * ds - sigma, lam * d2s)
        foot = np.array((-f * w[0], c - f * w[1]))
        along = dot(contact - foot, u)
        angle = pressure_angle(sigma, along * w + f * u, w)
        _, foot_curvature = relative_motion(sigma, foot, f * ds * u, f * (d2s * u + ds ** 2 * w))
        return Profile(theta, sigma, foot, contact, angle, foot_curvature, radius, along, w)

    _contact = contact_from_geometry


Follower = Union[TranslatingRoller, TranslatingFlat, OscillatingRoller, OscillatingFlat]
FOLLOWER_TYPES = (TranslatingRoller, TranslatingFlat, OscillatingRoller, OscillatingFlat)
ROLLERS = (TranslatingRoller, OscillatingRoller)


def check_follower(follower: object) -> None:
    if not isinstance(follower, FOLLOWER_TYPES):
        raise InvalidParameter('follower', follower, 'must be one of ' +
                               ', '.join(kind.__name__ for kind in FOLLOWER_TYPES))
