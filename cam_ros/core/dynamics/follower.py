"""Follower dynamics of a force-closed cam: contact force, camshaft torque, jump, spring sizing.

Model: one degree of freedom, the follower position s (m; arm angle in rad for an oscillating
follower), kept on the cam by a spring. At constant cam speed omega (rad/s) the generalised force
the cam must supply along s (N; moment about the pivot in N m for an oscillating arm) is

    Q = m a + c v + k s + P + F_ext,    a = omega^2 d2s/dtheta2,  v = omega ds/dtheta,

with m the moving mass (the arm's inertia about its pivot, kg m^2), k the spring rate (N/m;
N m/rad), P = k x0 the spring preload at s = 0, c = 2 zeta sqrt(k m) from the damping ratio
zeta, and F_ext a constant load, positive toward the cam (like the spring). Q >= 0 keeps the
follower on the cam.

Sign conventions:

* Contact force N (N): the normal force between cam and follower, positive when pressing; N < 0
  means the follower would leave the cam (jump). The cam drives s through the lever l = n . dr/ds
  of the normal n at the follower's contact point: l = cos(phi) (translating roller), 1
  (translating flat face), L cos(phi) (oscillating roller, arm length L), t (oscillating flat face:
  the contact offset along the face, the normal's lever arm about the pivot), so N = Q / l. A flat
  face slides on the cam: friction mu N acts along the face, against the sliding, and adds
  mu f sign(slip) to the lever of an oscillating face at face_offset f (a translating face's
  friction is square to its travel). Rollers roll: no friction.
* Camshaft torque T (N m): the torque the drive supplies, positive in the cam's sense of
  rotation, from the power balance T omega = Q ds/dt + mu N |v_slip|, i.e.
  T = Q ds/dtheta + mu N |v_slip| / omega; the sliding speed per unit cam speed is Rb + s for a
  translating face and |m_s D + f ds/dtheta| for an oscillating one (D its distance from the cam
  centre, m_s = +1 if the arm turns with the cam else -1). Over a revolution the conservative part
  does no net work: the mean of T is damping and friction alone.
* Jump speed: Q is a quadratic in omega at each angle, A omega^2 + B omega + C with A = m d2s,
  B = c ds, C = k s + P + F_ext; where C > 0 its smallest positive root is
  omega_j = 2 C / (-B + sqrt(B^2 - 4 A C)), and the jump speed is the least omega_j over the cam
  (0 if C <= 0 somewhere: contact is lost at rest). N changes sign with Q wherever l > 0.
* Spring sizing: the smallest preload P >= 0 with k s + P + SF (m a + c v + F_ext) >= 0 at every
  angle, SF the jump safety factor.

Contact stress: Hertz line contact (:mod:`.contact`) with the cam surface's signed radius of
curvature, the roller radius (flat face: 1/R = 0), the face width and both bodies' moduli.
Everything is SI and vectorised over arrays of cam angles.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional

import numpy as np
import numpy.typing as npt

from .contact import effective_modulus, half_width, peak_pressure
from ..geometry.followers import Follower, OscillatingRoller, TranslatingFlat, TranslatingRoller

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class DynamicsConfig:
    """The dynamics.* and contact.* parameters and limits.contact_stress, in SI.

    inertia is the moving mass (kg) of a translating follower or the arm's inertia about its
    pivot (kg m^2); spring_rate N/m or N m/rad; spring_preload and external_force N or N m;
    face_width m; moduli and contact_stress_limit Pa (limit 0: not checked).
    """

    inertia: float
    spring_rate: float
    spring_preload: float
    damping_ratio: float
    external_force: float
    jump_safety_factor: float
    face_width: float
    cam_modulus: float
    cam_poisson: float
    follower_modulus: float
    follower_poisson: float
    friction: float
    contact_stress_limit: float

    @property
    def damping(self) -> float:
        """Return the damping coefficient c = 2 zeta sqrt(k m) (N s/m; N m s/rad)."""
        return 2.0 * self.damping_ratio * math.sqrt(self.spring_rate * self.inertia)

    @property
    def modulus(self) -> float:
        """Return the contact's effective modulus E* (Pa)."""
        return effective_modulus(self.cam_modulus, self.cam_poisson, self.follower_modulus,
                                 self.follower_poisson)


def parse_dynamics(values: Mapping[str, Any], metre: float,
                   follower_type: str) -> Optional[DynamicsConfig]:
    """Return the dynamics of checked flat parameter values, None when no mass is given.

    values hold every parameter (defaults filled in) already checked against its spec and the
    rules across parameters (config.schema); metre is the length unit in m.
    """
    name = 'dynamics.arm_inertia' if follower_type.startswith('oscillating') else 'dynamics.mass'
    if not values[name]:
        return None
    return DynamicsConfig(
        inertia=values[name], spring_rate=values['dynamics.spring_rate'],
        spring_preload=values['dynamics.spring_preload'],
        damping_ratio=values['dynamics.damping_ratio'],
        external_force=values['dynamics.external_force'],
        jump_safety_factor=values['dynamics.jump_safety_factor'],
        face_width=values['contact.face_width'] * metre,
        cam_modulus=values['contact.cam_modulus'], cam_poisson=values['contact.cam_poisson'],
        follower_modulus=values['contact.follower_modulus'],
        follower_poisson=values['contact.follower_poisson'],
        friction=values['contact.friction'],
        contact_stress_limit=values['limits.contact_stress'])


@dataclass(frozen=True, eq=False)
class DynamicsValues:
    """Forces on the follower train at an array of cam angles (SI; see the module docstring).

    follower_force Q and spring_force k s + P are along s (N; N m for an oscillating arm);
    contact_force N (N) is the normal force, camshaft_torque (N m) the drive torque,
    contact_stress the Hertz peak pressure p0 (Pa).
    """

    follower_force: Array
    spring_force: Array
    contact_force: Array
    camshaft_torque: Array
    contact_stress: Array


@dataclass(frozen=True, eq=False)
class FollowerDynamics:
    """The dynamic model of one follower train on one follower geometry at cam speed omega."""

    config: DynamicsConfig
    follower: Follower
    omega: float
    _roller_curvature: float = field(init=False, repr=False)  # 1/Rr, 0 for a flat face
    _modulus: float = field(init=False, repr=False)  # E* (Pa)

    def __post_init__(self) -> None:
        """Precompute the constants used at every evaluation."""
        roller = getattr(self.follower, 'roller_radius', math.inf)
        object.__setattr__(self, '_roller_curvature', 1.0 / roller)
        object.__setattr__(self, '_modulus', self.config.modulus)

    def follower_force(self, s: Array, ds: Array, d2s: Array,
                       omega: Optional[float] = None) -> tuple[Array, Array]:
        """Return (Q, spring force k s + P) at cam speed omega (default: the model's)."""
        speed = self.omega if omega is None else omega
        c = self.config
        spring = c.spring_rate * s + c.spring_preload
        inertial = (c.inertia * speed * speed) * d2s + (c.damping * speed) * ds
        return inertial + spring + c.external_force, spring

    def _lever_and_slip(self, s: Array, ds: Array,
                        pressure_angle: Array) -> tuple[Array | float, Array | float]:
        """Return the lever l = dQ/dN and the sliding speed per unit cam speed (m)."""
        follower, mu = self.follower, self.config.friction
        if isinstance(follower, TranslatingRoller):
            return np.cos(pressure_angle), 0.0
        if isinstance(follower, OscillatingRoller):
            return follower.arm_length * np.cos(pressure_angle), 0.0
        if isinstance(follower, TranslatingFlat):
            return 1.0, follower.base_radius + s
        psi = follower.initial_arm_angle + s
        turns = 1.0 if follower.arm_turns_with_cam else -1.0
        pivot, face = follower.pivot_distance, follower.face_offset
        offset = pivot * np.cos(psi) / (1.0 - turns * ds)
        slip = -(turns * (pivot * np.sin(psi) - face) + face * ds)
        return offset + (mu * face) * np.sign(slip), np.abs(slip)

    def values(self, s: Array, ds: Array, d2s: Array, pressure_angle: Array,
               radius_of_curvature: Array) -> DynamicsValues:
        """Return the forces, torque and stress at the motion and geometry given per angle."""
        force, spring = self.follower_force(s, ds, d2s)
        lever, slip = self._lever_and_slip(s, ds, pressure_angle)
        contact = force / lever
        torque = force * ds
        if self.config.friction:
            torque = torque + self.config.friction * contact * slip
        stress = peak_pressure(contact / self.config.face_width,
                               self.curvature_sum(radius_of_curvature), self._modulus)
        return DynamicsValues(force, spring, contact, torque, stress)

    def curvature_sum(self, radius_of_curvature: Array) -> Array:
        """Return K = 1/rho_cam + 1/R_follower (1/m) from the cam surface's signed radius."""
        with np.errstate(divide='ignore'):
            return 1.0 / radius_of_curvature + self._roller_curvature

    def half_width(self, contact_force: Array, radius_of_curvature: Array) -> Array:
        """Return the Hertz contact half-width b (m)."""
        return half_width(contact_force / self.config.face_width,
                          self.curvature_sum(radius_of_curvature), self._modulus)

    def jump_speeds(self, s: Array, ds: Array, d2s: Array) -> Array:
        """Return the least cam speed (rad/s) at which Q reaches 0 at each angle, inf if never.

        0 where Q <= 0 already at rest.
        """
        c = self.config
        a, b = c.inertia * d2s, c.damping * ds
        rest = c.spring_rate * s + c.spring_preload + c.external_force
        root = np.sqrt(np.maximum(b * b - 4.0 * a * rest, 0.0))
        denominator = root - b
        real = (b * b - 4.0 * a * rest >= 0.0) & (denominator > 0.0)
        with np.errstate(divide='ignore', invalid='ignore'):
            speed = np.where(real, 2.0 * rest / denominator, np.inf)
        return np.where(rest > 0.0, speed, 0.0)

    def preload_shortfall(self, s: Array, ds: Array, d2s: Array) -> Array:
        """Return -(k s + SF (m a + c v + F_ext)) (N; N m): the preload needed at each angle."""
        c = self.config
        force, spring = self.follower_force(s, ds, d2s)
        return -(c.spring_rate * s + c.jump_safety_factor * (force - spring))
