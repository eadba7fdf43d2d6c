"""
The slave axes of one master, commanded together: one Follower per axis, one line shaft for all.

A machine of N axes is the general case and a single cam is N = 1 (its joint named follower).
Every master sample steps the machine's virtual master (line_shaft: within every axis's limits,
from path_limits), and every axis follows it; commands go out only when every axis has one,
since a forward_command_controller takes all its joints in one message. Disengaging, a master
loss, a fault and deactivating halt the line shaft: a synchronized stop on the cams (a machine
starts and stops as one, and never leaves its cams for it); while the master is silent the node's
clock steps it (tick).

An engagement that moves an axis off its cam (Follower.needs_move: from where its drive is),
and an offset change (from the old cam onto the new), is made with the line shaft at rest: it
halts (MOVING; at once where no axis follows it); once it rests the moves due are planned
together (engagement.plan_engagement: each axis's move, checked against the machine's
interference pairs with every other axis on its cam or where it holds, by check, given by
whoever knows the machine), inline or through submit (a concurrent.futures submit: off the
master thread, the axes holding meanwhile), and begun at the first step after; once every axis
is on its cam the line shaft catches up with the master. Halted for another reason (a loss, a
fault, disengaged, inactive), the moves wait until it is to follow again.

From COMPILED_FROM axes on, a sample at which every axis is steady (Follower.steady: engaged on
its cam with nothing else due) is computed for all axes in one NumPy pass from compiled tables
(compiled.py: refined to the exact program's rounding, never worse than ACCURACY of each axis's
stroke and peak velocity); any other sample, and every sample of fewer axes, takes each
follower's exact path. An axis with slave.direction whose tabled velocity is within the table's
error of moving backward sends the sample to the exact path, which decides the stop. A tabled
sample's commands are noted in the followers (Follower.took) when they are next looked at
(SlaveAxes.followers, and every method here), so the node sends them first; nothing reads a
follower but through them.
"""
from __future__ import annotations

from concurrent.futures import Future
from typing import Any, Callable, NamedTuple, Optional, Sequence

import numpy as np

from ..motion.program import MotionProgram
from .compiled import CompiledCams, compile_program, ProgramTable
from .follow import END_OF_PROFILE, ENGAGED, Follower, RUNNING, WAITING_CYCLE
from .line_shaft import AT_REST, DISENGAGED, LineShaft, MOVING, Virtual
from .master import ElectronicCam, Setpoints
from .master_tracker import MasterState
from .engagement import CheckMoves, plan_engagement
from .moves import MasterMotion
from .path_limits import PathLimits

#: Fewest axes whose steady commands come from the compiled tables: one pass costs about as much
#: as 1.5 axes' exact paths (about 11 us against 7 us an axis; benchmarks/machine.py).
COMPILED_FROM = 2
#: The velocity error taken for a tabled command near backward under slave.direction: this
#: many times the table's refined largest.
DIRECTION_MARGIN = 2.0

#: What an axis does while it follows the virtual master.
FOLLOWING = (*RUNNING, WAITING_CYCLE)
#: concurrent.futures' Executor.submit: runs fn(*args) elsewhere, returns its Future.
Submit = Callable[..., 'Future[Any]']


def by_axis(names: Sequence[str], said: Sequence[str]) -> str:
    """Join what each axis said, each after its name (just the text when one axis said it)."""
    if len(said) <= 1:
        return ''.join(said)
    return '; '.join(f'{name}: {text}' for name, text in zip(names, said))


class Commands(NamedTuple):
    """Every axis's position and velocity command at one master sample, in the axes' order."""

    position: list[float]
    velocity: list[float]


class SlaveAxes:
    """Followers by axis name, each with its command interface ('position' or 'velocity')."""

    def __init__(self, names: Sequence[str], followers: Sequence[Follower],
                 interfaces: Sequence[str], check: Optional[CheckMoves] = None,
                 submit: Optional[Submit] = None):
        self.names, self._followers = tuple(names), list(followers)
        self.check, self._submit = check, submit
        self._planning: Optional['Future[Any]'] = None  # the moves due, being planned
        # A tabled sample's commands, noted in the followers when they are next looked at:
        # after the node has sent them (see followers).
        self._unnoted: Optional[tuple[MasterState, Commands]] = None
        self.interfaces = list(interfaces)
        self._tables: dict[MotionProgram, ProgramTable] = {}
        self._steady_cams: Optional[list[Optional[ElectronicCam]]] = None
        self._compiled: Optional[CompiledCams] = None
        if len(self.names) >= COMPILED_FROM:
            self._tables = {program: compile_program(program) for program in
                            {follower.cam.program for follower in self.followers}}
        self.shaft = LineShaft(self.path_limits(), any(f.limits.direction for f in followers))
        # A new design's path limits, taken once every axis is on its new cam (see retarget).
        self._retarget: Optional[tuple[PathLimits, bool]] = None
        self.virtual: Optional[MasterState] = None  # what the followers last followed

    def __len__(self) -> int:
        return len(self.names)

    @property
    def followers(self) -> list[Follower]:
        """Return the followers, each holding the last command (a tabled one noted first)."""
        if self._unnoted is not None:
            (state, commands), self._unnoted = self._unnoted, None
            for follower, position, velocity in zip(self._followers, *commands):
                follower.took(state, position, velocity)
        return self._followers

    def path_limits(self) -> PathLimits:
        """Return the master limits of the followers' cams and limits (a design change: call it
        off the master thread, then give them to shaft.limits)."""
        config = self._followers[0].config
        return PathLimits.of([follower.cam for follower in self._followers],
                             [follower.limits for follower in self._followers],
                             config.nominal_speed, config.distance)

    def retarget(self, limits: PathLimits, one_way: bool, meanwhile: PathLimits,
                 one_way_meanwhile: bool) -> None:
        """Take a new design's path limits (limits: of the new cams; meanwhile: of the cams the
        axes ran and the new ones together). At once when every axis took its new cam; while
        an axis is to move onto it (Follower.changing) or waits for a place to hand over
        (Follower.handover), it may run either: meanwhile until none does. A refused change
        leaves its axis on the old cam: meanwhile stays (on the safe side) until the next."""
        if self._on_old_cams():
            self._retarget = limits, one_way
            self.shaft.retarget(meanwhile, one_way_meanwhile)
        else:
            self._retarget = None
            self.shaft.retarget(limits, one_way)

    def _take_new_limits(self) -> None:
        """Take the new design's path limits once every axis is on its new cam (retarget)."""
        if self._retarget is None or self._on_old_cams():
            return
        (limits, one_way), self._retarget = self._retarget, None
        self.shaft.retarget(limits, one_way)

    def _on_old_cams(self) -> bool:
        """Say whether an axis may still run its old cam after a design change: its move onto
        the new one not begun, or its handover waiting for a common place."""
        return any(follower.changing or follower.handover is not None
                   for follower in self._followers)

    @property
    def status(self) -> str:
        """Say what the axes do: the line shaft's stop and why, else one status when the axes
        agree, else each axis's."""
        if not self.shaft.following:
            return f'{self.shaft.mode}: {self.shaft.why}'
        said = [follower.status for follower in self.followers]
        if len(set(said)) == 1:
            return said[0]
        return '; '.join(f'{name}: {status}' for name, status in zip(self.names, said))

    @property
    def engaged(self) -> bool:
        """Say whether every axis follows its cam or ended its one-shot profile (or is off)."""
        return self.shaft.following and all(
            follower.phase in (ENGAGED, END_OF_PROFILE) or not follower.wanted
            for follower in self.followers)

    @property
    def resting(self) -> bool:
        """Say whether nothing moves: the line shaft rests and no axis moves onto its cam."""
        return self.shaft.mode == AT_REST and not self._moving()

    def _moving(self) -> bool:
        """Say whether an axis moves onto its cam, is to, or its move is being planned (read
        on every step without noting a tabled sample first: none of this is what it notes)."""
        return self._planning is not None or any(
            follower.needs_move or follower.move is not None for follower in self._followers)

    @property
    def held(self) -> list[Optional[float]]:
        """Return each axis's last position commanded (None: nothing yet)."""
        return [follower.held for follower in self.followers]

    def command(self, state: MasterState) -> Optional[Commands]:
        """Step the line shaft to a master sample; return every axis's command there, or None
        unless all have one."""
        if state.origin:
            self.shaft.origin()
        self._rest_for_moves()
        return self._step(state.position, self.shaft.master(state))

    def tick(self, stamp_ns: int, position: float) -> Optional[Commands]:
        """Step the line shaft to a time (ns, the master's clock) without a master sample (at
        master position, for the joint states); return the commands, None before any."""
        self._rest_for_moves()
        return self._step(position, self.shaft.tick(stamp_ns))

    def _step(self, position: float, virtual: Optional[Virtual]) -> Optional[Commands]:
        """Return the commands of a line shaft step; None if it did not step (a sample older
        than the clock's last step, or a wait): the last commands stand."""
        before = self.virtual
        if virtual is None or before is not None and virtual.stamp_ns <= before.stamp_ns:
            return None
        state = self._virtual(position, virtual)
        self._plan_moves(state)
        commands = self._follow(state)
        self._take_new_limits()
        self._resume()
        return commands

    def _rest_for_moves(self) -> None:
        """Halt the line shaft while an axis moves onto its cam or is to (see the module)."""
        if self._moving():
            self.shaft.halt(MOVING, idle=not any(follower.phase in FOLLOWING
                                                 for follower in self._followers))

    def _plan_moves(self, state: MasterState) -> None:
        """Begin the moves planned; have those due planned once the line shaft rests."""
        followers = self.followers
        if self._planning is None:
            if state.omega or self.shaft.why != MOVING or not any(
                    follower.needs_move for follower in followers):
                return  # (halted for another reason: the moves wait until it follows again)
            master = MasterMotion(state.track, 0.0)
            requests = {name: follower.move_request(master)
                        for name, follower in zip(self.names, followers) if follower.needs_move}
            others = {name: follower.during(master)
                      for name, follower in zip(self.names, followers) if name not in requests}
            planning = (requests, others, master, self.check)
            if self._submit is not None:
                self._planning = self._submit(plan_engagement, *planning)
            else:
                self._planning = Future()
                self._planning.set_result(plan_engagement(*planning))
        if not self._planning.done():
            return
        found, self._planning = self._planning.result(), None
        for name, follower in zip(self.names, followers):
            if name in found and follower.needs_move:  # (still: not disengaged meanwhile)
                changing = follower.changing
                follower.begin_move(found[name], state)
                if changing and not follower.changing and isinstance(found[name], str):
                    self._retarget = None  # refused: on its old cam (see retarget)

    def _resume(self) -> None:
        """Once no axis moves onto its cam, let the line shaft follow the master (or rest,
        saying why an axis did not engage)."""
        if self.shaft.why != MOVING or self._moving():
            return
        refused = [(name, follower.reason) for name, follower in
                   zip(self.names, self.followers) if follower.wanted and follower.reason]
        if refused:
            self.shaft.halt('not engaged: ' + by_axis(*zip(*refused)))
        else:
            self.shaft.follow()

    @staticmethod
    def _virtual(position: float, virtual: Virtual) -> MasterState:
        """Return the master sample the followers see: the virtual master's."""
        return MasterState(virtual.stamp_ns, position, virtual.omega, virtual.alpha,
                           virtual.step, virtual.theta)

    def _follow(self, state: MasterState) -> Optional[Commands]:
        """Return every axis's command at a virtual master state, or None unless all have one."""
        self.virtual = state
        if len(self.names) >= COMPILED_FROM:
            steady = self._steady(state)
            if steady is not None:
                return steady
        points = [follower.command(state) for follower in self.followers]
        if any(point is None for point in points):
            return None
        return Commands([float(point.position) for point in points],  # type: ignore[union-attr]
                        [float(point.velocity) for point in points])  # type: ignore[union-attr]

    def _steady(self, state: MasterState) -> Optional[Commands]:
        """Return every axis's command from the tables if all are steady, else None (then
        nothing changed)."""
        followers = self._followers  # steady() reads nothing a tabled sample changes
        cams = [follower.steady(state) for follower in followers]
        if None in cams:
            return None
        if cams != self._steady_cams:  # ElectronicCam compares by identity
            self._steady_cams, self._compiled = cams, self._compile(cams)  # type: ignore
        compiled = self._compiled
        if compiled is None:
            return None
        values = compiled.commands(state.track, state.omega)
        directions = [follower.limits.direction for follower in followers]
        if any(directions):
            way, velocity = np.array(directions), values[1]
            doubt = DIRECTION_MARGIN * abs(state.omega) * compiled.velocity_error
            if ((way != 0) & (way * velocity <= doubt) & (velocity != 0.0)).any():
                return None
        commands = Commands(*values.tolist())
        self._unnoted = state, commands
        return commands

    def _compile(self, cams: Sequence[ElectronicCam]) -> Optional[CompiledCams]:
        """Return the cams' stacked tables (None if a table misses ACCURACY); keep the tables
        of these cams' programs only."""
        self._tables = {program: self._tables.get(program) or compile_program(program)
                        for program in {cam.program for cam in cams}}
        tables = [self._tables[cam.program] for cam in cams]
        if not all(table.errors.accurate for table in tables):
            return None
        return CompiledCams(cams, tables)

    def values(self, commands: Commands) -> list[float]:
        """Return the command of each axis for its interface (position, or velocity)."""
        return [position if interface == 'position' else velocity for position, velocity,
                interface in zip(commands.position, commands.velocity, self.interfaces)]

    def ahead(self, times: np.ndarray) -> list[Setpoints]:
        """Return each axis's setpoints at times (s) from the last command if the virtual master
        keeps its speed."""
        state = self.virtual
        assert state is not None
        return [follower.ahead(state, times) for follower in self.followers]

    def engage(self, on: bool, rejoin: Sequence[str] = ()) -> tuple[bool, str]:
        """Engage every axis (each from where it is, then the line shaft catches up with the
        master; the axes in rejoin from where their drives report, Follower.rejoin) or
        disengage (the line shaft stops on the cams); return success (all) and what each
        said."""
        if not on:
            stopping = self.shaft.following and self.shaft.state is not None
            self.shaft.halt(DISENGAGED)
            return True, 'disengaged: the line shaft stops every axis on its cam' if stopping \
                else 'disengaged'
        for name in rejoin:
            self.followers[self.names.index(name)].rejoin()
        answers = [follower.engage() for follower in self.followers]
        self.shaft.follow()
        return all(ok for ok, _ in answers), by_axis(self.names, [said for _, said in answers])

    def events(self) -> list[str]:
        """Take what the followers noted (axis names in front when there are several)."""
        said = []
        for name, follower in zip(self.names, self.followers):
            said += [event if len(self) == 1 else f'{name}: {event}' for event in follower.events]
            follower.events.clear()
        return said
