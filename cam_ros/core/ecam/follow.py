"""
Run a slave on an electronic cam of its machine's line shaft: the first engagement (PLCopen
MC_CamIn start modes), one-shot cams, offset changes and design changes, all without a step in
the commands and within the axis's velocity, acceleration and direction (slave_limits, moves).

The master a follower sees is the machine's virtual master (line_shaft): master losses, new
master origins, disengaging, faults and an inactive node are stops and resynchronizations of that
master, during which every axis stays on its cam; a follower never sees them.

Start modes (master.engage_mode), used for ~/engage and at start-up:

- immediate: the slave takes the cam's value at once (a step unless it is already there; with
  slave limits set or on a rotary axis, a move as ramp's instead, since a step exceeds any limit).
- ramp: the slave moves from where it is onto its cam in time (moves.plan_move: ruckig, within
  its velocity, acceleration, jerk and direction; an axis without limits no faster and no harder
  than its cam at cam_speed), with the virtual master at rest: a move off the cam is planned and
  made only while the line shaft rests (needs_move; SlaveAxes halts it, checks the moves against
  the interference pairs and lets it catch up with the master once every axis is on its cam).
- next_cycle: the slave holds until the cam angle passes 0, where the cam must command the held
  position at rest (else the engagement is refused with the reason).

An engagement starts from the last command; before any command, or when rejoining after a
fault (rejoin), from the slave's reported position (slave.state_topic) when known, else none: the
slave then starts on the cam's own value. A rotary slave joins the cam at a whole number of turns
from where it is (slave_limits.join_turns), never by unwinding the turns it made.
A design change while the slave follows its cam takes over where the two designs share a
position and a velocity (Handover), without a step; where they share none (any offset or
master scaling change) it is a move in time from the old cam onto the new one (as an
engagement's: needs_move, with the line shaft at rest, checked against the pairs; refused, the
slave stays on the old cam). A one-shot cam (master.periodic false) holds the position it reaches
one master cycle (one cam turn) after its start: the end of profile.
A one-way slave whose commands would turn back (the line shaft never does: only a move's
round-off or a bug) stops within its acceleration limit (Stop) and holds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping, Optional

import numpy as np

from ..cam_angles import TWO_PI
from .slave_path import Held, SlavePath
from .handover import Handover
from .master import chain_rule, ElectronicCam, Setpoints
from .master_tracker import MasterState
from .moves import AxisState, MasterMotion, Move, MoveRequest, on_cam
from .slave_limits import AxisUnit, BACKWARD_TOLERANCE, CamPeaks, shifted, SlaveLimits
from .stop import Stop

IMMEDIATE, RAMP, NEXT_CYCLE = 'immediate', 'ramp', 'next_cycle'
#: What the slave is doing: the message of ~/state and of the engagement diagnostics.
HOLDING, WAITING_CYCLE, ENGAGING, ENGAGED = 'holding', 'waiting for the cycle start', \
    'engaging', 'engaged'
STOPPING, END_OF_PROFILE = 'stopping', 'end of profile'
RUNNING = (ENGAGING, ENGAGED)
#: next_cycle: largest difference (m or rad) between the held position and the cam at angle 0,
#: and largest |dy/dtheta| there (per rad of cam), for a start without a step.
NEXT_CYCLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class EngageConfig:
    """master.engage_mode, master.engage_distance_deg (in rad of master), master.periodic.

    nominal_speed is the master speed at cam_speed (rad/s): an axis without limits moves onto
    its cam no faster than its cam at it.
    """

    mode: str = RAMP
    distance: float = math.radians(30.0)
    periodic: bool = True
    nominal_speed: float = 0.0

    @classmethod
    def from_parameters(cls, values: Mapping[str, Any]) -> 'EngageConfig':
        """Read the (already checked) master.* parameters."""
        distance = math.radians(values['master.engage_distance_deg'])
        return cls(values['master.engage_mode'], distance, values['master.periodic'],
                   values['cam_speed'] * values['master.scaling'])


class Follower:
    """The slave's commands for each master sample, and what it is doing (phase, reason).

    unit says the slave's values in messages; events collects what the node logs
    (moves, refusals, stops), oldest first.
    """

    def __init__(self, cam: ElectronicCam, config: EngageConfig, engage: bool,
                 limits: SlaveLimits = SlaveLimits(), unit: AxisUnit = AxisUnit()):
        self.cam, self.config, self.limits, self.unit = cam, config, limits, unit
        self.wanted = engage  # ~/engage's last word (master.engage_on_start at first)
        self.phase, self.reason = HOLDING, '' if engage else 'not engaged'
        self.held: Optional[float] = None  # the last position commanded
        self.present: Optional[float] = None  # the slave's reported position
        self.handover: Optional[Handover] = None
        self.events: list[str] = []
        self._turns = 0  # whole slave turns the cam is followed at (rotary slaves)
        self._path: SlavePath = cam
        self._stop: Optional[Stop] = None
        self._move: Optional[Move] = None  # the move onto the cam under way
        self._move_ns = 0  # its start (the virtual master's stamp)
        self._changing: Optional[ElectronicCam] = None  # an offset change's cam, to move onto
        self._requested: Optional[ElectronicCam] = None  # the cam of the last move_request
        self._peaks = (cam, CamPeaks.of(cam))
        self._start = 0.0  # master track where the cam run began
        self._last: Optional[MasterState] = None  # the previous sample
        self._velocity = 0.0  # the last velocity commanded
        self._pending = engage  # the next sample starts an engagement

    @property
    def needs_move(self) -> bool:
        """Say whether a move off the cam is due (an engagement's or an offset change's): the
        line shaft must rest."""
        if not self.wanted or self._origin() is None:
            return False
        mode = self.config.mode
        return self._changing is not None or self._pending and (
            mode == RAMP or mode == IMMEDIATE and bool(self.limits.limited or self.limits.turn))

    @property
    def changing(self) -> bool:
        """Say whether an offset change waits to move the slave onto its new cam (it follows
        the old one until then)."""
        return self._changing is not None

    @property
    def joined(self) -> ElectronicCam:
        """Return the cam on the whole slave turns the slave follows it at."""
        return shifted(self.cam, self._turns, self.limits)

    @property
    def move(self) -> Optional[Move]:
        """Return the move onto the cam under way (None: none)."""
        return self._move

    def during(self, master: MasterMotion) -> Move:
        """Return what the slave does while others move onto their cams: its own move, its
        cam, or the position it holds."""
        if self._move is not None:
            return self._move
        origin = self._origin()
        if self.phase in RUNNING or origin is None:
            return on_cam(self.joined, self.limits, master)
        return on_cam(Held(origin), self.limits, master)

    @property
    def status(self) -> str:
        """Say what the slave is doing, with why it holds."""
        return f'{self.phase}: {self.reason}' if self.reason else self.phase

    def engage(self) -> tuple[bool, str]:
        """Engage at the next master sample (if not engaged); return success and a message.

        Disengaging is the machine's: its line shaft stops every axis on its cam."""
        self.wanted = True
        if self.phase in (ENGAGING, ENGAGED, WAITING_CYCLE):
            return True, f'already {self.phase}'
        problem = self._next_cycle_problem(self._origin())
        if problem:
            self.phase, self.reason = HOLDING, problem
            return False, problem
        self._pending = True
        if self.phase != STOPPING:
            self.phase, self.reason = HOLDING, ''
        return True, f'engaging ({self.config.mode}) at the next master message'

    def rejoin(self) -> None:
        """Engage again from the reported position (a stalled axis after a fault): the first
        command is where the drive is, then a move onto the cam."""
        if self.present is None or self._move is not None:
            return
        self.held, self._velocity = None, 0.0
        self.phase, self.reason, self._pending = HOLDING, '', True
        self._path = self.joined

    def move_request(self, master: MasterMotion) -> MoveRequest:
        """Return the move due (needs_move) with the virtual master resting as master, to plan
        (MoveRequest.plan) here or elsewhere; begin_move then makes it."""
        origin = self._origin()
        if self._changing is not None:  # from its old cam where theta_v rests
            origin = float(self._path.derivatives(master.theta).y)
        assert origin is not None
        self._requested = self._changing or self.cam  # (peaks: the same for any offsets)
        return MoveRequest(self._requested, self.limits, AxisState(origin), master,
                           self.config.nominal_speed, self.unit, self._peaks[1])

    def begin_move(self, found: Move | str, state: MasterState) -> None:
        """Begin a planned (and checked) move at this sample, or say why not: an engagement
        holds, an offset change leaves the slave on its old cam. A move planned for a cam
        changed again since is not begun (needs_move stays: planned again)."""
        changing = self._changing
        if self._requested is not (changing or self.cam):
            return
        self._changing = None
        if changing is None:
            self._begin_at(state)
        elif isinstance(found, str):
            self.events.append(f'offset change refused, the slave stays on its old cam: {found}')
            return
        else:
            self._set_cam(changing)
        if isinstance(found, str):
            self.phase, self.reason = HOLDING, found
            self.events.append(f'not engaged: {found}')
            return
        self._turns, self._path = found.turns, found.cam
        if found.duration == 0.0:
            return
        self.phase, self._move, self._move_ns = ENGAGING, found, state.stamp_ns
        gap = abs(found.start.position - float(found.cam.derivatives(state.track).y))
        what = 'its new cam' if changing is not None else 'its cam'
        self.events.append(
            f'{"immediate engagement moves" if self.config.mode == IMMEDIATE else "moves"} '
            f'onto {what}: {self.unit.say(gap)} in {found.duration:.6g} s'
            + (f' after {found.delay:.6g} s' if found.delay else ''))

    def change(self, cam: ElectronicCam, config: EngageConfig,
               limits: Optional[SlaveLimits] = None) -> str:
        """Take a new design, start modes and limits; return how the cam changes."""
        old, self.config = self.cam, config
        if limits is not None:
            self.limits = limits  # (the cam's peaks are its own, whatever the limits)
        self.handover = self._changing = None  # (a change not begun yet is replaced)
        if self.phase not in RUNNING or self._last is None:
            self._set_cam(cam)
            self._path = cam
            if self.phase == WAITING_CYCLE:
                self.phase, self._pending = HOLDING, True  # checked again on the new cam
            return 'applied at once (not following the master)'
        if old.program == cam.program and old.mapping == cam.mapping:
            return 'cam unchanged'
        if self._move is not None:
            return 'refused, the slave runs on the old cam: it is moving onto it (change it ' \
                'again once engaged)'
        handover = Handover(self.joined, shifted(cam, self._turns, self.limits))
        if len(handover.intervals):
            self.handover = handover
            return f'pending: {handover.describe()}'
        self._changing = cam
        return 'moves onto the new cam in time, with the line shaft at rest'

    def command(self, state: MasterState) -> Optional[Setpoints]:
        """Return the setpoints for a master sample (None: nothing commanded yet, none due)."""
        track = state.track
        if self.phase == STOPPING:
            return self._stopping(state)
        if self._pending and self.wanted:
            if not self.needs_move:  # a move is its machine's to plan (SlaveAxes)
                self._begin(state)
        elif self.phase == WAITING_CYCLE:
            self._wait_for_cycle(track)
        elif self.phase in RUNNING:
            self._run(state)
        angle = self.cam.mapping.cam_angle(track)
        if self.phase in RUNNING:
            point = chain_rule(angle, self._path.derivatives(track), state.omega, state.alpha)
            if self._move is not None:
                point = self._moved(point, state, 0.0)
            backward = BACKWARD_TOLERANCE if self._move else 0.0  # a move's round-off
            if self.limits.direction * point.velocity < -backward:  # the master turned back
                self._begin_stop('the master turned back under slave.direction')
                return self._stopping(state)
        else:
            origin = self._origin()
            self._last = state
            if origin is None:
                return None
            point = chain_rule(angle, Held(origin).derivatives(track), 0.0, 0.0)
        self._last = state
        self.held, self._velocity = float(point.position), float(point.velocity)
        return point

    def steady(self, state: MasterState) -> Optional[ElectronicCam]:
        """
        Return the cam whose setpoints alone are this sample's command, or None.

        That is the cam the slave is engaged on (on its whole turns) when nothing else is due
        at the sample: no engagement to begin, move, pending design, stop or one-shot end.
        Its setpoints, unless they move
        against slave.direction, are what command() returns; taking them with took() leaves the
        follower as command() does. None: call command().
        """
        path = self._path
        if self.phase != ENGAGED or self.handover is not None or (
                self._pending and self.wanted) or not isinstance(path, ElectronicCam):
            return None
        if not self.config.periodic and abs(state.track - self._start) >= \
                TWO_PI * self.cam.mapping.master_scaling:
            return None
        return path

    def took(self, state: MasterState, position: float, velocity: float) -> None:
        """Note the position and velocity commanded at a sample from steady()'s cam."""
        self._last, self.held, self._velocity = state, position, velocity

    def ahead(self, state: MasterState, times: np.ndarray) -> Setpoints:
        """Return the setpoints at times (s) from now if the master keeps its speed."""
        master = state.track + state.omega * times
        angle = self.cam.mapping.cam_angle(master)
        if self._stop is not None:
            position, velocity, acceleration = self._stop.at(
                (state.stamp_ns - self._stop.stamp_ns) * 1e-9 + times)
            return Setpoints(angle, position, velocity, acceleration, np.zeros_like(times))
        running = self.phase in RUNNING
        path = self._path if running else Held(self.held if self.held is not None else 0.0)
        point = chain_rule(angle, path.derivatives(master), state.omega if running else 0.0, 0.0)
        return self._moved(point, state, times) if running and self._move else point

    def _moved(self, point: Setpoints, state: MasterState, ahead: Any) -> Setpoints:
        """Add the move's offset from the cam (moves.Move.relative) at ahead s after state."""
        assert self._move is not None
        offsets: tuple[Any, ...] = self._move.relative(
            (state.stamp_ns - self._move_ns) * 1e-9 + ahead)
        if isinstance(point.position, float):  # one sample: floats, as chain_rule's
            offsets = tuple(float(np.asarray(value).reshape(-1)[0]) for value in offsets)
        e, de, dde, d3e = offsets
        return Setpoints(point.cam_angle, point.position + e, point.velocity + de,
                         point.acceleration + dde, point.jerk + d3e)

    def _origin(self) -> Optional[float]:
        """Return where the slave is held: the last command, else its reported position."""
        return self.held if self.held is not None else self.present

    def _set_cam(self, cam: ElectronicCam) -> None:
        """Follow a new design (its peaks, over a cycle whatever the offsets, are refined again
        only when its motion differs)."""
        old = self._peaks[0]
        same = old.program == cam.program and replace(
            old.mapping, slave_offset=0.0, master_offset=0.0) == replace(
                cam.mapping, slave_offset=0.0, master_offset=0.0)
        self.cam = cam
        if not same:
            self._peaks = (cam, CamPeaks.of(cam))

    def _next_cycle_problem(self, origin: Optional[float]) -> str:
        """Say why next_cycle cannot start from origin ('' if it can, or for another mode)."""
        if self.config.mode != NEXT_CYCLE or origin is None:
            return ''
        y, slope = (float(value) for value in self.cam.slave(0.0))
        if self.limits.turn:
            y += self.limits.turn * round((origin - y) / self.limits.turn)
        if abs(y - origin) > NEXT_CYCLE_TOLERANCE or abs(slope) > NEXT_CYCLE_TOLERANCE:
            return (f'next_cycle cannot engage: at cam angle 0 the cam commands '
                    f'{self.unit.say(y)} at dy/dtheta {slope:.6g}, the slave holds '
                    f'{self.unit.say(origin)} at rest (use ramp)')
        return ''

    def _begin_at(self, state: MasterState) -> None:
        """Engage at this master sample: on the cam from here (a one-shot cam's start)."""
        self._pending, self.reason = False, ''
        self.phase, self._path, self._start = ENGAGED, self.joined, state.track

    def _begin(self, state: MasterState) -> None:
        """Start an engagement without a move at this master sample (see needs_move)."""
        origin = self._origin()
        self._begin_at(state)
        if origin is None or self.config.mode != NEXT_CYCLE:
            return
        problem = self._next_cycle_problem(origin)
        self.phase, self.reason = (HOLDING, problem) if problem else (WAITING_CYCLE, '')
        if not problem and self.limits.turn:
            self._turns = round((origin - float(self.cam.slave(0.0)[0])) / self.limits.turn)

    def _begin_stop(self, why: str) -> None:
        """Stop the slave from its last command within slave.max_acceleration, then hold."""
        last = self._last
        assert last is not None and self.held is not None
        self._stop = Stop(last.stamp_ns, self.held, self._velocity, self.limits.max_acceleration)
        self.phase, self.reason, self._pending = STOPPING, why, self.wanted
        self.handover = None
        self.events.append(f'stopping: {why} (from {self.unit.say(self._velocity, "/s")}, at '
                           f'rest in {self._stop.duration:.6g} s at '
                           f'{self.unit.say(self._stop.rest)})')

    def _stopping(self, state: MasterState) -> Setpoints:
        """Return the stop's setpoints at a sample; hold once the slave is at rest."""
        stop = self._stop
        assert stop is not None
        position, velocity, acceleration = stop.at((state.stamp_ns - stop.stamp_ns) * 1e-9)
        if stop.done(state.stamp_ns):
            self._stop, self.phase = None, HOLDING
        self._last, self.held, self._velocity = state, float(position), float(velocity)
        return Setpoints(float(self.cam.mapping.cam_angle(state.track)), float(position),
                         float(velocity), float(acceleration), 0.0)

    def _wait_for_cycle(self, track: float) -> None:
        """Engage where the cam angle passed 0 since the previous sample."""
        if self._last is None:
            return
        mapping = self.cam.mapping
        turns = np.floor(mapping.turns([self._last.track, track]) / TWO_PI)
        if turns[0] != turns[1]:
            crossed = max(turns) * TWO_PI * mapping.master_scaling + mapping.master_offset
            self.phase, self._path, self._start = ENGAGED, self.joined, float(crossed)

    def _run(self, state: MasterState) -> None:
        """Follow the path: finish a move, hand a design over, end a one-shot cam."""
        track = state.track
        handover = self.handover
        if handover is not None and handover.due(track, state.step):
            self._set_cam(shifted(handover.new, -self._turns, self.limits))
            self._path, self.handover = handover.new, None
        move = self._move
        if move is not None and (state.stamp_ns - self._move_ns) * 1e-9 >= move.duration:
            self._move, self.phase = None, ENGAGED
        cycle = TWO_PI * self.cam.mapping.master_scaling
        if not self.config.periodic and abs(track - self._start) >= cycle:
            end = self._start + math.copysign(cycle, track - self._start)
            self.held = float(self._path.derivatives(end).y)
            self.phase, self.reason = END_OF_PROFILE, ''
