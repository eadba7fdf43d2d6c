"""Form-closed cams: a groove (track) guiding the roller on both flanks, or a conjugate pair.

Groove. The roller of radius Rr runs in a track of width 2 Rr + clearance whose flanks are the
pitch curve offset by -w (inner flank, toward the cam centre) and +w (outer flank), w = Rr +
clearance/2. They share the pitch curve's normal, so the pressure angle is the same; seen from
the roller the inner flank is convex where the pitch curve is (radius rho_p - w) and the outer
flank where the pitch curve is concave (radius |rho_p| - w): each is undercut where that radius
falls to 0 or below. The inner flank pushes the follower away from the cam (Q > 0, see
dynamics/flanks.py), the outer one pulls it back.

Conjugate pair. Two cams on one shaft, one roller each on one rigid follower: cam 1 is the
design's cam; cam 2 drives the return. A translating yoke carries roller 2 on the same line of
travel, a fixed spacing B below roller 1: its centre is (e, d + s - B) with B = 2 d + s_max +
s_min, so cam 2's prime circle is d where the follower is highest; cam 2 pushes it in -y. An
oscillating follower's second arm is turned back by conjugate_angle gamma from the first: arm
angle psi - gamma, in (-pi, 0), on the other side of the line from the pivot to the cam centre,
so that cam 2 turns the arm back. With zero offset a single cam of constant breadth with two
opposed rollers can replace the pair exactly when s(theta) + s(theta + pi) is constant.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Union

import numpy as np

from ..errors import InvalidParameter
from ..extremes import CHECK_SAMPLES, refine_extrema, TWO_PI
from ..motion.program import MotionProgram
from .cam_geometry import cam_geometry
from .check import pitch_curvature_of, GeometryExtremes, check_geometry, GeometryCheck
from .envelope import Profile, roller_profile
from .followers import (arm_angle_problem, arm_vectors, contact_from_geometry, first_bad,
                        Follower, OscillatingRoller, TranslatingRoller)
from .machining import cam_contour, Contour

Array = np.ndarray
#: s(theta) + s(theta + pi) may spread by this much (m or rad, relative to the stroke) and the
#: cam still count as of constant breadth.
BREADTH_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Flank:
    """One flank of a groove, seen from the roller: its smallest convex radius (m, inf if it
    has no convex part), where (rad), and whether it is undercut (that radius <= 0)."""

    radius_of_curvature_min: float
    at: float
    undercut: bool


def _grid(program: MotionProgram, samples: int) -> tuple[Array, ...]:
    theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    motion = program.evaluate(theta)
    return theta, motion.s, motion.ds, motion.d2s


def groove_flanks(follower: Union[TranslatingRoller, OscillatingRoller], program: MotionProgram,
                  clockwise: bool, clearance: float = 0.0,
                  samples: int = CHECK_SAMPLES) -> dict[str, Flank]:
    """Return the 'inner' and 'outer' flanks of a groove cam, extremes refined on program."""
    half = follower.roller_radius + 0.5 * clearance
    theta, s, ds, d2s = _grid(program, samples)
    sampled = follower._geometry(theta, -1 if clockwise else 1, s, ds, d2s)
    extremes = GeometryExtremes(follower, clockwise, theta, sampled, program)
    (high, high_at), (low, low_at) = extremes.extremes([(pitch_curvature_of, 'max'),
                                                        (pitch_curvature_of, 'min')])

    def flank(bend: float, at: float) -> Flank:
        radius = 1.0 / bend - half if bend > 0.0 else math.inf
        return Flank(radius, at, bend > 0.0 and radius <= 0.0)
    return {'inner': flank(high, high_at), 'outer': flank(-low, low_at)}


def groove_contours(follower: Union[TranslatingRoller, OscillatingRoller],
                    program: MotionProgram, clockwise: bool,
                    clearance: float = 0.0) -> dict[str, Contour]:
    """Return the inner and outer flank curves (cam frame), normals pointing into the groove."""
    pitch = cam_contour(follower, program, clockwise).offset(follower.roller_radius)
    half = follower.roller_radius + 0.5 * clearance
    return {'inner': pitch.offset(-half), 'outer': pitch.offset(half).flipped()}


@dataclass(frozen=True)
class ConjugateRoller(TranslatingRoller):
    """Roller 2 of a translating conjugate yoke: spacing (m) below roller 1 on its line.

    base_radius, roller_radius and offset are roller 1's (the design's follower).
    """

    spacing: float = 0.0

    def __post_init__(self) -> None:
        """Check roller 1's lengths and the spacing."""
        super().__post_init__()
        if not (math.isfinite(self.spacing) and self.spacing > 0.0):
            raise InvalidParameter('spacing', self.spacing, 'must be a finite length > 0 (m)')

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        return first_bad('s', s, self.prime_height + s - self.spacing >= 0.0,
                         'roller 2 must stay below the cam centre')

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array, d2s: Array) -> Profile:
        zero, one = np.zeros_like(s), np.ones_like(s)
        centre = np.array((self.offset + zero, self.prime_height + s - self.spacing))
        return roller_profile(theta, sigma, centre, np.array((zero, ds)),
                              np.array((zero, d2s)), np.array((zero, -one)), self.roller_radius)

    # Roller 1's closed form (TranslatingRoller._contact) assumes roller 1's centre and normal.
    _contact = contact_from_geometry


@dataclass(frozen=True)
class ConjugateArm(OscillatingRoller):
    """Arm 2 of an oscillating conjugate follower, turned back by conjugate_angle (rad)."""

    conjugate_angle: float = 0.0

    def __post_init__(self) -> None:
        """Check arm 1's lengths and the angle between the arms."""
        super().__post_init__()
        if not (math.isfinite(self.conjugate_angle) and 0.0 < self.conjugate_angle < TWO_PI):
            raise InvalidParameter('conjugate_angle', self.conjugate_angle,
                                   'must be in (0, 2 pi) rad: the angle between the two arms')

    def _motion_problem(self, s: Array, ds: Array) -> Optional[InvalidParameter]:
        return arm_angle_problem(self.initial_arm_angle - self.conjugate_angle + math.pi, s)

    def _geometry(self, theta: Array, sigma: int, s: Array, ds: Array, d2s: Array) -> Profile:
        psi = self.initial_arm_angle + s - self.conjugate_angle
        _, u, w = arm_vectors(sigma, self.arm_turns_with_cam, psi)
        arm = self.arm_length
        centre = np.array((arm * u[0], self.pivot_distance + arm * u[1]))
        return roller_profile(theta, sigma, centre, arm * ds * w, arm * (d2s * w - ds ** 2 * u),
                              -w, self.roller_radius)


def _stroke(program: MotionProgram, samples: int) -> tuple[float, float]:
    """Return the refined (min s, max s) of the program."""
    theta, s, _, _ = _grid(program, samples)
    (low, _), (high, _) = refine_extrema(lambda a: np.array([program.evaluate(a).s] * 2),
                                         theta, np.array([s, s]), ('min', 'max'),
                                         breaks=program.breaks)
    return low, high


def conjugate_follower(follower: Follower, program: MotionProgram, conjugate_angle: float = 0.0,
                       samples: int = CHECK_SAMPLES) -> Union[ConjugateRoller, ConjugateArm]:
    """Return the second roller of a conjugate pair driven by program (see the module doc)."""
    if isinstance(follower, TranslatingRoller):
        low, high = _stroke(program, samples)
        return ConjugateRoller(follower.base_radius, follower.roller_radius, follower.offset,
                               2.0 * follower.prime_height + low + high)
    if isinstance(follower, OscillatingRoller):
        return ConjugateArm(follower.base_radius, follower.roller_radius,
                            follower.pivot_distance, follower.arm_length,
                            follower.arm_turns_with_cam, conjugate_angle)
    raise InvalidParameter('follower', follower, 'a conjugate cam needs a roller follower')


def second_roller_problem(follower: Follower, program: MotionProgram, conjugate_angle: float,
                          samples: int = CHECK_SAMPLES) -> Optional[str]:
    """Return why a conjugate pair's second roller cannot follow program, else None."""
    try:
        second = conjugate_follower(follower, program, conjugate_angle, samples)
    except InvalidParameter as err:
        return err.rule
    _, s, ds, _ = _grid(program, samples)
    problem = second._motion_problem(s, ds)
    return None if problem is None else f'the second roller cannot follow: {problem.rule}'


@dataclass(frozen=True)
class ConstantBreadth:
    """s(theta) + s(theta + pi) over a half turn: its spread (m) and whether it is constant."""

    spread: float
    holds: bool


def constant_breadth(program: MotionProgram,
                     samples: int = CHECK_SAMPLES) -> ConstantBreadth:
    """Return whether one cam with two opposed rollers could replace a conjugate pair."""
    theta = np.linspace(0.0, math.pi, samples // 2, endpoint=False)

    def total(angles: Array) -> Array:
        both = program.evaluate(angles).s + program.evaluate(angles + math.pi).s
        return np.array([both, both])

    breaks = np.concatenate((np.mod(program.breaks, math.pi), [0.0]))
    (high, _), (low, _) = refine_extrema(total, theta, total(theta), ('max', 'min'),
                                         breaks=breaks, period=math.pi)
    stroke = np.ptp(program.evaluate(theta).s) or 1.0
    spread = high - low
    return ConstantBreadth(spread, spread <= BREADTH_TOLERANCE * stroke)


@dataclass(frozen=True, eq=False)
class ClosureCheck:
    """The two sides of a form-closed cam (a groove's 'inner' and 'outer' flanks, a conjugate
    pair's 'first' and 'second' cams), cam 2's own check and follower (conjugate), and the
    constant-breadth test (conjugate translating yoke without offset, else None)."""

    closure: str
    sides: dict[str, Flank]
    second: Optional[GeometryCheck] = None
    second_follower: Optional[Union[ConjugateRoller, ConjugateArm]] = None
    breadth: Optional[ConstantBreadth] = None

    @property
    def ok(self) -> bool:
        """Return True when no side is undercut and cam 2 (if any) meets its limits."""
        return (not any(side.undercut for side in self.sides.values())
                and (self.second is None or self.second.ok))


def _flank(check: GeometryCheck) -> Flank:
    return Flank(check.min_radius, check.min_radius_at, check.undercut)


def closure_check(closure: str, follower: Follower, clockwise: bool, check: GeometryCheck,
                  program: MotionProgram, *, clearance: float = 0.0, conjugate_angle: float = 0.0,
                  samples: int = CHECK_SAMPLES) -> Optional[ClosureCheck]:
    """Return the check of a form-closed cam (None for 'force') from cam 1's check.

    follower (a roller), clockwise and program are cam 1's, as check was made from them.

    Cam 2 of a conjugate pair drives the follower's return, which is its own working stroke:
    it is checked with the return's pressure-angle limit where the follower rises and the rise's
    where it returns, and with cam 1's radius limit.
    """
    if closure == 'force':
        return None
    if not isinstance(follower, (TranslatingRoller, OscillatingRoller)):
        raise InvalidParameter('follower', follower, f'a {closure} cam needs a roller follower')
    if closure == 'groove':
        return ClosureCheck(closure, groove_flanks(follower, program, clockwise, clearance,
                                                   samples))
    second = conjugate_follower(follower, program, conjugate_angle, samples)
    theta, s, ds, d2s = _grid(program, samples)
    rise, ret = check.pressure_angle_limit, check.pressure_angle_return_limit
    second_check = check_geometry(cam_geometry(second, theta, s, ds, d2s, clockwise=clockwise),
                                  max_pressure_angle=ret, max_pressure_angle_return=rise,
                                  min_radius=check.radius_limit, program=program)
    breadth = (constant_breadth(program, samples) if isinstance(follower, TranslatingRoller)
               and follower.offset == 0.0 else None)
    return ClosureCheck(closure, {'first': _flank(check), 'second': _flank(second_check)},
                        second_check, second, breadth)
