"""A whole cam design: motion program + follower + speed + limits (built by design_from_config).

This is what the node serves and the CLI reports on: one immutable object, built and validated
once, evaluated for any array of cam angles.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import cast

import numpy as np
import numpy.typing as npt

from .cam_angles import cam_angle, cam_angles, TWO_PI
from .config.schema import CamConfig
from .design_warnings import (closure_warnings, dynamics_warnings, geometry_warnings,
                              motion_warnings, vibration_warnings)
from .dynamics.flanks import form_closed_sides, Side, side_loads, SideLoads, side_values
from .dynamics.follower import DynamicsValues, FollowerDynamics
from .dynamics.polydyne import compensated_program
from .dynamics.report import DynamicsReport, dynamics_report
from .dynamics.vibration import vibration_report, VibrationReport
from .ecam.master import ElectronicCam, MasterConfig
from .ecam.slave_limits import AxisUnit, CamPeaks, SlaveLimits
from .errors import InvalidParameter
from .extremes import CHECK_SAMPLES
from .kept import kept
from .geometry.followers import Follower, OscillatingRoller, TranslatingRoller
from .geometry.cam_geometry import CamGeometry, cam_geometry, contact_at, contact_measures
from .geometry.check import GeometryCheck, check_geometry
from .geometry.closure import closure_check, ClosureCheck, conjugate_follower, groove_contours
from .geometry.machining import cam_contour, Contour
from .motion.program import Discontinuity, MotionProgram, time_derivatives

RollerFollower = TranslatingRoller | OscillatingRoller


@dataclass(frozen=True, eq=False)
class CamState:
    """The cam evaluated at an array of angles (SI; derivatives per rad and per s)."""

    angle: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray
    d3s: np.ndarray
    pressure_angle: np.ndarray
    radius_of_curvature: np.ndarray
    dynamics: DynamicsValues | None = None  # None: the design has no dynamics


@dataclass(frozen=True, eq=False)
class CamDesign:
    """One validated cam: evaluate it anywhere, sample its profile, check it against limits.

    A motion-only design (follower.type none, `follower` None) has the motion and nothing of a
    cam: its pressure angle and radius of curvature are nan, and geometry, check and contours
    raise InvalidParameter naming follower.type.
    """

    config: CamConfig
    program: MotionProgram
    follower: Follower | None

    @property
    def clockwise(self) -> bool:
        """True for a cam turning clockwise seen from +z."""
        return self.config.clockwise

    @cached_property
    def surface(self) -> MotionProgram:
        """Return the motion the cam surface gives the follower's input.

        The program itself, or with dynamics.compensate the polydyne cam (see polydyne.py),
        whose elastic train outputs the program at cam_speed. Geometry is the surface's.
        """
        train = self.config.train
        if train is None or not train.compensate:
            return self.program
        return compensated_program(self.program, self.config.cam_speed, train)

    def evaluate(self, angles: npt.ArrayLike) -> CamState:
        """Evaluate follower motion and cam geometry at cam angles (rad, taken modulo 2 pi).

        An advancing program (a rotary slave) is evaluated at the angles as given: each whole
        turn adds its advance to the position.
        """
        angles = np.asarray(angles, dtype=float)
        if angles.shape == (1,) and (self.dynamics is None or self._sides is None):
            return self._evaluate_one(float(angles[0]))
        theta = cam_angles(angles)
        motion = self.program.evaluate(angles)  # the program wraps, and counts an advance
        timed = motion.at_speed(self.config.cam_speed)
        if self.follower is None:
            nan = np.full(theta.shape, math.nan)
            return CamState(theta, timed.position, timed.velocity, timed.acceleration,
                            timed.jerk, motion.ds, motion.d2s, motion.d3s, nan, nan.copy())
        cam = motion if self.surface is self.program else self.surface.evaluate(theta)
        pressure_angle, radius = contact_measures(self.follower, theta, cam.s, cam.ds,
                                                  cam.d2s, clockwise=self.clockwise)
        if self.dynamics is None:
            forces = None
        elif self._sides is not None:  # form-closed: the side carrying the load
            forces = side_values(self.dynamics, self._sides, theta, motion, cam)
        else:
            forces = self.dynamics.values(motion.s, motion.ds, motion.d2s, pressure_angle,
                                          radius)
        return CamState(theta, timed.position, timed.velocity, timed.acceleration, timed.jerk,
                        motion.ds, motion.d2s, motion.d3s, pressure_angle, radius, forces)

    def _evaluate_one(self, angle: float) -> CamState:
        """Return evaluate's numbers at one angle, computed in floats.

        A one-angle request (~/evaluate's usual call) would otherwise spend its time in NumPy's
        per-call cost on arrays of one element; the results are put into arrays of one at the end.
        """
        theta = cam_angle(angle)
        s, ds, d2s, d3s = self.program.at(angle)
        timed = time_derivatives(self.config.cam_speed, ds, d2s, d3s)
        if self.follower is None:
            pressure_angle = radius = math.nan
        else:
            cam = (s, ds, d2s) if self.surface is self.program else self.surface.at(theta)[:3]
            pressure_angle, radius = contact_at(self.follower, theta, *cam,
                                                clockwise=self.clockwise)
        (theta_, s_, velocity, acceleration, jerk, ds_, d2s_, d3s_, pressure_angle_,
         radius_) = [np.array([value]) for value in (theta, s, *timed, ds, d2s, d3s,
                                                     pressure_angle, radius)]
        for motion in (s_, velocity, acceleration, jerk, ds_, d2s_, d3s_):  # as a batch's
            motion.flags.writeable = False
        forces = None if self.dynamics is None else self.dynamics.values(
            s_, ds_, d2s_, pressure_angle_, radius_)
        return CamState(theta_, s_, velocity, acceleration, jerk, ds_, d2s_, d3s_,
                        pressure_angle_, radius_, forces)

    @cached_property
    def dynamics(self) -> FollowerDynamics | None:
        """Return the follower-train model at the cam speed, None without dynamics."""
        config = self.config.dynamics
        return None if config is None else FollowerDynamics(config, self.cam_follower,
                                                            self.config.cam_speed)

    def profile(self, count: int) -> CamState:
        """Evaluate the cam at count equally spaced angles over one revolution from 0."""
        return self.evaluate(np.linspace(0.0, TWO_PI, count, endpoint=False))

    def geometry(self, count: int = CHECK_SAMPLES) -> CamGeometry:
        """Return the cam's geometry (pitch curve, surface, ...) at count angles from 0.

        The check's (CHECK_SAMPLES) is computed once: building the design validates it
        (CamGeometry is frozen, its arrays read-only).
        """
        if count == CHECK_SAMPLES:
            return self._checked_geometry
        return sampled_geometry(self.cam_follower, self.surface, self.clockwise, count)

    @cached_property
    def _checked_geometry(self) -> CamGeometry:
        return sampled_geometry(self.cam_follower, self.surface, self.clockwise, CHECK_SAMPLES)

    @property
    def cam_follower(self) -> Follower:
        """Return the follower; raise InvalidParameter for a motion-only design (no cam)."""
        if self.follower is None:
            raise InvalidParameter('follower.type', 'none', 'a motion-only design has no cam '
                                   '(no geometry, drawing or cutter path): give a follower type')
        return self.follower

    @cached_property
    def check(self) -> GeometryCheck:
        """Check the design against its limits: extremes refined from a dense sampling.

        Kept for an equal follower, surface, sense and limits (core/kept.py): a design built
        again for a new cam speed alone has the same check. The geometry it samples is not
        kept (half a megabyte); a design's own is computed again where the check is not kept.
        """
        config = self.config
        return kept(checked_geometry, self.cam_follower, self.surface, self.clockwise,
                    config.pressure_angle_limit, config.min_radius_of_curvature,
                    config.pressure_angle_return_limit)

    @cached_property
    def dynamics_check(self) -> DynamicsReport | None:
        """Return the refined dynamics figures at the cam speed, None without dynamics."""
        if self.dynamics is None:
            return None
        return dynamics_report(self.dynamics, self.program, self.evaluate)

    @cached_property
    def vibration_check(self) -> VibrationReport | None:
        """Return the elastic train's figures at the cam speed, None for a rigid train."""
        train = self.config.train
        if train is None:
            return None
        return vibration_report(self.surface, self.config.cam_speed, train, self.dynamics,
                                output=self.program)

    @cached_property
    def velocity_jumps(self) -> tuple[Discontinuity, ...]:
        """Return the joints where ds/dtheta jumps (an infinite acceleration).

        They fail the verdict unless limits.allow_velocity_jumps is true.
        """
        return tuple(jump for jump in self.program.continuity_report() if jump.order == 1)

    def contours(self) -> dict[str, Contour]:
        """Return the cam's working curves, exact in the cam angle (cam frame, machining.py).

        'surface'; a groove's 'inner' and 'outer' flanks (normals into the groove); a conjugate
        pair's 'first' and 'second' cams.
        """
        f = self.config.follower
        if f.closure == 'groove':
            return groove_contours(cast(RollerFollower, self.cam_follower), self.surface,
                                   self.clockwise, f.groove_clearance)
        first = cam_contour(self.cam_follower, self.surface, self.clockwise)
        if f.closure == 'force':
            return {'surface': first}
        second = cast(Follower, self._conjugate)
        return {'first': first, 'second': cam_contour(second, self.surface, self.clockwise)}

    @cached_property
    def _conjugate(self) -> Follower | None:
        """Return a conjugate pair's second roller or arm (closure.py), None for other cams."""
        f = self.config.follower
        if f.closure != 'conjugate':
            return None
        return conjugate_follower(self.cam_follower, self.surface, f.conjugate_angle)

    @cached_property
    def closure(self) -> ClosureCheck | None:
        """Return the second side of a form-closed cam (closure.py), None for force closure."""
        f = self.config.follower
        if f.closure == 'force':
            return None
        return closure_check(f.closure, self.cam_follower, self.clockwise, self.check,
                             self.surface, clearance=f.groove_clearance,
                             conjugate_angle=f.conjugate_angle)

    @cached_property
    def _sides(self) -> tuple[Side, Side] | None:
        """Return the two sides of a form-closed cam (dynamics/flanks.py), None for force."""
        f = self.config.follower
        if f.closure == 'force':
            return None
        return form_closed_sides(self.cam_follower, self.clockwise, self._conjugate,
                                 f.groove_clearance)

    @cached_property
    def side_loads(self) -> SideLoads | None:
        """Return which side of a form-closed cam carries the load where (with dynamics)."""
        if self._sides is None or self.dynamics is None:
            return None
        return side_loads(self.dynamics, self.program, *self._sides)

    @property
    def ok(self) -> bool:
        """Return True when the design meets its limits, is not undercut and does not jump.

        A velocity jump at a joint fails it too, unless limits.allow_velocity_jumps is true.
        A form-closed cam cannot jump: its sides must not be undercut, cam 2 must meet the
        limits and each side's stress the allowable.
        """
        dynamics, vibration, closure = self.dynamics_check, self.vibration_check, self.closure
        if self.slave_excess:
            return False
        if self.follower is None:  # motion only: nothing but the motion to judge
            return self.config.allow_velocity_jumps or not self.velocity_jumps
        if closure is not None:
            loads = self.side_loads
            return (self.check.ok and closure.ok and (loads is None or loads.ok)
                    and (self.config.allow_velocity_jumps or not self.velocity_jumps))
        return (self.check.ok and (dynamics is None or dynamics.ok)
                and (vibration is None or vibration.ok)
                and (self.config.allow_velocity_jumps or not self.velocity_jumps))

    def warnings(self) -> list[str]:
        """Say, once, what a designer must know: limits broken, undercut, discontinuities, jump."""
        motion = motion_warnings(self.program, self.config, self.slave_excess)
        if self.follower is None:  # motion only: no cam to check
            return motion
        notes = geometry_warnings(self.check, self.config) + motion
        if self.closure is not None:
            return notes + closure_warnings(self.closure, self.side_loads)
        return (notes + vibration_warnings(self.vibration_check, self.config)
                + dynamics_warnings(self.dynamics_check, self.config))

    @cached_property
    def electronic_cam(self) -> ElectronicCam:
        """Return the program driven by the master through the config's master.* and slave.*
        offsets and scalings (MC_CamIn): what an e-cam of this design commands."""
        return ElectronicCam(self.program, MasterConfig.from_config(self.config).mapping)

    @cached_property
    def slave_excess(self) -> str:
        """Say which slave.* limits the e-cam exceeds at cam_speed ('' if none or unset)."""
        limits = SlaveLimits.from_config(self.config)
        if not limits.limited:
            return ''
        peaks = CamPeaks.of(self.electronic_cam).at(
            MasterConfig.from_config(self.config).nominal_speed, 0.0, limits.direction)
        excess = peaks.excess(limits, AxisUnit.of(self.config))
        return f'at cam_speed the slave axis exceeds its limits: {excess}' if excess else ''

    def summary(self) -> str:
        """Describe the design in one line for logs."""
        laws = ', '.join(f'{s.law.name} {math.degrees(s.start):g}-{math.degrees(s.end):g} deg'
                         for s in self.program.segments)
        if self.follower is None:
            unit, factor = self.config.file_position_unit
            advance = (f', advancing {self.program.advance * factor:g} {unit} per cycle'
                       if self.program.advance else '')
            return (f'motion only (follower.type none) at {self.config.cam_speed:g} rad/s: '
                    f'{laws}{advance}')
        check = self.check
        return (f'{self.config.follower.type} follower, '
                f'{"clockwise" if self.clockwise else "counter-clockwise"} cam at '
                f'{self.config.cam_speed:g} rad/s: {laws}; max |pressure angle| '
                f'{math.degrees(check.max_pressure_angle):.2f} deg, min radius of curvature '
                f'{check.min_radius:.6g} m')


def sampled_geometry(follower: Follower, surface: MotionProgram, clockwise: bool,
                     count: int) -> CamGeometry:
    """Return a cam's geometry at count equally spaced cam angles from 0."""
    theta = np.linspace(0.0, TWO_PI, count, endpoint=False)
    motion = surface.evaluate(theta)
    return cam_geometry(follower, theta, motion.s, motion.ds, motion.d2s, clockwise=clockwise)


def checked_geometry(follower: Follower, surface: MotionProgram, clockwise: bool,
                     pressure_limit: float, min_radius: float,
                     pressure_return_limit: float) -> GeometryCheck:
    """Return a cam's check against its limits, extremes refined on the exact surface."""
    geometry = sampled_geometry(follower, surface, clockwise, CHECK_SAMPLES)
    return check_geometry(geometry, max_pressure_angle=pressure_limit, min_radius=min_radius,
                          program=surface, max_pressure_angle_return=pressure_return_limit)
