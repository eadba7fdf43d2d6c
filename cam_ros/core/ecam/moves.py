"""
Moves off the cams: one axis joining its cam in time, within its limits (ruckig).

A move takes an axis from where it is (position, velocity, acceleration) onto its cam while the
virtual master theta_v turns at a constant speed omega (0: at rest, the common case). It is planned
in the frame of the axis's own cam:

    y(t) = y_cam(theta_v(t)) + e(t)        theta_v(t) = theta + omega t

e starts at the axis's offset from the cam (and its velocity and acceleration relative to the
cam's) and ends at 0 with de = dde = 0: from then on the axis is on its cam, exactly. ruckig
computes e as a time-optimal move of constant-jerk pieces within bounds on e:

- velocity |de| <= V - max |y' omega|, acceleration |dde| <= A - max |y''| omega^2 and jerk
  |d3e| <= J - max |y'''| |omega|^3 (J = slave.max_jerk; 0: none, an infinite jerk: then the
  acceleration steps at the pieces' joints, as a trapezoid's does), the cam's own use taken at its
  peaks over a whole cycle (CamPeaks), so cam + e keeps each limit whatever the master angle;
  each limit is planned PLAN_MARGIN below;
- one-way (slave.direction): de never lets y' omega + de go against the direction (ruckig's
  min_velocity, or max_velocity for a negative axis);
- an axis without a velocity (acceleration) limit moves off its cam no faster (no harder) than
  its cam itself moves at cam_speed: its cam's own peak at the nominal master speed bounds e.

ruckig's answer is then re-checked: the command cam + e, its velocity, acceleration and jerk and
its direction, refined to their true extremes over the whole move (extremes.refine_extrema, the
pieces' joints and the cam's segment joints as breaks). Bounds on e alone leave round-off (and
ruckig's own tolerances) unchecked; where a limit is passed, the bound on e shrinks by the excess
and the move is planned again (up to REPLANS times), or refused saying why.

A rotary axis (length_unit deg) joins its cam at whole turns from where it is, as
slave_limits.join_turns chooses: the nearest, or for a one-way axis also the nearest ahead (turns
are never unwound); of two candidates the shorter move wins.

A move can start later (Move.delayed, for sequencing moves that would collide): the axis holds its
start in the cam's frame, e frozen, so with theta_v at rest it stands, and with theta_v moving it
moves with its cam, its offset kept. Only a move that starts at rest relative to its cam
(de = dde = 0) can wait: any other would step its velocity.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import NamedTuple, Union

import numpy as np
import numpy.typing as npt
from ruckig import InputParameter, Ruckig, RuckigError, Trajectory

from ..cam_angles import TWO_PI
from ..extremes import refine_extremum, refine_extrema
from .slave_path import SlavePath
from .master import ElectronicCam
from .slave_limits import (AxisUnit, BACKWARD_TOLERANCE, CamPeaks, join_turns, Peaks,
                           PLAN_MARGIN, SAMPLES_PER_RAD, shifted, SlaveLimits)

#: Times a move is planned again with tighter bounds when the re-check finds a limit passed.
REPLANS = 8
#: Fewest time samples of a re-check, and samples per piece of constant jerk at the least.
FEWEST_SAMPLES, SAMPLES_PER_PIECE = 512, 32
#: An offset from the cam (m or rad) below this is none: the axis is on its cam.
POSITION_TOLERANCE = 1e-12


class MasterMotion(NamedTuple):
    """theta_v during a move: at theta (rad of master) when the move starts, at constant speed."""

    theta: float
    omega: float = 0.0  # rad/s of master; 0: at rest

    def at(self, times: npt.ArrayLike) -> np.ndarray:
        """Return theta_v at times (s after the move starts)."""
        return self.theta + self.omega * np.asarray(times, dtype=float)


class AxisState(NamedTuple):
    """Where an axis is when a move starts (SI: m or rad, per s, per s^2)."""

    position: float
    velocity: float = 0.0
    acceleration: float = 0.0


class MoveSetpoints(NamedTuple):
    """A move's commands at times (SI)."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


class MovePeaks(NamedTuple):
    """A command's largest |velocity|, |acceleration|, |jerk| and velocity against the way."""

    velocity: float
    acceleration: float
    jerk: float
    backward: float  # largest velocity against slave.direction (<= 0: never backward)

    def excess(self, limits: SlaveLimits, unit: AxisUnit) -> str:
        """Say which limits these peaks pass ('' if none), with the figures."""
        over = [Peaks(self.velocity, self.acceleration, self.backward).excess(limits, unit)]
        if limits.max_jerk and self.jerk > limits.max_jerk:
            over.append(f'jerk {unit.say(self.jerk, "/s^3")} over slave.max_jerk '
                        f'{unit.say(limits.max_jerk, "/s^3")}')
        return '; '.join(item for item in over if item)


class Bounds(NamedTuple):
    """ruckig's bounds on e: its velocity between min and max, |dde| and |d3e| (inf: none)."""

    min_velocity: float
    max_velocity: float
    max_acceleration: float
    max_jerk: float


class Profile(NamedTuple):
    """e(t) in pieces of constant jerk: each piece's start time, e, de, dde there, its jerk."""

    start: np.ndarray
    e: np.ndarray
    de: np.ndarray
    dde: np.ndarray
    jerk: np.ndarray
    duration: float

    @classmethod
    def of(cls, trajectory: Trajectory) -> 'Profile':
        """Return ruckig's trajectory (its brake pieces, then its seven) as pieces."""
        main = trajectory.profiles[0][0]
        brake = main.brake
        pieces = [np.concatenate((np.asarray(brake_part, dtype=float)[:2],
                                  np.asarray(main_part, dtype=float)[:7]))
                  for brake_part, main_part in ((brake.t, main.t), (brake.p, main.p),
                                                (brake.v, main.v), (brake.a, main.a),
                                                (brake.j, main.j))]
        lengths, e, de, dde, jerk = pieces
        kept = lengths > 0.0  # ruckig's unused pieces have zero length (and stale values)
        ends = np.cumsum(lengths[kept])
        return cls(ends - lengths[kept], e[kept], de[kept], dde[kept], jerk[kept],
                   float(ends[-1]) if ends.size else 0.0)

    def at(self, tau: np.ndarray) -> tuple[np.ndarray, ...]:
        """Return e and its three derivatives at times tau (0 after the end, the start before)."""
        if not self.start.size:
            zero = np.zeros_like(tau)
            return zero, zero, zero, zero
        i = np.clip(np.searchsorted(self.start, tau, side='right') - 1, 0, self.start.size - 1)
        h = np.maximum(tau - self.start[i], 0.0)
        j, a, v, p = self.jerk[i], self.dde[i], self.de[i], self.e[i]
        moving = np.where(tau >= 0.0, 1.0, 0.0)  # before: the start held (a wait)
        done = tau >= self.duration  # after: on the cam, exactly
        e = np.where(done, 0.0, p + h * (v + h * (a / 2.0 + h * j / 6.0)))
        de = np.where(done, 0.0, moving * (v + h * (a + h * j / 2.0)))
        dde = np.where(done, 0.0, moving * (a + h * j))
        return e, de, dde, np.where(done, 0.0, moving * j)


@dataclass(frozen=True, eq=False)
class Move:
    """One axis's move onto its cam (see the module): cam + e(t - delay)."""

    cam: SlavePath  # the cam joined (a rotary axis's at the whole turns chosen), or Held
    limits: SlaveLimits
    master: MasterMotion
    start: AxisState
    profile: Profile
    bounds: Bounds
    turns: int = 0  # whole turns of a rotary axis's cam joined, from its cam as configured
    delay: float = 0.0  # s the axis holds its start (in the cam's frame) before moving

    @property
    def duration(self) -> float:
        """Return the time (s) from the start to the axis on its cam, the delay included."""
        return self.delay + self.profile.duration

    def relative(self, times: npt.ArrayLike) -> tuple[np.ndarray, ...]:
        """Return e and its three time derivatives at times (s after the start)."""
        return self.profile.at(np.asarray(times, dtype=float) - self.delay)

    def at(self, times: npt.ArrayLike) -> MoveSetpoints:
        """Return the commanded position, velocity and acceleration at times (s)."""
        position, velocity, acceleration, _ = self.commands(times)
        return MoveSetpoints(position, velocity, acceleration)

    def commands(self, times: npt.ArrayLike) -> tuple[np.ndarray, ...]:
        """Return the command's position and its three time derivatives at times (s)."""
        t = np.asarray(times, dtype=float)
        d = self.cam.derivatives(self.master.at(t))
        w = self.master.omega
        e, de, dde, d3e = self.relative(t)
        return (d.y + e, d.dy * w + de, d.d2y * (w * w) + dde, d.d3y * (w * w * w) + d3e)

    @property
    def waits(self) -> bool:
        """Say whether the move may start later: at rest relative to its cam (see the module)."""
        profile = self.profile
        steps = math.isinf(self.bounds.max_jerk)  # the acceleration steps at the start anyway
        return not (profile.duration and (profile.de[0] or (profile.dde[0] and not steps)))

    def delayed(self, seconds: float) -> 'Move':
        """Return the same move starting seconds later, the axis holding its start meanwhile."""
        if seconds < 0.0 or not math.isfinite(seconds):
            raise ValueError(f'delay {seconds!r}: must be a finite number >= 0')
        if seconds and not self.waits:
            raise ValueError('a move that does not start at rest relative to its cam cannot '
                             'wait: its velocity would step')
        return replace(self, delay=self.delay + seconds)

    def breaks(self, until: float | None = None) -> np.ndarray:
        """Return the times in [0, until] (default: the end) where the command or a derivative
        may jump: the pieces' joints and the cam's segment joints."""
        end = self.duration if until is None else until
        times = [self.delay + self.profile.start, np.array([self.delay, self.duration])]
        w = self.master.omega
        if w:
            travel = sorted((self.master.theta, float(self.master.at(end))))
            times.append((self.cam.breaks(*travel) - self.master.theta) / w)
        found = np.concatenate(times)
        return np.unique(found[(found >= 0.0) & (found <= end)])

    def grid(self) -> np.ndarray:
        """Return sample times over [0, duration] dense enough to locate the move's extremes."""
        scaling = self.cam.mapping.master_scaling if isinstance(self.cam, ElectronicCam) else 1.0
        count = max(FEWEST_SAMPLES, SAMPLES_PER_PIECE * (self.profile.start.size + 1),
                    math.ceil(abs(self.master.omega) * self.duration / scaling
                              * SAMPLES_PER_RAD))
        return np.unique(np.concatenate((np.linspace(0.0, self.duration, count + 1),
                                         self.breaks())))

    @cached_property
    def peaks(self) -> MovePeaks:
        """Return the command's peaks over the whole move, refined (backward: by its limits)."""
        direction = self.limits.direction
        if self.duration <= 0.0:
            _, v, a, j = (float(value[0]) for value in self.commands(np.zeros(1)))
            return MovePeaks(abs(v), abs(a), abs(j), -direction * v)

        def rows(times: np.ndarray) -> np.ndarray:
            _, v, a, j = self.commands(times)
            return np.array([np.abs(v), np.abs(a), np.abs(j), -direction * v])

        t = self.grid()
        found = refine_extrema(rows, t, rows(t), ('max',) * 4, breaks=self.breaks(), period=None)
        return MovePeaks(*(value for value, _ in found))


def on_cam(cam: SlavePath, limits: SlaveLimits, master: MasterMotion) -> Move:
    """Return the move of an axis that stays on its cam (or on a Held position, whatever
    theta_v does): none, of duration 0."""
    d = cam.derivatives(master.theta)
    w = master.omega
    none = np.empty(0)
    return Move(cam, limits, master,
                AxisState(float(d.y), float(d.dy) * w, float(d.d2y) * w * w),
                Profile(none, none, none, none, none, 0.0), Bounds(0.0, 0.0, 0.0, 0.0))


def cam_jerk(cam: ElectronicCam) -> float:
    """Return the cam's largest |y'''| per rad of master over a cycle (refined)."""
    low = cam.mapping.master_offset
    high = low + TWO_PI * cam.mapping.master_scaling
    q = np.linspace(low, high, FEWEST_SAMPLES * 8 + 1)
    breaks = cam.breaks(low, high)
    q = np.unique(np.concatenate((q, breaks)))

    def steepness(master: np.ndarray) -> np.ndarray:
        return np.abs(np.asarray(cam.derivatives(master).d3y, dtype=float))
    return refine_extremum(steepness, q, steepness(q), 'max', breaks=breaks, period=None)[0]


def plan_move(cam: ElectronicCam, limits: SlaveLimits, start: AxisState, master: MasterMotion,
              nominal_speed: float, unit: AxisUnit = AxisUnit(),
              peaks: CamPeaks | None = None) -> Union[Move, str]:
    """
    Return the fastest move from start onto the cam within the limits, or why there is none.

    nominal_speed: the master speed at cam_speed (rad/s; what bounds an axis without limits);
    peaks: the cam's own (CamPeaks.of(cam), refined once per design; computed when not given).
    The reason is one line with the figure and the limit.
    """
    peaks = peaks if peaks is not None else CamPeaks.of(cam)
    moving = MovePeaks(abs(start.velocity), abs(start.acceleration) if limits.max_jerk else 0.0,
                       0.0, -limits.direction * start.velocity).excess(limits, unit)
    if moving:
        return f'starts over its limits: {moving}'
    own = peaks.at(master.omega, 0.0, limits.direction)
    jerk = cam_jerk(cam) * abs(master.omega) ** 3 if limits.max_jerk and master.omega else 0.0
    too_much = MovePeaks(own.velocity, own.acceleration, jerk, own.backward).excess(limits, unit)
    if too_much:
        return f'its cam itself at master speed {master.omega:.6g} rad/s: {too_much}'
    bounds = _bounds(limits, peaks, own, jerk, nominal_speed)
    if isinstance(bounds, str):
        return bounds
    found = [_plan_onto(shifted(cam, turns, limits), turns, limits, start, master, bounds, unit)
             for turns in join_turns(cam, master.theta, start.position, limits)]
    moves = [move for move in found if isinstance(move, Move)]
    if moves:
        return min(moves, key=lambda move: move.duration)
    return str(found[0])


class MoveRequest(NamedTuple):
    """What plan_move takes, gathered where a move is due so it can be planned elsewhere."""

    cam: ElectronicCam
    limits: SlaveLimits
    start: AxisState
    master: MasterMotion
    nominal_speed: float
    unit: AxisUnit
    peaks: CamPeaks

    def plan(self) -> Union[Move, str]:
        """Return plan_move's answer."""
        return plan_move(self.cam, self.limits, self.start, self.master, self.nominal_speed,
                         self.unit, self.peaks)


def _bounds(limits: SlaveLimits, peaks: CamPeaks, own: Peaks, jerk: float,
            nominal_speed: float) -> Union[Bounds, str]:
    """Return ruckig's bounds on e (see the module), or why there are none."""
    free = peaks.at(nominal_speed, 0.0, 0)
    keep = 1.0 - PLAN_MARGIN
    found = {}
    for name, limit, used, chosen in (
            ('velocity', limits.max_velocity, own.velocity, free.velocity),
            ('acceleration', limits.max_acceleration, own.acceleration, free.acceleration)):
        found[name] = limit * keep - used if limit else chosen
        if found[name] <= 0.0:
            return (f'its cam at this master speed leaves no room within slave.max_{name}'
                    if limit else f'no slave.max_{name} and its cam does not move at cam_speed '
                                  f'(whose peaks bound a move without limits): give one')
    velocity, acceleration = found['velocity'], found['acceleration']
    jerk_bound = limits.max_jerk * keep - jerk if limits.max_jerk else math.inf
    low, high = -velocity, velocity
    if limits.direction > 0:
        low = max(low, own.backward)
    elif limits.direction < 0:
        high = min(high, -own.backward)
    return Bounds(low, high, acceleration, jerk_bound)


def _ruckig(relative: tuple[float, float, float], bounds: Bounds) -> Union[Profile, str]:
    """Return ruckig's time-optimal e from relative (e, de, dde) to rest at 0, or why not."""
    given = InputParameter(1)
    given.current_position, given.current_velocity, given.current_acceleration = (
        [value] for value in relative)
    given.target_position, given.target_velocity, given.target_acceleration = [0.0], [0.0], [0.0]
    given.min_velocity, given.max_velocity = [bounds.min_velocity], [bounds.max_velocity]
    given.max_acceleration, given.max_jerk = [bounds.max_acceleration], [bounds.max_jerk]
    trajectory = Trajectory(1)
    try:
        Ruckig(1).calculate(given, trajectory)
    except RuckigError:
        return 'no move within its bounds reaches it'
    return Profile.of(trajectory)


def _plan_onto(cam: ElectronicCam, turns: int, limits: SlaveLimits, start: AxisState,
               master: MasterMotion, bounds: Bounds, unit: AxisUnit) -> Union[Move, str]:
    """Plan onto one cam (one choice of turns); re-check and replan (see the module)."""
    d = cam.derivatives(master.theta)
    w = master.omega
    offset = start.position - float(d.y)
    if abs(offset) <= POSITION_TOLERANCE:
        offset = 0.0
    relative = (offset, start.velocity - float(d.dy) * w,
                start.acceleration - float(d.d2y) * w * w)
    if limits.direction and not w and limits.direction * offset > 0.0:
        return (f'its cam is {unit.say(abs(relative[0]))} '
                f'{"behind" if limits.direction > 0 else "ahead of"} it with the master at rest: '
                'it cannot reach it without moving against slave.direction')
    over = ''
    for _ in range(REPLANS):
        profile = _ruckig(relative, bounds)
        if isinstance(profile, str):
            return f'from {unit.say(start.position)} onto its cam: {profile}'
        move = Move(cam, limits, master, start, profile, bounds, turns)
        found = move.peaks
        over = found.excess(limits, unit)
        if not over:
            return move
        bounds = _tighter(bounds, found, limits)
    return f'no move keeps within the limits: {over}'


def _tighter(bounds: Bounds, found: MovePeaks, limits: SlaveLimits) -> Bounds:
    """Return bounds shrunk by what the re-checked command passed each limit by (and a bit)."""
    def less(bound: float, peak: float, limit: float) -> float:
        if not limit or peak <= limit:
            return bound
        return bound - (peak - limit) - PLAN_MARGIN * limit
    speed = less(max(bounds.max_velocity, -bounds.min_velocity), found.velocity,
                 limits.max_velocity)
    low, high = max(bounds.min_velocity, -speed), min(bounds.max_velocity, speed)
    if limits.direction and found.backward > BACKWARD_TOLERANCE:
        if limits.direction > 0:
            low += found.backward
        else:
            high -= found.backward
    return Bounds(low, high,
                  less(bounds.max_acceleration, found.acceleration, limits.max_acceleration),
                  less(bounds.max_jerk, found.jerk, limits.max_jerk))
