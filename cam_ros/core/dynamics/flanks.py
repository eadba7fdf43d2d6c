"""Which side of a form-closed cam carries the load, and the Hertz stress on each side.

A groove or a conjugate pair holds the roller from both sides, so there is no return spring:
the generalised force Q the cam must supply (follower.py, spring 0) is carried by the first side
(a groove's inner flank, the first cam) where Q > 0 and by the second (the outer flank, the
second cam) where Q < 0. At each sign change of Q the load crosses over: a groove's roller
leaves one flank for the other and reverses its spin. There is no jump to check. Each side's
contact force is |Q| over its own lever (follower.py) and its Hertz stress uses that side's
surface radius seen from the roller. Extremes and crossovers are refined on the exact motion
(:mod:`..extremes`), the crossovers splitting the search like joints.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np

from ..extremes import CHECK_SAMPLES, refine_extrema, refine_roots, TWO_PI
from ..geometry.envelope import Profile
from ..geometry.followers import Follower
from ..motion.program import MotionProgram
from .contact import peak_pressure
from .follower import DynamicsValues, FollowerDynamics

Array = np.ndarray
#: (lever, surface radius of curvature seen from the roller) of one side at the motion given.
Side = Callable[[Array, Array, Array, Array], tuple[Array, Array]]


@dataclass(frozen=True)
class SideLoad:
    """The load one side carries: the spans (rad, (start, end), may wrap through 0) where it
    does, its largest contact force (N) and Hertz peak pressure (Pa, NaN where undercut) and
    where they occur."""

    spans: tuple[tuple[float, float], ...]
    contact_force_max: float
    contact_force_max_at: float
    contact_stress_max: float
    contact_stress_max_at: float


@dataclass(frozen=True)
class SideLoads:
    """The two sides' loads, the crossovers between them (rad) and the allowable stress."""

    crossovers: tuple[float, ...]
    sides: tuple[SideLoad, SideLoad]
    contact_stress_limit: Optional[float]

    @property
    def ok(self) -> bool:
        """Return True when neither side's stress exceeds the allowable (or is undefined)."""
        limit = self.contact_stress_limit
        return limit is None or all(side.contact_stress_max <= limit for side in self.sides)


Spans = tuple[tuple[float, float], ...]


def _crossovers(force: Callable[[Array], Array], theta: Array, values: Array,
                breaks: Array) -> tuple[Array, tuple[Spans, Spans]]:
    """Return where Q changes sign and the spans where Q > 0 and where Q < 0.

    Where Q is 0 (a dwell without load) neither side carries anything; a sign change across
    such a stretch is placed where Q reaches 0 (bisection on the loaded samples).
    """
    loaded = values != 0.0
    if np.count_nonzero(loaded) < 3:
        return np.array([]), ((), ())
    roots = refine_roots(force, theta[loaded], values[loaded], breaks=breaks)  # jumps too
    signs = np.sign(values[loaded])
    if roots.size == 0:
        whole = ((0.0, TWO_PI),)
        return roots, ((whole, ()) if signs[0] > 0 else ((), whole))
    owner = (np.searchsorted(roots, theta[loaded], side='right') - 1) % roots.size
    first = np.unique(owner, return_index=True)
    sign_of = dict(zip(first[0].tolist(), signs[first[1]].tolist()))
    ends = np.append(roots[1:], roots[0] + TWO_PI)
    spans: list[list[tuple[float, float]]] = [[], []]
    for index, (start, end) in enumerate(zip(roots.tolist(), ends.tolist())):
        if index in sign_of:
            spans[0 if sign_of[index] > 0 else 1].append((start, end % TWO_PI))
    return roots, (tuple(spans[0]), tuple(spans[1]))


def side_loads(model: FollowerDynamics, program: MotionProgram, first: Side, second: Side,
               samples: int = CHECK_SAMPLES) -> SideLoads:
    """Return the loads of the two sides of a form-closed cam at the model's speed."""
    theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    width, modulus = model.config.face_width, model.config.modulus

    def force(angles: Array) -> Array:
        motion = program.evaluate(angles)
        return model.follower_force(motion.s, motion.ds, motion.d2s)[0]

    def rows(angles: Array) -> Array:
        motion = program.evaluate(angles)
        q = model.follower_force(motion.s, motion.ds, motion.d2s)[0]
        found = []
        for side, carries in ((first, q > 0.0), (second, q < 0.0)):
            lever, radius = side(angles, motion.s, motion.ds, motion.d2s)
            contact = np.where(carries, np.abs(q) / lever, 0.0)
            stress = peak_pressure(contact / width, model.curvature_sum(radius), modulus)
            found += [contact, np.where(carries, stress, 0.0)]
        return np.array(found)

    grid_force = force(theta)
    crossovers, spans = _crossovers(force, theta, grid_force, program.breaks)
    breaks = np.concatenate((np.asarray(program.breaks, dtype=float), crossovers))
    grid = rows(theta)
    undefined = np.isnan(grid)
    refined = refine_extrema(rows, theta, np.nan_to_num(grid), ('max',) * 4, breaks=breaks)
    loads = []
    for index, sign in ((0, 1.0), (1, -1.0)):
        (force_max, force_at), (stress_max, stress_at) = refined[2 * index:2 * index + 2]
        if undefined[2 * index + 1].any():  # undercut: no Hertz contact
            stress_max = math.nan
            stress_at = float(theta[np.argmax(undefined[2 * index + 1])])
        loads.append(SideLoad(spans[index], force_max, force_at, stress_max, stress_at))
    limit = model.config.contact_stress_limit
    return SideLoads(tuple(float(angle) for angle in crossovers), (loads[0], loads[1]),
                     limit if limit > 0.0 else None)


def roller_side(follower: Follower, clockwise: bool,
                radius: Callable[[Profile], Array]) -> Side:
    """Return a Side of a roller follower: lever cos(phi) (L cos(phi) on an arm of length L,
    follower.py) and the surface radius radius(profile) seen from the roller."""
    sigma = -1 if clockwise else 1
    arm = getattr(follower, 'arm_length', 1.0)

    def side(angles: Array, s: Array, ds: Array, d2s: Array) -> tuple[Array, Array]:
        profile = follower._geometry(angles, sigma, s, ds, d2s)
        with np.errstate(divide='ignore'):
            return arm * np.cos(profile.pressure_angle), radius(profile)
    return side


def form_closed_sides(follower: Follower, clockwise: bool, second: Optional[Follower] = None,
                      clearance: float = 0.0) -> tuple[Side, Side]:
    """Return the two sides of a groove (second None) or a conjugate pair (second: roller 2).

    A groove's flanks are seen from the roller at radius rho_p - w (inner) and -(rho_p + w)
    (outer), w = Rr + clearance/2; a conjugate cam at its own surface radius.
    """
    if second is not None:
        return (roller_side(follower, clockwise, _own_surface),
                roller_side(second, clockwise, _own_surface))
    half = getattr(follower, 'roller_radius') + 0.5 * clearance
    return (roller_side(follower, clockwise, lambda profile: 1.0 / profile.pitch_curvature - half),
            roller_side(follower, clockwise,
                        lambda profile: -(1.0 / profile.pitch_curvature + half)))


def side_values(model: FollowerDynamics, sides: tuple[Side, Side], angles: Array,
                motion: Any, cam: Any) -> DynamicsValues:
    """Return the forces on a form-closed cam at angles (follower.py's DynamicsValues).

    motion drives the forces, cam (the surface's motion) the geometry (s, ds, d2s each). The
    contact force is on the side carrying the load, negative where the second side does; the
    stress is that side's.
    """
    q, spring = model.follower_force(motion.s, motion.ds, motion.d2s)
    (lever_1, radius_1), (lever_2, radius_2) = (side(angles, cam.s, cam.ds, cam.d2s)
                                                for side in sides)
    first = q >= 0.0
    contact = np.where(first, q / lever_1, q / lever_2)
    stress = peak_pressure(np.abs(contact) / model.config.face_width,
                           model.curvature_sum(np.where(first, radius_1, radius_2)),
                           model.config.modulus)
    return DynamicsValues(q, spring, contact, q * motion.ds, stress)


def _own_surface(profile: Profile) -> Array:
    """Return a conjugate cam's own surface radius, seen from its roller."""
    return profile.surface_radius
