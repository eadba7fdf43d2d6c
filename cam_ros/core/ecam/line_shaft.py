"""
The line shaft: one virtual master that every axis of a machine follows, so that no stop, loss,
fault, overspeed or master jump takes an axis off its cam or past its limits.

Every coupled axis is commanded y_i(theta_v). The virtual master theta_v is stepped in time, by
master samples and, while the master is silent, by the node's clock:

- following, locked: theta_v is the master's position (plus whole machine cycles, see shift) as
  long as the master's speed and acceleration are admissible (path_limits: within every axis's
  limits and stoppable from there); the commands are then exactly the cams at the master.
- following, filtered: where the master is not admissible (overspeed, a hard acceleration, a jump,
  the master turning back under a one-way axis) theta_v lags: it moves toward the master as hard as
  CHASE of the admissible accelerations allows, never faster than a stop allows, and locks again
  once it is within one step of admissible motion of the master's position and speed.
- halted (a master loss, a fault, a disengagement, an inactive node, axes moving onto their cams;
  `why` says which): theta_v decelerates as hard as the limits allow, on the path, to rest, and
  rests: a synchronized stop (MC_Halt of the line shaft); every axis stays on its cam, so it
  cannot collide. Halted before its first sample, theta_v starts at rest there.

Resynchronizing (follow() after a halt, a new master origin): theta_v's target is the master's
position taken modulo one machine cycle, ahead of theta_v when any axis is one-way, else the nearer
way; theta_v then catches up as above. While filtered, a lag of more than a cycle is taken modulo
the cycle too: the axes never unwind turns. A one-way machine's theta_v never moves backward.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Optional

from .master_tracker import MasterState
from .path_limits import PathLimits, WINDOW

#: A filtered theta_v approaches the master at this fraction of the admissible accelerations.
CHASE = 0.5
#: A filtered theta_v is never faster than this many times the faster of the master's speed
#: and the speed at cam_speed (where the axes rest, their limits bound nothing).
CATCH_UP = 3.0
#: Gain of the approach near the master, per substep: the lag falls by this fraction a step.
GAIN = 0.25
#: theta_v moves in substeps of at most SUBSTEP s and SUBSTEP_TRAVEL grid cells of travel (the
#: band taken on the safe side over a substep's travel), over at most LONGEST_STEP s of a step
#: (a node's clock steps it every few ms).
SUBSTEP, SUBSTEP_TRAVEL, LONGEST_STEP = 2e-3, WINDOW - 2.0, 0.25
#: Why theta_v is halted (said in ~/state and the diagnostics). MOVING: while axes move onto
#: their cams (ecam.moves, planned with theta_v at rest); any other reason replaces it.
LOST, DISENGAGED, INACTIVE = 'master lost', 'disengaged', 'inactive'
MOVING = 'axes moving onto their cams'
#: What theta_v does.
LOCKED, FILTERED, STOPPING, AT_REST = 'locked', 'filtered', 'stopping', 'at rest'


class Virtual(NamedTuple):
    """theta_v at one instant: stamp (ns), position (rad), speed (rad/s), acceleration."""

    stamp_ns: int
    theta: float
    omega: float
    alpha: float
    step: float  # travel since the previous instant (rad)


@dataclass
class _Target:
    """The master as last heard: its track plus shift (rad), speed, acceleration, stamp."""

    theta: float
    omega: float
    alpha: float
    stamp_ns: int


class LineShaft:
    """
    theta_v of a machine: stepped by master samples (master) and the clock (tick).

    limits: the machine's path limits; one_way: any axis has slave.direction.
    """

    def __init__(self, limits: PathLimits, one_way: bool):
        self.limits, self.one_way = limits, one_way
        self.state: Optional[Virtual] = None  # None: no master sample yet
        self.why = ''  # why halted ('' while following)
        self.shift = 0.0  # whole machine cycles added to the master's track
        self.filtered = 0  # steps at which theta_v was not the master
        self.locked = False  # theta_v is the master
        self._target: Optional[_Target] = None
        self._resync = False  # the next master sample sets shift again
        self._own = 0.0  # the master's own limit (path_limits.master_limit) during a stop

    # What it does --------------------------------------------------------------------------
    @property
    def following(self) -> bool:
        """Say whether theta_v follows the master (else it stops or rests: why says why)."""
        return not self.why

    @property
    def mode(self) -> str:
        """Return LOCKED, FILTERED, STOPPING or AT_REST."""
        if self.why:
            return AT_REST if self.state is None or self.state.omega == 0.0 else STOPPING
        return LOCKED if self.locked else FILTERED

    @property
    def lag(self) -> float:
        """Return how far theta_v is behind the master (rad; 0 when locked)."""
        if self.state is None or self._target is None:
            return 0.0
        return self._target.theta - self.state.theta

    # Commands --------------------------------------------------------------------------------
    def retarget(self, limits: PathLimits, one_way: bool) -> None:
        """Take a new design's limits (theta_v goes on from where it is)."""
        self.limits, self.one_way = limits, one_way

    def halt(self, why: str, idle: bool = False) -> None:
        """Stop theta_v within every limit, on the path, and rest (a synchronized stop); idle:
        no axis follows theta_v, so it rests where it is at once."""
        if not self.why and self.state is not None:
            self._own = self.limits.master_limit(self.state.omega)
        self.why = why if self.why in ('', MOVING) else self.why
        if idle and self.state is not None:
            self.state = self.state._replace(omega=0.0, alpha=0.0)
            self.locked = False

    def follow(self) -> None:
        """Follow the master again: catch up with its phase (modulo a cycle) within the limits."""
        if self.why:
            self.why, self._resync, self.locked = '', True, False

    def origin(self) -> None:
        """A new master origin: take its position modulo a cycle at the next sample."""
        self._resync, self.locked = True, False

    def master(self, sample: MasterState) -> Virtual:
        """Step theta_v to a master sample; return theta_v there."""
        target, state = self._target, self.state
        if target is None or self._resync:
            self._set_shift(sample.track)
            if state is not None and state.omega == 0.0:  # at rest: on the master's clock now
                self.state = state._replace(stamp_ns=sample.stamp_ns, step=0.0)
        self._target = _Target(sample.track + self.shift, sample.omega, sample.alpha,
                               sample.stamp_ns)
        return self._step(sample.stamp_ns)

    def tick(self, stamp_ns: int) -> Optional[Virtual]:
        """Step theta_v to a time with no master sample: the master is extrapolated at its
        last speed while followed (not before a sample after follow() or origin(): theta_v
        waits for one); None before any master sample."""
        target = self._target
        if target is None or self.state is None:
            return None
        if stamp_ns <= self.state.stamp_ns or self._resync:
            return self.state
        if self.following:
            elapsed = (stamp_ns - target.stamp_ns) * 1e-9
            self._target = _Target(target.theta + target.omega * elapsed, target.omega, 0.0,
                                   stamp_ns)
        return self._step(stamp_ns)

    # Steps ---------------------------------------------------------------------------------------
    def _set_shift(self, track: float) -> None:
        """Choose the whole cycles added to the track: the target nearest theta_v, ahead of it
        for a one-way machine."""
        self._resync = False
        state, cycle = self.state, self.limits.cycle
        if state is None:
            self.shift = 0.0
            return
        behind = (state.theta - track) / cycle
        turns = math.ceil(behind) if self.one_way else round(behind)
        self.shift = turns * cycle

    def _step(self, stamp_ns: int) -> Virtual:
        state, target = self.state, self._target
        assert target is not None
        if state is None:  # the first sample: theta_v starts on the master (at rest if halted)
            self.locked = self.following
            self.state = Virtual(stamp_ns, target.theta, target.omega, target.alpha, 0.0) \
                if self.following else Virtual(stamp_ns, target.theta, 0.0, 0.0, 0.0)
            return self.state
        dt = (stamp_ns - state.stamp_ns) * 1e-9
        if dt <= 0.0:
            return state
        admissible = self.following and self._admissible(target)
        if admissible and (self._near(state, target, dt, 1.0) if self.locked else
                           self._near(state, target, dt, CHASE)):
            self.locked = True
            self.state = Virtual(stamp_ns, target.theta, target.omega, target.alpha,
                                 target.theta - state.theta)
            return self.state
        self.locked = False
        if not self.following and state.omega == 0.0:  # at rest: it stays
            self.state = Virtual(stamp_ns, state.theta, 0.0, 0.0, 0.0)
            return self.state
        self.filtered += 1
        self._wrap_lag(state, target)
        theta, omega = state.theta, state.omega
        fastest = max(abs(omega), abs(target.omega), 1e-9)
        cell = self.limits.cycle / len(self.limits.theta)
        moving = min(dt, LONGEST_STEP)  # a master that jumps in time: at most this much
        count = math.ceil(moving / min(SUBSTEP, SUBSTEP_TRAVEL * cell / fastest))
        h = moving / count
        for left in range(count, 0, -1):
            theta, omega = self._substep(theta, omega, h, target, left * h + dt - moving)
        self.state = Virtual(stamp_ns, theta, omega, (omega - state.omega) / moving,
                             theta - state.theta)
        return self.state

    def _substep(self, theta: float, omega: float, h: float, target: _Target,
                 before: float) -> tuple[float, float]:
        """Move theta_v over h: toward the target (as it was `before` s before its stamp, at the
        substep's start) or, halted, to rest; return its position and speed."""
        limits = self.limits
        lower, upper = limits.band(theta, omega, omega * h)
        if lower > upper:  # at a joint where the bands part: the middle of the two
            lower = upper = 0.5 * (lower + upper)
        own = limits.master_limit(max(abs(omega), abs(target.omega))) if self.following \
            else self._own
        lower, upper = max(lower, -own), min(upper, own)
        if self.following:
            alpha = self._chase(theta, omega, h, target.theta - target.omega * before,
                                target.omega, lower, upper)
        else:
            alpha = lower if omega > 0.0 else upper if omega < 0.0 else 0.0
        end = omega + alpha * h
        if end * omega < 0.0 and (not self.following or self.one_way):  # at rest within h
            return theta - omega * omega / (2.0 * alpha), 0.0
        return theta + 0.5 * (omega + end) * h, end

    def _chase(self, theta: float, omega: float, h: float, goal: float, speed: float,
               lower: float, upper: float) -> float:
        """Return the acceleration toward the master (at goal, moving at speed) within [lower,
        upper]: the speed that closes the lag as a stop at CHASE of the band would (linear
        near 0), never past the master in one step, under the braking curve."""
        rate = CHASE * max(min(-lower, upper), 0.0)
        lag = goal - theta
        gain = GAIN / h
        linear = rate / (gain * gain)
        if abs(lag) <= linear:
            closing = gain * lag
        else:
            closing = math.copysign(math.sqrt(2.0 * rate * (abs(lag) - 0.5 * linear)), lag)
        closing = max(-abs(lag) / h, min(closing, abs(lag) / h))
        ahead = (abs(omega) + abs(closing)) * h
        limits = self.limits
        fastest = CATCH_UP * max(abs(speed), self.limits.nominal_speed)
        wanted = min(max(speed + closing, -fastest), fastest)
        if wanted > 0.0:
            wanted = min(wanted, limits.stoppable(theta, 1.0, ahead))
        else:
            wanted = 0.0 if self.one_way else max(wanted, -limits.stoppable(theta, -1.0, ahead))
        return min(max((wanted - omega) / h, lower), upper)

    def _near(self, state: Virtual, target: _Target, dt: float, share: float) -> bool:
        """Say whether theta_v may be the target after dt: within one step at share of the
        axes' band (locking: CHASE of its narrower side, and theta_v accelerating at no more than
        the rest; locked: 1, its wider side) of where theta_v's own motion takes it. A lock so
        moves the commands as such a step would; a master followed that jumps further is
        filtered."""
        expected = state.theta + 0.5 * (state.omega + target.omega) * dt
        speed = max(abs(state.omega), abs(target.omega))
        lower, upper = self.limits.band(expected, speed, target.theta - expected)
        if share < 1.0:  # a lock ends a catch-up: as a catch-up, within the master's own limit
            lower, upper = (max(lower, -self.limits.master_limit(speed)),
                            min(upper, self.limits.master_limit(speed)))
        band = max(min(-lower, upper) if share < 1.0 else max(-lower, upper), 0.0)
        rate = share * band
        if share < 1.0 and abs(state.alpha) > band - rate:  # a lock on top of a hard chase
            return False
        return abs(target.theta - expected) <= 0.5 * rate * dt * dt and \
            abs(target.omega - state.omega) <= rate * dt

    def _wrap_lag(self, state: Virtual, target: _Target) -> None:
        """Take a lag of more than a cycle modulo the cycle (never unwinding turns)."""
        cycle, lag = self.limits.cycle, target.theta - state.theta
        if abs(lag) >= cycle:
            turns = math.floor(lag / cycle) if lag > 0.0 else math.ceil(lag / cycle)
            self.shift -= turns * cycle
            target.theta -= turns * cycle

    def _admissible(self, target: _Target) -> bool:
        """Say whether the master's speed and acceleration are admissible at its position:
        stoppable, within the band of the grid (the safe side), forward if one-way."""
        if self.one_way and target.omega < 0.0:
            return False
        if abs(target.omega) > self.limits.stoppable(target.theta, target.omega):
            return False
        lower, upper = self.limits.band(target.theta, target.omega)
        return lower <= target.alpha <= upper
