"""
Electronic cam: follow a master axis, PLCopen MC_CamIn style, without ROS.

A master position q (rad, any real, multi-turn or negative) maps to the cam angle and the cam to
the slave (follower) setpoint:

    theta = ((q - q0) / m) mod 2 pi            q0 = master.offset_deg, m = master.scaling
    y     = k s(theta) + y0                    y0 = slave.offset, k = slave.scaling

(a program that advances, a rotary slave, adds k times its advance per whole cam turn).

With the master speed omega = dq/dt and acceleration alpha = d2q/dt2, the chain rule gives the
follower's velocity, acceleration and jerk exactly (s', s'', s''' per rad of cam angle):

    v = k s' omega / m
    a = k (s'' omega**2 / m**2 + s' alpha / m)
    j = k (s''' omega**3 / m**3 + 3 s'' omega alpha / m**2)   (the master's own jerk taken as 0)

Master samples are taken, unwrapped and checked by master_tracker.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, NamedTuple

import numpy as np
import numpy.typing as npt

from ..arrays import Values
from ..cam_angles import cam_angle, cam_angles, TWO_PI
from ..config.parameters import UNITS
from ..config.schema import CamConfig
from ..motion.program import MotionProgram


@dataclass(frozen=True)
class CamMapping:
    """MC_CamIn's offsets and scalings (see the module docstring); SI values."""

    master_offset: float = 0.0  # rad of master
    master_scaling: float = 1.0  # rad of master per rad of cam
    slave_offset: float = 0.0  # m, or rad of arm angle
    slave_scaling: float = 1.0

    def cam_angle(self, master: npt.ArrayLike) -> Values:
        """Return the cam angle theta in [0, 2 pi) of master positions (rad); a float of one."""
        turns = self.turns(master)
        return cam_angle(turns) if isinstance(turns, float) else cam_angles(turns)

    def turns(self, master: npt.ArrayLike) -> Values:
        """Return the cam angle before the modulo: (q - q0) / m (rad); a float of one."""
        q = master if isinstance(master, float) else np.asarray(master, dtype=float)
        return (q - self.master_offset) / self.master_scaling


class Setpoints(NamedTuple):
    """Follower setpoints (m or rad, per s, s^2, s^3) at master positions, and their cam angle."""

    cam_angle: Values
    position: Values
    velocity: Values
    acceleration: Values
    jerk: Values


class MasterDerivatives(NamedTuple):
    """A slave path y(q) and its first three derivatives per rad of master position q."""

    y: Values
    dy: Values
    d2y: Values
    d3y: Values


def chain_rule(cam_angle: npt.ArrayLike, path: MasterDerivatives, omega: npt.ArrayLike,
               alpha: npt.ArrayLike) -> Setpoints:
    """
    Return the setpoints of a path at master speed omega and acceleration alpha (jerk 0).

    Floats in (one master sample), floats out: the same numbers as arrays (w * w * w, not
    w ** 3: Python's pow and NumPy's differ in the last digit now and then).
    """
    w, dw = (value if isinstance(value, float) else np.asarray(value, dtype=float)
             for value in (omega, alpha))
    angle = cam_angle if isinstance(cam_angle, float) else np.asarray(cam_angle, dtype=float)
    return Setpoints(angle, path.y, path.dy * w, path.d2y * (w * w) + path.dy * dw,
                     path.d3y * (w * w * w) + 3.0 * path.d2y * w * dw)


@dataclass(frozen=True, eq=False)
class ElectronicCam:
    """A motion program driven by a master axis through a CamMapping."""

    program: MotionProgram
    mapping: CamMapping

    def slave(self, theta: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Return the slave position y and dy/dtheta (per rad of cam) at cam angles theta."""
        values = self.program.evaluate(theta)
        k = self.mapping.slave_scaling
        return k * values.s + self.mapping.slave_offset, k * values.ds

    def derivatives(self, master: npt.ArrayLike) -> MasterDerivatives:
        """Return y and its derivatives per rad of master (not of cam) at master positions."""
        mapping = self.mapping
        # The program wraps the turns and adds an advancing program's advance per whole turn.
        turns = mapping.turns(master)
        values: tuple[Values, Values, Values, Values]
        if isinstance(turns, float):
            values = self.program.at(turns)
        else:
            motion = self.program.evaluate(turns)
            values = motion.s, motion.ds, motion.d2s, motion.d3s
        s, ds, d2s, d3s = values
        k, m = mapping.slave_scaling, mapping.master_scaling
        return MasterDerivatives(k * s + mapping.slave_offset, k * ds / m, k * d2s / m ** 2,
                                 k * d3s / m ** 3)

    def breaks(self, low: float, high: float) -> np.ndarray:
        """Return the master positions in [low, high] where the cam or a derivative may jump."""
        mapping, angles = self.mapping, np.asarray(self.program.breaks)
        first = math.floor((mapping.turns(low) - angles.max()) / TWO_PI)
        last = math.ceil((mapping.turns(high) - angles.min()) / TWO_PI)
        turns = np.arange(first, last + 1)[:, np.newaxis] * TWO_PI
        q = (mapping.master_offset + mapping.master_scaling * (angles + turns)).reshape(-1)
        return q[(q >= low) & (q <= high)]

    def setpoints(self, master: npt.ArrayLike, omega: npt.ArrayLike = 0.0,
                  alpha: npt.ArrayLike = 0.0) -> Setpoints:
        """Return the setpoints at master positions, speeds and accelerations (broadcast)."""
        return chain_rule(self.mapping.cam_angle(master), self.derivatives(master), omega, alpha)


@dataclass(frozen=True)
class MasterConfig:
    """The master.*, slave.* and command.* parameters in SI."""

    source: str
    topic: str
    joint: str
    timeout: float  # s
    max_speed: float  # rad/s of master; 0: no check
    nominal_speed: float  # rad/s of master that turns the cam at cam_speed
    mapping: CamMapping
    interface: str
    trajectory_horizon: float  # s
    trajectory_points: int

    @classmethod
    def from_config(cls, config: CamConfig) -> 'MasterConfig':
        """Read the (already checked) parameters of a CamConfig."""
        values: Mapping[str, Any] = config.parameters
        slave_unit = math.radians(1.0) if config.oscillating else UNITS[config.length_unit]
        mapping = CamMapping(math.radians(values['master.offset_deg']), values['master.scaling'],
                             values['slave.offset'] * slave_unit, values['slave.scaling'])
        return cls(values['master.source'], values['master.topic'], values['master.joint'],
                   values['master.timeout'], values['master.max_speed'],
                   values['cam_speed'] * mapping.master_scaling, mapping,
                   values['command.interface'], values['command.trajectory_horizon'],
                   values['command.trajectory_points'])

    def speed_limit(self, jump_speed: float | None) -> tuple[float, str]:
        """
        Return the master speed to warn above (inf: none) and what sets it.

        That is master.max_speed (if not 0) or the master speed at which the cam turns at its
        jump speed (rad/s of cam, None without dynamics), whichever is lower.
        """
        limits = [(self.max_speed, 'master.max_speed')] if self.max_speed else []
        if jump_speed is not None:
            limits.append((jump_speed * self.mapping.master_scaling, 'the jump speed'))
        return min(limits, default=(math.inf, 'no limit'))
