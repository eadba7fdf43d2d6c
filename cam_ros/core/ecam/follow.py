"""
Run a slave on an electronic cam: engage and disengage (PLCopen MC_CamIn start modes), master
loss, one-shot cams, offset changes and design changes, all without a step in the commands.

Start modes (master.engage_mode), used alike for ~/engage, at start-up and after a master loss:

- immediate: the slave takes the cam's value at once (a step unless it is already there).
- ramp: the slave leaves its held position on a Blend onto the cam over master.engage_distance_deg
  of master travel (position, velocity and acceleration continuous at both ends).
- next_cycle: the slave holds until the cam angle passes 0, where the cam must command the held
  position at rest (else the engagement is refused with the reason).

The held position is the last command; before any command, the slave's reported position
(slave.state_topic) when known, else none: the slave then starts on the cam's own value.
Offset changes blend from the old cam to the new one over the same distance; other design changes
wait for a place the two designs share (Handover). A one-shot cam (master.periodic false) holds
the position it reaches one master cycle (one cam turn) after its start: the end of profile.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping, Optional

import numpy as np

from ..cam_angles import TWO_PI
from .engage import Blend, Held, SlavePath
from .handover import Handover
from .master import chain_rule, ElectronicCam, MasterState, Setpoints

IMMEDIATE, RAMP, NEXT_CYCLE = 'immediate', 'ramp', 'next_cycle'
#: What the slave is doing: the message of ~/state and of the engagement diagnostics.
HOLDING, WAITING_CYCLE, ENGAGING, ENGAGED = 'holding', 'waiting for the cycle start', \
    'engaging', 'engaged'
END_OF_PROFILE = 'end of profile'
#: next_cycle: largest difference (m or rad) between the held position and the cam at angle 0,
#: and largest |dy/dtheta| there (per rad of cam), for a start without a step.
NEXT_CYCLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class EngageConfig:
    """master.engage_mode, master.engage_distance_deg (in rad of master), master.periodic."""

    mode: str = RAMP
    distance: float = math.radians(30.0)
    periodic: bool = True

    @classmethod
    def from_parameters(cls, values: Mapping[str, Any]) -> 'EngageConfig':
        """Read the (already checked) master.* parameters."""
        distance = math.radians(values['master.engage_distance_deg'])
        return cls(values['master.engage_mode'], distance, values['master.periodic'])


class Follower:
    """The slave's commands for each master sample, and what it is doing (phase, reason)."""

    def __init__(self, cam: ElectronicCam, config: EngageConfig, engage: bool):
        self.cam, self.config = cam, config
        self.wanted = engage  # ~/engage's last word (master.engage_on_start at first)
        self.phase, self.reason = HOLDING, '' if engage else 'not engaged'
        self.held: Optional[float] = None  # the last position commanded
        self.present: Optional[float] = None  # the slave's reported position
        self.handover: Optional[Handover] = None
        self._path: SlavePath = cam
        self._start = 0.0  # master track where the cam run began
        self._last: Optional[float] = None  # master track of the previous sample
        self._pending = engage  # the next sample starts an engagement

    @property
    def status(self) -> str:
        """Say what the slave is doing, with why it holds."""
        return f'{self.phase}: {self.reason}' if self.reason else self.phase

    def engage(self, on: bool) -> tuple[bool, str]:
        """Engage (at the next master sample) or disengage (hold); return success and a message."""
        if not on:
            self.wanted = self._pending = False
            self.phase, self.reason, self.handover = HOLDING, 'disengaged', None
            return True, f'disengaged: holding at {self.held:.9g}' if self.held is not None \
                else 'disengaged'
        self.wanted = True
        if self.phase in (ENGAGING, ENGAGED, WAITING_CYCLE):
            return True, f'already {self.phase}'
        problem = self._next_cycle_problem(self._origin())
        if problem:
            self.phase, self.reason = HOLDING, problem
            return False, problem
        self._pending, self.phase, self.reason = True, HOLDING, ''
        return True, f'engaging ({self.config.mode}) at the next master message'

    def lose(self) -> None:
        """The master is lost: hold; engage again in the same mode when it returns."""
        self._last = None
        if self.phase in (ENGAGING, ENGAGED):
            self.phase, self.reason, self.handover = HOLDING, 'master lost', None
            self._pending = True

    def change(self, cam: ElectronicCam, config: EngageConfig) -> str:
        """Take a new design and start modes; return how the cam changes."""
        old, self.config = self.cam, config
        self.cam, self.handover = cam, None
        if self.phase not in (ENGAGING, ENGAGED) or self._last is None:
            self._path = cam
            if self.phase == WAITING_CYCLE:
                self.phase, self._pending = HOLDING, True  # checked again on the new cam
            return 'applied at once (not following the master)'
        same = replace(old.mapping, master_offset=0.0, slave_offset=0.0) == replace(
            cam.mapping, master_offset=0.0, slave_offset=0.0) and old.program == cam.program
        if same or self.phase == ENGAGING:
            self._path, self.phase = Blend(self._path, cam, self._last, config.distance), ENGAGING
            return f'blended over {math.degrees(config.distance):g} deg of master'
        self.cam, self.handover = old, Handover(old, cam)
        return f'pending: {self.handover.describe()}'

    def command(self, state: MasterState) -> Optional[Setpoints]:
        """Return the setpoints for a master sample (None: nothing commanded yet, none due)."""
        track = state.track
        if self._pending and self.wanted:
            self._begin(track)
        elif self.phase == WAITING_CYCLE:
            self._wait_for_cycle(track)
        elif self.phase in (ENGAGING, ENGAGED):
            self._run(state)
        self._last = track
        angle = self.cam.mapping.cam_angle(track)
        if self.phase in (ENGAGING, ENGAGED):
            point = chain_rule(angle, self._path.derivatives(track), state.omega, state.alpha)
        else:
            origin = self._origin()
            if origin is None:
                return None
            point = chain_rule(angle, Held(origin).derivatives(track), 0.0, 0.0)
        self.held = float(point.position)
        return point

    def ahead(self, state: MasterState, times: np.ndarray) -> Setpoints:
        """Return the setpoints at times (s) from now if the master keeps its speed."""
        master = state.track + state.omega * times
        running = self.phase in (ENGAGING, ENGAGED)
        path = self._path if running else Held(self.held if self.held is not None else 0.0)
        return chain_rule(self.cam.mapping.cam_angle(master), path.derivatives(master),
                          state.omega if running else 0.0, 0.0)

    def _origin(self) -> Optional[float]:
        """Return where the slave is held: the last command, else its reported position."""
        return self.held if self.held is not None else self.present

    def _next_cycle_problem(self, origin: Optional[float]) -> str:
        """Say why next_cycle cannot start from origin ('' if it can, or for another mode)."""
        if self.config.mode != NEXT_CYCLE or origin is None:
            return ''
        y, slope = (float(value) for value in self.cam.slave(0.0))
        if abs(y - origin) > NEXT_CYCLE_TOLERANCE or abs(slope) > NEXT_CYCLE_TOLERANCE:
            return (f'next_cycle cannot engage: at cam angle 0 the cam commands {y:.9g} at '
                    f'dy/dtheta {slope:.6g}, the slave holds {origin:.9g} at rest (use ramp)')
        return ''

    def _begin(self, track: float) -> None:
        """Start an engagement at this master sample in the configured mode."""
        self._pending, self.reason = False, ''
        origin, mode = self._origin(), self.config.mode
        self.phase, self._path, self._start = ENGAGED, self.cam, track
        if origin is None or mode == IMMEDIATE:
            return
        if mode == RAMP:
            self.phase = ENGAGING
            self._path = Blend(Held(origin), self.cam, track, self.config.distance)
            return
        problem = self._next_cycle_problem(origin)
        self.phase, self.reason = (HOLDING, problem) if problem else (WAITING_CYCLE, '')

    def _wait_for_cycle(self, track: float) -> None:
        """Engage where the cam angle passed 0 since the previous sample."""
        if self._last is None:
            return
        mapping = self.cam.mapping
        turns = np.floor(mapping.turns([self._last, track]) / TWO_PI)
        if turns[0] != turns[1]:
            crossed = max(turns) * TWO_PI * mapping.master_scaling + mapping.master_offset
            self.phase, self._path, self._start = ENGAGED, self.cam, float(crossed)

    def _run(self, state: MasterState) -> None:
        """Follow the path: finish a blend, hand a design over, end a one-shot cam."""
        track = state.track
        if self.handover is not None and self.handover.due(track, state.step, state.omega):
            self.cam = self._path = self.handover.new
            self.handover = None
        if isinstance(self._path, Blend) and self._path.done(track):
            self._path, self.phase = self._path.end, ENGAGED
        cycle = TWO_PI * self.cam.mapping.master_scaling
        if not self.config.periodic and abs(track - self._start) >= cycle:
            end = self._start + math.copysign(cycle, track - self._start)
            self.held = float(self._path.derivatives(end).y)
            self.phase, self.reason = END_OF_PROFILE, ''
