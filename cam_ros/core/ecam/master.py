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

Master samples come with integer-nanosecond stamps. omega is the message's velocity when it has
one; otherwise, like alpha, it is estimated by the least-squares quadratic over the positions of
the last master.velocity_window seconds, at least the last three (speed_estimate: exact for a
master at constant acceleration, any spacing of the stamps; a window averages stamp jitter, and
the stamps of a master on a fixed cycle are de-jittered by a delay-locked loop, cycle_clock).
Successive positions are unwrapped (the master moves less than half a turn between messages),
so an encoder that wraps at 2 pi and a multi-turn position give the same estimates.
"""
from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import Any, Mapping, NamedTuple, Sequence

import numpy as np
import numpy.typing as npt

from ..arrays import Values
from ..cam_angles import cam_angle, cam_angles, TWO_PI
from ..config.parameters import UNITS
from ..config.schema import CamConfig
from ..motion.program import MotionProgram
from .speed_estimate import SpeedEstimator

#: Status of the master: none yet, messages arriving, silent for half the timeout, timed out.
WAITING, OK, STALE, LOST = 'waiting', 'ok', 'stale', 'lost'
#: Why a master message was dropped (the diagnostics count each).
NO_JOINT, NOT_FINITE = 'no master joint', 'not finite'
LENGTHS, BACKWARDS = 'mismatched array lengths', 'stamp not after the previous'


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
                   values['master.timeout'], values['master.max_speed'], mapping,
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


class BadMaster(Exception):
    """A master message that must be dropped; the reason is one of the module's constants."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(reason)


def read_master(joint: str, names: Sequence[str], position: Sequence[float],
                velocity: Sequence[float], effort: Sequence[float]) -> tuple[float, float | None]:
    """
    Return the master's (position, velocity or None) from a JointState's arrays.

    Raise BadMaster with the reason (one of NO_JOINT, LENGTHS, NOT_FINITE): the joint must be
    named, position must have one entry per name and velocity and effort none or one per name
    (as sensor_msgs/JointState says), the master's values must be finite.
    """
    if joint not in names:
        raise BadMaster(NO_JOINT)
    count = len(names)
    if len(position) != count or {len(velocity), len(effort)} - {0, count}:
        raise BadMaster(LENGTHS)
    index = names.index(joint)
    speed = float(velocity[index]) if velocity else None
    if not math.isfinite(position[index]) or (speed is not None and not math.isfinite(speed)):
        raise BadMaster(NOT_FINITE)
    return float(position[index]), speed


class MasterState(NamedTuple):
    """One accepted master sample: stamp (ns), position (rad), speed and acceleration.

    position is the master's as sent; track is the same position followed continuously (the
    first sample's, then every unwrapped step added), which the cam angle is taken from, so an
    encoder wrapping at 2 pi gives the commands of a multi-turn master for any master.scaling.
    """

    stamp_ns: int
    position: float
    omega: float
    alpha: float
    step: float  # unwrapped travel since the previous sample (rad), 0 for the first
    track: float  # continuous master position (rad): position + a whole number of turns


class MasterTracker:
    """
    Accept master samples, estimate speed and acceleration, and watch for silence.

    `accept` checks the stamp and returns the MasterState; `check(now_ns)` moves the status to
    STALE after half the timeout without a message and to LOST after the timeout (which ends an
    overspeed), returning the new status once when it changes. A sample after LOST starts the
    estimates afresh.
    """

    def __init__(self, timeout_ns: int, max_speed: float = math.inf, window_ns: int = 0):
        self.timeout_ns = int(timeout_ns)
        self.max_speed = float(max_speed)
        self.speed = SpeedEstimator(window_ns)  # window_ns 0: the last three samples
        self.status = WAITING
        self.dropped: Counter[str] = Counter()
        self.accepted = 0
        self.overspeed = False
        self.last: MasterState | None = None
        self._received_ns = 0

    def accept(self, stamp_ns: int, position: float, velocity: float | None,
               received_ns: int) -> MasterState:
        """Return the state of a new sample; raise BadMaster(BACKWARDS) for an old stamp."""
        last = self.last
        if last is not None and stamp_ns <= last.stamp_ns:
            raise BadMaster(BACKWARDS)
        if self.status == LOST:
            self.speed.reset()
        state = estimate(last if self.status != LOST else None, self.speed, stamp_ns, position,
                         velocity, 0.0 if last is None else last.track - last.position)
        self.last, self._received_ns, self.status = state, received_ns, OK
        self.accepted += 1
        self.overspeed = abs(state.omega) > self.max_speed
        return state

    def drop(self, reason: str) -> None:
        """Count a dropped message."""
        self.dropped[reason] += 1

    def check(self, now_ns: int) -> str | None:
        """Update the status for the time now (ns); return it if it changed."""
        if self.status == WAITING:
            return None
        silent = now_ns - self._received_ns
        status = LOST if silent >= self.timeout_ns else STALE if 2 * silent >= self.timeout_ns \
            else OK
        if status == self.status:
            return None
        self.status = status
        self.overspeed = self.overspeed and status != LOST
        return status


def estimate(previous: MasterState | None, speed: SpeedEstimator, stamp_ns: int,
             position: float, velocity: float | None, turns: float = 0.0) -> MasterState:
    """
    Return the state at a new sample, given the previous one (None: the first, or the first
    after a loss) and the estimator of the samples before, which takes the new one.

    A given velocity is taken as omega, and alpha = (omega - omega_before)/h1 with h1 the last
    stamp interval; otherwise both come from the estimator. Without a previous sample the track
    is position + turns, the whole turns the track had gained over the position before (0 for a
    multi-turn master).
    """
    if previous is None:
        speed.add(stamp_ns, position + turns)
        return MasterState(stamp_ns, position, velocity or 0.0, 0.0, 0.0, position + turns)
    d1 = math.remainder(position - previous.position, TWO_PI)
    # The representative of position (mod 2 pi) nearest the previous track plus the step: a
    # multi-turn master's track is its position exactly, a wrapping one's is that plus k turns.
    track = position + TWO_PI * round((previous.track + d1 - position) / TWO_PI)
    speed.add(stamp_ns, track)
    if velocity is not None:
        h1 = (stamp_ns - previous.stamp_ns) * 1e-9
        return MasterState(stamp_ns, position, velocity, (velocity - previous.omega) / h1, d1,
                           track)
    omega, alpha = speed.estimate()
    return MasterState(stamp_ns, position, omega, alpha, d1, track)
