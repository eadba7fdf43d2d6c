"""
An axis against its slave.* limits, as a PLC's cam editor tabulates it (`cam_ros report`).

At master speed omega and acceleration alpha the slave is commanded v = y' omega and
a = y'' omega^2 + y' alpha (y per rad of master; slave_limits). At constant speed its peaks are
max |y'| |omega| and max |y''| omega^2, exact from the refined CamPeaks, at cam_speed and at
master.max_speed. The largest master acceleration of either sign the axis allows at cam_speed is
the largest |alpha| with |y'' omega^2| + |y'| |alpha| <= A at every angle:

    alpha_max = min over theta of (A - |y''(theta)| omega^2) / |y'(theta)|,

refined on the exact motion (extremes), not read off a grid; where the cam alone exceeds A at
constant speed, none is allowed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..cam_angles import TWO_PI
from ..config.schema import CamConfig
from ..extremes import CHECK_SAMPLES, refine_extremum
from .master import ElectronicCam, MasterConfig
from .slave_limits import BACKWARD_TOLERANCE, CamPeaks, SlaveLimits

#: A slope below this fraction of the cam's steepest counts as none in the master-acceleration
#: search (the bound there is a huge positive number, never the least).
FLAT = 1e-12


@dataclass(frozen=True)
class SpeedPeaks:
    """The axis's peak |velocity| and |acceleration| at one constant master speed (SI)."""

    master_speed: float  # rad/s of master
    velocity: float  # m/s or rad/s
    acceleration: float  # m/s^2 or rad/s^2

    def velocity_ok(self, limits: SlaveLimits) -> Optional[bool]:
        """Say whether the velocity keeps to slave.max_velocity (None: not limited)."""
        return None if not limits.max_velocity else self.velocity <= limits.max_velocity

    def acceleration_ok(self, limits: SlaveLimits) -> Optional[bool]:
        """Say whether the acceleration keeps to slave.max_acceleration (None: not limited)."""
        return (None if not limits.max_acceleration
                else self.acceleration <= limits.max_acceleration)


@dataclass(frozen=True)
class AxisLimits:
    """One limited axis against its limits (SI; see the module).

    master_acceleration: the largest |alpha| (rad/s^2 of master) allowed at cam_speed, inf when
    the axis never moves, None without slave.max_acceleration, and negative (none allowed) when
    the cam alone exceeds it at cam_speed; master_acceleration_at: the cam angle (rad) that sets
    it (nan when none does). backward: the largest velocity against slave.direction at
    cam_speed (<= 0: never).
    """

    limits: SlaveLimits
    cam_speed: SpeedPeaks
    max_speed: Optional[SpeedPeaks]  # None: master.max_speed not given
    master_acceleration: Optional[float]
    master_acceleration_at: float
    backward: float

    @property
    def direction_ok(self) -> Optional[bool]:
        """Say whether the axis keeps to slave.direction at cam_speed (None: any way)."""
        return None if not self.limits.direction else self.backward <= BACKWARD_TOLERANCE

    @property
    def ok(self) -> bool:
        """Return True when nothing exceeds its limit at cam_speed or at master.max_speed."""
        speeds = [self.cam_speed] + ([self.max_speed] if self.max_speed else [])
        limits = self.limits
        states = [state for peaks in speeds
                  for state in (peaks.velocity_ok(limits), peaks.acceleration_ok(limits))]
        return False not in states + [self.direction_ok]


def axis_limits(config: CamConfig, cam: ElectronicCam) -> Optional[AxisLimits]:
    """Check a design's e-cam (config's slave.* and master.*) against its limits; None when
    no limit or direction is set."""
    limits = SlaveLimits.from_config(config)
    if not limits.limited:
        return None
    master = MasterConfig.from_config(config)
    peaks = CamPeaks.of(cam)

    def at(omega: float) -> SpeedPeaks:
        found = peaks.at(omega, 0.0, limits.direction)
        return SpeedPeaks(omega, found.velocity, found.acceleration)

    nominal = at(master.nominal_speed)
    alpha, where = (None, math.nan) if not limits.max_acceleration else \
        largest_master_acceleration(cam, master.nominal_speed, limits.max_acceleration, peaks)
    return AxisLimits(limits, nominal, at(master.max_speed) if master.max_speed else None, alpha,
                      where, peaks.at(master.nominal_speed, 0.0, limits.direction).backward)


def largest_master_acceleration(cam: ElectronicCam, omega: float, limit: float,
                                peaks: CamPeaks) -> tuple[float, float]:
    """Return (alpha_max, cam angle) of the module's formula at master speed omega.

    alpha_max is -inf (nan angle) when the cam alone exceeds limit at omega, inf when it never
    moves.
    """
    if peaks.curvature * omega * omega > limit:
        return -math.inf, math.nan
    steepest = max(-peaks.slope[0], peaks.slope[1])
    if steepest == 0.0:
        return math.inf, math.nan
    program, mapping = cam.program, cam.mapping
    slope_scale = abs(mapping.slave_scaling / mapping.master_scaling)
    bend_scale = abs(mapping.slave_scaling) / mapping.master_scaling ** 2 * omega * omega

    def bound(theta: np.ndarray) -> np.ndarray:
        motion = program.evaluate(theta)
        slope = np.maximum(slope_scale * np.abs(motion.ds), FLAT * steepest)
        return (limit - bend_scale * np.abs(motion.d2s)) / slope

    theta = np.linspace(0.0, TWO_PI, CHECK_SAMPLES, endpoint=False)
    return refine_extremum(bound, theta, bound(theta), 'min', breaks=program.breaks)
