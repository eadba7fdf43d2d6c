"""
Take master samples: check them, follow the master over turns, dropouts and restarts, estimate
its speed, and watch for silence.

Master samples come with integer-nanosecond stamps. omega is the message's velocity when it has
one; otherwise, like alpha, it is estimated by the least-squares quadratic over the positions of
the last master.velocity_window seconds, at least the last three (speed_estimate: exact for a
master at constant acceleration, any spacing of the stamps; a window averages stamp jitter, and
the stamps of a master on a fixed cycle are de-jittered by a delay-locked loop, cycle_clock).

The cam angle is taken from the track, the master's position followed continuously: the first
sample's position, then each sample's travel added. The travel since the previous sample is

- for a multi-turn master (one that has sent a position outside [-pi, 2 pi]): the difference of
  the positions, exactly;
- for an encoder that wraps at 2 pi: the representative of that difference (mod 2 pi) nearest
  the travel predicted from the last speed over the elapsed time. Between messages that is the
  step within half a turn; after a dropout it is the turn nearest the prediction, so a shaft
  that crossed 0 unseen goes on forward.

A travel that no plausible motion explains is a new master origin (a restart from 0, a
re-homing): one off the travel predicted from the last speed by more than JUMP_FACTOR times what
master.max_speed allows over the elapsed time (without it: the larger of the last speed and
NOMINAL_FACTOR times the master speed at cam_speed), judged once the speed is known again after
a loss or an origin (KNOWN_SPEED samples). The sample says so (origin), the estimates start
afresh and the tracker counts it; the follower stops, holds and engages again from where the
slave is, never by unwinding the turns it made.
"""
from __future__ import annotations

import math
from collections import Counter
from typing import NamedTuple, Sequence

from ..cam_angles import TWO_PI
from .speed_estimate import SpeedEstimator

#: Status of the master: none yet, messages arriving, silent for half the timeout, timed out.
WAITING, OK, STALE, LOST = 'waiting', 'ok', 'stale', 'lost'
#: Why a master message was dropped (the diagnostics count each).
NO_JOINT, NOT_FINITE = 'no master joint', 'not finite'
LENGTHS, BACKWARDS = 'mismatched array lengths', 'stamp not after the previous'
#: A travel off its prediction by more than JUMP_FACTOR times the plausible speed times the
#: elapsed time is a new origin, judged once the estimates have KNOWN_SPEED samples (the first
#: after a loss or an origin is taken as it comes: the speed is not known yet). Without
#: master.max_speed the plausible speed is at least NOMINAL_FACTOR times the speed at cam_speed.
JUMP_FACTOR, KNOWN_SPEED, NOMINAL_FACTOR = 2.0, 3, 10.0


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

    position is the master's as sent; track is the same position followed continuously (see the
    module docstring), which the cam angle is taken from, so an encoder wrapping at 2 pi gives
    the commands of a multi-turn master for any master.scaling.
    """

    stamp_ns: int
    position: float
    omega: float
    alpha: float
    step: float  # travel since the previous sample (rad); 0 for the first, after a loss or jump
    track: float  # continuous master position (rad)
    origin: bool = False  # a new master origin: a travel no plausible motion explains


class MasterTracker:
    """
    Accept master samples, estimate speed and acceleration, and watch for silence.

    `accept` checks the stamp and returns the MasterState; `check(now_ns)` moves the status to
    STALE after half the timeout without a message and to LOST after the timeout (which ends an
    overspeed), returning the new status once when it changes. A sample after LOST or at a new
    origin starts the estimates afresh. max_speed is the speed to warn above; bound the
    master.max_speed (0: none) and nominal the master speed at cam_speed, which set the
    plausible speed (inf: no origin is ever new).
    """

    def __init__(self, timeout_ns: int, max_speed: float = math.inf, window_ns: int = 0,
                 bound: float = 0.0, nominal: float = math.inf):
        self.timeout_ns = int(timeout_ns)
        self.max_speed = float(max_speed)
        self.bound, self.nominal = float(bound), float(nominal)
        self.speed = SpeedEstimator(window_ns)  # window_ns 0: the last three samples
        self.status = WAITING
        self.dropped: Counter[str] = Counter()
        self.accepted = 0
        self.jumps = 0  # new origins
        self.jump, self.jump_time = 0.0, 0.0  # the last new origin's travel (rad) and time (s)
        self.overspeed = False
        self.multi_turn = False
        self.last: MasterState | None = None
        self._run = 0  # samples since the estimates started afresh
        self._received_ns = 0

    def accept(self, stamp_ns: int, position: float, velocity: float | None,
               received_ns: int) -> MasterState:
        """Return the state of a new sample; raise BadMaster(BACKWARDS) for an old stamp."""
        last = self.last
        if last is not None and stamp_ns <= last.stamp_ns:
            raise BadMaster(BACKWARDS)
        self.multi_turn = self.multi_turn or not -math.pi <= position <= TWO_PI
        if last is None:
            state = estimate(None, self.speed, stamp_ns, position, velocity, position)
        else:
            elapsed = (stamp_ns - last.stamp_ns) * 1e-9
            travel = self._travel(last, position, elapsed)
            predicted = last.omega * elapsed
            origin = self._run >= KNOWN_SPEED and \
                abs(travel - predicted) > JUMP_FACTOR * self.plausible_speed() * elapsed
            fresh = origin or self.status == LOST
            if fresh:
                self.speed.reset()
                self._run = 0
            if origin:
                self.jumps, self.jump, self.jump_time = self.jumps + 1, travel, elapsed
            state = estimate(None if fresh else last, self.speed, stamp_ns, position, velocity,
                             last.track + travel)._replace(origin=origin)
        self.last, self._received_ns, self.status = state, received_ns, OK
        self.accepted, self._run = self.accepted + 1, self._run + 1
        self.overspeed = abs(state.omega) > self.max_speed
        return state

    def plausible_speed(self) -> float:
        """Return the fastest master speed (rad/s) that explains a travel (see the module)."""
        if self.bound:
            return self.bound
        return max(abs(self.last.omega) if self.last else 0.0, NOMINAL_FACTOR * self.nominal)

    def _travel(self, last: MasterState, position: float, elapsed: float) -> float:
        """Return the master's travel from the last sample (rad; see the module docstring)."""
        difference = position - last.position
        if self.multi_turn:
            return difference
        predicted = last.omega * elapsed
        return predicted + math.remainder(difference - predicted, TWO_PI)

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
             position: float, velocity: float | None, track: float) -> MasterState:
    """
    Return the state at a new sample on the track given, from the previous sample (None: the
    first, the first after a loss or at a new origin) and the estimator of the samples before,
    which takes the new one.

    A given velocity is taken as omega, and alpha = (omega - omega_before)/h1 with h1 the last
    stamp interval; otherwise both come from the estimator.
    """
    speed.add(stamp_ns, track)
    if previous is None:
        return MasterState(stamp_ns, position, velocity or 0.0, 0.0, 0.0, track)
    step = track - previous.track
    if velocity is not None:
        h1 = (stamp_ns - previous.stamp_ns) * 1e-9
        return MasterState(stamp_ns, position, velocity, (velocity - previous.omega) / h1, step,
                           track)
    omega, alpha = speed.estimate()
    return MasterState(stamp_ns, position, omega, alpha, step, track)
