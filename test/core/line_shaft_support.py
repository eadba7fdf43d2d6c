"""A limited four-axis line (config/machine.yaml plus a pusher), master profiles and checks, for
the path-limits and line-shaft tests."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint
import toppra.interpolator

from cam_ros.core.ecam.line_shaft import LineShaft
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.path_limits import PathLimits
from cam_ros.core.ecam.slave_limits import SlaveLimits
from cam_ros.core.machine.machine import load_machine

MACHINE = Path(__file__).resolve().parents[2] / 'config' / 'machine.yaml'
NOMINAL = 10.471975511965978  # the machine's cam_speed, rad/s
#: Limits of feeder, knife (one-way, rotary) and jaw: about 1.25 x what the cams use at cam_speed.
LIMITS = (SlaveLimits(2.5, 40.0), SlaveLimits(15.0, 30.0, 1, 2 * math.pi), SlaveLimits(2.0, 55.0))
DT = 0.004  # a 250 Hz master


@dataclass(frozen=True)
class Line:
    """The machine's cams, their limits and the path limits."""

    cams: tuple
    limits: tuple
    path: PathLimits

    def positions(self, theta: np.ndarray) -> np.ndarray:
        """Return each axis's command (columns) at virtual master positions theta."""
        return np.stack([np.asarray(cam.derivatives(theta).y, dtype=float)
                         for cam in self.cams], axis=-1)


def line(limits=LIMITS) -> Line:
    """Return the machine of config/machine.yaml with limits."""
    cams = tuple(axis.cam for axis in load_machine(MACHINE).axes)
    return Line(cams, tuple(limits), PathLimits.of(cams, limits, NOMINAL, math.radians(30.0)))


def run(shaft: LineShaft, acceleration: Callable[[float], float], seconds: float,
        events: dict[int, Callable[[LineShaft], None]] = {}, silent=range(0)):
    """Drive shaft with a master of that acceleration (rad/s^2) from rest at 0 every DT; at the
    steps in events call them first; during the steps in silent tick instead (no sample).
    Return theta_v's states and modes, and the master's tracks."""
    theta = omega = 0.0
    states, modes, tracks = [], [], []
    for k in range(round(seconds / DT)):
        alpha = acceleration(k * DT)
        after = omega + alpha * DT
        theta, omega = theta + 0.5 * (omega + after) * DT, after
        if k in events:
            events[k](shaft)
        stamp = round(k * DT * 1e9)
        if k in silent:
            state = shaft.tick(stamp)
        else:
            state = shaft.master(MasterState(stamp, theta, omega, alpha, 0.0, theta))
        states.append(state)
        modes.append(shaft.mode)
        tracks.append(theta)
    return states, modes, tracks


def peaks(machine: Line, states) -> tuple[np.ndarray, np.ndarray]:
    """Return each axis's largest |velocity| and |acceleration| of the commands, by finite
    differences of the positions at the samples (what a drive sees)."""
    theta = np.array([state.theta for state in states])
    position = machine.positions(theta)
    velocity = np.diff(position, axis=0) / DT
    return np.abs(velocity).max(axis=0), np.abs(np.diff(velocity, axis=0) / DT).max(axis=0)


def within(machine: Line, states, slack: float = 1e-9) -> None:
    """Assert every axis's commands stay within its velocity and acceleration limits."""
    velocity, acceleration = peaks(machine, states)
    for axis, limits in enumerate(machine.limits):
        assert velocity[axis] <= limits.max_velocity * (1 + slack), (axis, velocity[axis])
        assert acceleration[axis] <= limits.max_acceleration * (1 + slack), \
            (axis, acceleration[axis])


class CamPath(toppra.interpolator.AbstractGeometricPath):
    """The machine's axes as a toppra path over master positions, from the cams' exact
    derivatives (a spline through positions would ring at the segment joints)."""

    def __init__(self, machine: Line, start: float, end: float):
        self._cams, self._interval = machine.cams, np.array([start, end])

    def __call__(self, path_positions, order=0):
        theta = np.atleast_1d(np.asarray(path_positions, dtype=float))
        field = ('y', 'dy', 'd2y')[order]
        values = np.stack([np.asarray(getattr(cam.derivatives(theta), field), dtype=float)
                           for cam in self._cams], axis=-1)
        return values if np.ndim(path_positions) else values[0]

    @property
    def dof(self):
        return len(self._cams)

    @property
    def path_interval(self):
        return self._interval

    @property
    def waypoints(self):
        return None


def toppra_stop_time(machine: Line, start: float, end: float, omega: float) -> float:
    """Return the shortest time from master speed omega at start to rest at end along the
    path within the axes' limits (an independent time-optimal reference: toppra)."""
    toppra.setup_logging('ERROR')
    path = CamPath(machine, start, end)
    velocity = np.array([[-lim.max_velocity, lim.max_velocity] for lim in machine.limits])
    acceleration = np.array([[-lim.max_acceleration, lim.max_acceleration]
                             for lim in machine.limits])
    instance = toppra.algorithm.TOPPRA(
        [toppra.constraint.JointVelocityConstraint(velocity),
         toppra.constraint.JointAccelerationConstraint(acceleration)],
        path, gridpoints=np.linspace(start, end, 4001), parametrizer='ParametrizeConstAccel')
    trajectory = instance.compute_trajectory(omega, 0.0)
    assert trajectory is not None, 'toppra found no stop'
    return float(trajectory.duration)
