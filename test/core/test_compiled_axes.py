"""SlaveAxes' compiled steady path against each Follower's own exact path, sample by sample: the
followers alone are driven with the virtual master the axes' line shaft gave theirs."""
from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from cam_ros.core.cam_angles import TWO_PI
from cam_ros.core.ecam.axes import COMPILED_FROM, SlaveAxes
from cam_ros.core.ecam.compiled import ACCURACY
from cam_ros.core.ecam.follow import ENGAGED, EngageConfig, Follower, HOLDING
from cam_ros.core.ecam.line_shaft import MOVING
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.moves import MasterMotion
from cam_ros.core.ecam.slave_limits import SlaveLimits
from cam_ros.core.machine.machine import load_machine
from cam_ros.core.motion.laws import Cycloidal
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

MACHINE = load_machine(Path(__file__).resolve().parents[2] / 'config' / 'machine.yaml')
OMEGA, DT = 100 * TWO_PI / 60, 0.001  # 100 cycles/min at 1 kHz
#: The knife again, one-way (slave.direction positive) with limits far above its needs.
ONE_WAY = SlaveLimits(100.0, 200.0, 1, TWO_PI)


#: The machine's start modes: its cams at cam_speed bound the moves of axes without limits.
CONFIG = EngageConfig(nominal_speed=float(MACHINE.config.parameters['cam_speed']))


def followers(config: EngageConfig = CONFIG, knife_limits: bool = True
              ) -> list[Follower]:
    """Return the machine's three followers and a one-way copy of the knife, engaging (each
    from a position of its own: a move onto its cam first)."""
    found = [Follower(axis.cam, config, True, SlaveLimits.from_config(axis.design.config))
             for axis in MACHINE.axes]
    if knife_limits:
        found.append(Follower(MACHINE.axis('knife').cam, config, True, ONE_WAY))
    for follower, present in zip(found, (0.05, 0.3, 0.01, 0.2)):
        follower.present = present
    return found


def strokes(pairs: list[Follower]) -> np.ndarray:
    """Return each axis's stroke (m or rad) from a dense scan of its exact cam over a cycle."""
    q = np.linspace(0.0, TWO_PI, 100_001)
    return np.array([np.ptp(follower.cam.setpoints(q).position) for follower in pairs])


class Counted:
    """Count the calls of a follower's exact path."""

    def __init__(self, follower: Follower):
        self.follower, self.calls = follower, 0
        self.command = follower.command
        follower.command = self  # type: ignore[method-assign]

    def __call__(self, state: MasterState):
        self.calls += 1
        return self.command(state)


def begin_moves(alone: list[Follower], virtual: MasterState) -> None:
    """Begin the followers' moves onto their cams, planned as SlaveAxes plans them (no pairs
    here), where the line shaft rests."""
    for follower in alone:
        if follower.needs_move and not virtual.omega:
            master = MasterMotion(virtual.track, 0.0)
            follower.begin_move(follower.move_request(master).plan(), virtual)


def run(axes: SlaveAxes, alone: list[Follower], track: np.ndarray, omega: np.ndarray,
        events: dict[int, object] = {}) -> dict[str, list]:
    """Drive both with the same master samples; return per sample what each did.

    events[k](axes, alone) is called before sample k. A sample is steady when every exact
    follower was engaged before it and still is after it; tabled when no follower of the axes
    ran its exact path.
    """
    counters = [Counted(follower) for follower in axes.followers]
    said: dict[str, list] = {'fast': [], 'exact': [], 'phases': [], 'tabled': [], 'steady': []}
    for k, (q, w) in enumerate(zip(track, omega)):
        if k in events:
            events[k](axes, alone)  # type: ignore[operator]
        engaged = all(follower.phase == ENGAGED for follower in alone)
        state = MasterState(k * 10 ** 6, q, w, 0.3, w * DT, q)
        before = sum(counter.calls for counter in counters)
        commands = axes.command(state)
        said['tabled'].append(sum(counter.calls for counter in counters) == before)
        begin_moves(alone, axes.virtual)
        exact = [follower.command(axes.virtual) for follower in alone]
        said['fast'].append(list(zip(commands.position, commands.velocity)))
        said['exact'].append([(float(p.position), float(p.velocity)) for p in exact])
        phases = [follower.phase for follower in axes.followers]
        said['steady'].append(engaged and set(phases) == {ENGAGED})  # nothing else was due
        assert phases == [follower.phase for follower in alone], k
        said['phases'].append(phases)
    return said


def assert_close(said: dict[str, list], pairs: list[Follower], omega: np.ndarray) -> None:
    """Every command within ACCURACY of the stroke (position) and of the peak speed."""
    fast, exact = np.array(said['fast']), np.array(said['exact'])
    stroke = strokes(pairs)
    assert (np.abs(fast[:, :, 0] - exact[:, :, 0]) <= ACCURACY * stroke).all()
    speed = np.abs(omega)[:, np.newaxis] * stroke
    assert (np.abs(fast[:, :, 1] - exact[:, :, 1]) <= ACCURACY * speed).all()


def test_steady_samples_are_tabled_and_moves_stops_and_engagements_stay_exact():
    fast, alone = followers(), followers()
    axes = SlaveAxes(['feeder', 'knife', 'jaw', 'knife2'], fast, ['position'] * 4)
    count = 2400
    omega = np.full(count, OMEGA)
    track = 3.0 + np.cumsum(omega) * DT
    feeder = MACHINE.axis('feeder').cam

    def shift(axes, alone):  # an offset change of the feeder: a move, the line shaft at rest
        for pairs in (axes.followers, alone):
            pairs[0].change(ElectronicCam(feeder.program, replace(
                feeder.mapping, master_offset=math.radians(10.0))), EngageConfig())

    def stop(axes, alone):  # the line shaft stops every axis on its cam
        axes.engage(False)

    def engage(axes, alone):
        axes.engage(True)
        for follower in alone:
            follower.engage()

    said = run(axes, alone, track, omega, {500: shift, 1000: stop, 1800: engage})
    assert_close(said, fast, omega)
    assert said['tabled'] == said['steady']  # every steady sample, and only those
    assert sum(said['steady']) > 1200
    assert axes.shaft.mode == 'locked' and axes.shaft.filtered > 0  # stopped, caught up
    for mine, theirs in zip(fast, alone):  # a later move starts where the commands were
        assert abs(mine.held - theirs.held) <= ACCURACY * float(np.max(strokes([mine])))


def test_a_master_turning_back_under_a_one_way_axis_is_followed_by_the_line_shaft_standing():
    fast, alone = followers(), followers()
    axes = SlaveAxes(['feeder', 'knife', 'jaw', 'knife2'], fast, ['position'] * 4)
    omega = np.concatenate((np.full(800, OMEGA), np.full(200, -OMEGA)))
    track = 0.5 + np.cumsum(omega) * DT
    said = run(axes, alone, track, omega)
    assert_close(said, fast, omega)
    assert set(said['phases'][-1]) == {ENGAGED}  # every axis stays on its cam
    assert axes.virtual.omega == 0.0 and axes.shaft.mode == 'filtered'
    assert sum(said['tabled']) > 200


def test_tabled_commands_are_noted_in_the_followers_before_anything_reads_them():
    # Only axes.command for 400 samples: the followers are not looked at in between, yet an
    # offset change then finds them where the last command sent left them, as the exact
    # followers: on their old cams until the line shaft rests.
    fast, alone = followers(), followers()
    axes = SlaveAxes(['feeder', 'knife', 'jaw', 'knife2'], fast, ['position'] * 4)
    k, last = 0, None
    while k < 400 or last is None:
        q = 3.0 + OMEGA * DT * k
        state = MasterState(k * 10 ** 6, q, OMEGA, 0.0, OMEGA * DT, q)
        last = axes.command(state)
        begin_moves(alone, axes.virtual)
        for follower in alone:
            follower.command(axes.virtual)
        k += 1
    assert all(follower.phase == ENGAGED for follower in alone)
    assert axes.held == last.position  # the tabled sample, noted when read
    stroke = strokes(fast)
    assert (np.abs(np.array(axes.held) - [f.held for f in alone]) <= ACCURACY * stroke).all()
    feeder = MACHINE.axis('feeder').cam
    moved = ElectronicCam(feeder.program, replace(feeder.mapping,
                                                  master_offset=math.radians(10.0)))
    said = [pairs[0].change(moved, EngageConfig()) for pairs in (axes.followers, alone)]
    assert said[0] == said[1] == 'moves onto the new cam in time, with the line shaft at rest'
    q = 3.0 + OMEGA * DT * k
    state = MasterState(k * 10 ** 6, q, OMEGA, 0.0, OMEGA * DT, q)
    stopping, exact = axes.command(state), [f.command(axes.virtual) for f in alone]
    assert axes.shaft.why == MOVING
    assert np.abs(np.array(stopping.position) - [float(p.position) for p in exact]).max() <= \
        ACCURACY * stroke.max()
    assert np.abs(np.array(stopping.velocity) - [float(p.velocity) for p in exact]).max() <= \
        ACCURACY * OMEGA * stroke.max() * 10


def test_a_one_shot_machine_ends_its_profile_on_the_same_sample():
    config = replace(CONFIG, mode='immediate', periodic=False)
    fast, alone = followers(config, False), followers(config, False)
    axes = SlaveAxes(['feeder', 'knife', 'jaw'], fast, ['position'] * 3)
    omega = np.full(1500, OMEGA)  # moves onto the cams, a catch-up, then one cycle
    said = run(axes, alone, 0.5 + np.cumsum(omega) * DT, omega)
    assert_close(said, fast, omega)
    assert said['phases'][-1] == ['end of profile'] * 3
    assert said['tabled'] == said['steady'] and sum(said['tabled']) > 500


def test_a_single_axis_takes_the_exact_path_to_the_last_bit():
    assert COMPILED_FROM == 2
    fast, alone = followers(knife_limits=False)[1:2], followers(knife_limits=False)[1:2]
    axes = SlaveAxes(['knife'], fast, ['velocity'])
    omega = np.full(600, OMEGA)
    said = run(axes, alone, 2.0 + np.cumsum(omega) * DT, omega)
    assert said['fast'] == said['exact']
    assert not any(said['tabled'])


def test_a_tabled_velocity_near_backward_leaves_the_stop_to_the_exact_path():
    # One-way axes whose second half falls by 1e-12 m: within slave.direction's tolerance for
    # the cam (BACKWARD_TOLERANCE), yet its exact velocity is negative, which stops the slave.
    fall = 1e-12
    program = MotionProgram((Segment(Cycloidal(), 0.0, math.pi, 0.0, 0.1),
                             Segment(Cycloidal(), math.pi, TWO_PI, 0.1, 0.1 - fall)),
                            advance=0.1 - fall)
    cam = ElectronicCam(program, CamMapping())
    limits = SlaveLimits(10.0, 1e3, 1, 0.0)

    def make() -> list[Follower]:
        return [Follower(cam, EngageConfig(), True, limits) for _ in range(3)]

    fast, alone = make(), make()
    axes = SlaveAxes(['a', 'b', 'c'], fast, ['position'] * 3)
    omega = np.full(300, OMEGA)
    track = 0.5 + np.cumsum(omega) * DT
    said = run(axes, alone, track, omega)
    assert_close(said, fast, omega)
    first = int(np.argmax(track >= math.pi))  # the first sample on the fall
    assert [phases[0] for phases in said['phases']].index(HOLDING) == first
    assert sum(said['tabled']) > 200
