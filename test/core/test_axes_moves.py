"""A machine's engagement on the line shaft (ecam/axes.py): every axis moves onto its cam in time
with the line shaft at rest, the moves checked against the interference pairs (the machine's
check, core/machine/move_check.py), then the line shaft catches up with the master.

Every assertion reads the commands SlaveAxes returns, sample by sample, against the pairs of
config/machine.yaml written out here: gap = 310 mm - feeder - jaw >= 15 mm.
"""
from __future__ import annotations

import math
from concurrent.futures import Future

import numpy as np
import pytest
from conftest import CONFIG_DIR

from cam_ros.core import read_parameters_file
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.follow import ENGAGED, EngageConfig, Follower, HOLDING
from cam_ros.core.ecam.line_shaft import AT_REST, LOCKED
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.path_limits import PathLimits
from cam_ros.core.ecam.slave_limits import AxisUnit, SlaveLimits
from cam_ros.core.machine.move_check import checked_moves
from cam_ros.core.machine.served import machine_from_values

DEG = math.pi / 180.0
#: A pusher slower than the jaw: 0.2 m/s, 4 m/s^2 (test_move_check's).
SLOW_PUSHER = {'feeder.slave.max_velocity': 200.0, 'feeder.slave.max_acceleration': 4000.0}
PERIOD = 1_000_000  # ns: 1 kHz


def machine_axes(present, idle=(), submit=None, **changes):
    """Return config/machine.yaml's machine (with changes) and its SlaveAxes, each axis's drive
    reporting present[name] (m or rad; an axis not named starts on its cam), engaging but the
    axes named in idle."""
    values = read_parameters_file(CONFIG_DIR / 'machine.yaml')
    values.update(changes)
    shop = machine_from_values(values)
    followers = []
    for axis in shop.axes:
        config = axis.design.config
        follower = Follower(axis.cam, EngageConfig.from_parameters(config.parameters),
                            axis.name not in idle,
                            SlaveLimits.from_config(config), AxisUnit.of(config))
        follower.present = present.get(axis.name)
        followers.append(follower)
    axes = SlaveAxes([axis.name for axis in shop.axes], followers, ['position'] * 3,
                     lambda moves, master: checked_moves(shop, moves, master), submit)
    return shop, axes


def run(axes, theta, seconds, omega=0.0):
    """Feed master samples from theta at speed omega; return each axis's commands (rows)."""
    rows = []
    for k in range(round(seconds * 1e9 / PERIOD)):
        q = theta + omega * k * PERIOD * 1e-9
        commands = axes.command(MasterState(k * PERIOD, q, omega, 0.0, omega * PERIOD * 1e-9,
                                            q))
        rows.append(commands.position)
    return np.array(rows)


def test_moves_that_would_collide_together_go_one_after_another_and_keep_the_gap():
    shop, axes = machine_axes({'feeder': 0.24, 'jaw': 0.0}, **SLOW_PUSHER)
    commands = run(axes, 240.0 * DEG, 1.5)
    feeder, jaw = commands[:, 0], commands[:, 2]
    gap = 0.31 - feeder - jaw
    assert gap.min() >= 0.015  # on the commands themselves
    # Together they would not: the jaw closes in 0.09 s, the slow pusher takes longer.
    assert feeder[0] == 0.24 and jaw[0] == 0.0
    backed_off = int(np.argmax(np.abs(feeder - feeder[-1]) <= 1e-12))  # on its cam
    assert backed_off > 0 and np.all(jaw[:backed_off] == 0.0)  # the jaw waits, open
    assert jaw[-1] == float(shop.axis('jaw').cam.setpoints(240.0 * DEG).position)
    assert [follower.phase for follower in axes.followers] == [ENGAGED] * 3
    assert axes.shaft.following and axes.shaft.mode == LOCKED  # the master rests: locked
    assert any('moves onto its cam' in event for event in axes.events())


def test_moves_that_collide_in_every_order_are_refused_and_every_axis_holds():
    shop, axes = machine_axes({'feeder': 0.24, 'jaw': 0.08})
    commands = run(axes, 100.0 * DEG, 0.3, omega=2.0)
    assert np.all(commands[:, 0] == 0.24) and np.all(commands[:, 2] == 0.08)
    feeder, _, jaw = axes.followers
    assert feeder.phase == jaw.phase == HOLDING
    assert feeder.reason.startswith('the moves collide together or one after another: '
                                    'clearance feeder-jaw: smallest gap -')
    assert axes.shaft.mode == AT_REST and axes.shaft.why.startswith('not engaged: feeder: ')
    assert not axes.engaged


def test_an_axis_left_disengaged_is_checked_where_it_holds():
    # The pusher stays out at 240 mm, not engaged; the jaw's move would close onto it.
    shop, axes = machine_axes({'feeder': 0.24, 'jaw': 0.0}, idle=('feeder',))
    commands = run(axes, 240.0 * DEG, 0.3)
    assert np.all(commands[:, 0] == 0.24) and np.all(commands[:, 2] == 0.0)
    jaw = axes.followers[2]
    assert jaw.phase == HOLDING and jaw.reason.startswith(
        'the moves collide together: clearance feeder-jaw: smallest gap -')


class Later:
    """A planner thread that takes its time: submit keeps the work until finish() runs it."""

    def __init__(self):
        self.waiting = []

    def submit(self, function, *args):
        future = Future()
        self.waiting.append((future, function, args))
        return future

    def finish(self):
        for future, function, args in self.waiting:
            future.set_result(function(*args))
        self.waiting.clear()


def test_moves_planned_elsewhere_begin_at_the_step_after_and_are_the_same():
    # While the planner works, every axis holds and the line shaft rests; the moves then begin
    # at the next step, as the same moves planned inline begin at once.
    later = Later()
    _, axes = machine_axes({'feeder': 0.24, 'jaw': 0.0}, submit=later.submit, **SLOW_PUSHER)
    held = run(axes, 240.0 * DEG, 0.01)
    assert len(later.waiting) == 1 and (held == held[0]).all()
    assert held[0, 0] == 0.24 and held[0, 2] == 0.0 and axes.shaft.mode == AT_REST
    assert [follower.phase for follower in axes.followers] == [HOLDING, ENGAGED, HOLDING]
    later.finish()
    rows = []
    for k in range(10, 1500):
        q = 240.0 * DEG
        rows.append(axes.command(MasterState(k * PERIOD, q, 0.0, 0.0, 0.0, q)).position)
    _, inline = machine_axes({'feeder': 0.24, 'jaw': 0.0}, **SLOW_PUSHER)
    np.testing.assert_array_equal(np.array(rows), run(inline, 240.0 * DEG, 1.49))


def test_an_offset_change_on_a_running_machine_is_a_stop_a_checked_move_and_a_catch_up():
    # The jaw closes 10 deg of machine angle earlier: the line shaft stops every axis on its
    # cam, the jaw alone moves onto its new cam (the others stand), then the line shaft
    # catches up with the master, every command keeping the 15 mm gap; once locked the
    # commands are the new cams at the master, exactly.
    shop, axes = machine_axes({})
    omega = 10.471975511965978  # cam_speed: 100 cycles/min
    before = run(axes, 30.0 * DEG, 1.0, omega)
    assert axes.shaft.mode == LOCKED
    values = read_parameters_file(CONFIG_DIR / 'machine.yaml')
    values['jaw.master.offset_deg'] = -10.0
    changed = machine_from_values(values)
    jaw = changed.axis('jaw')
    config = jaw.design.config
    said = axes.followers[2].change(jaw.cam, EngageConfig.from_parameters(config.parameters),
                                    SlaveLimits.from_config(config))
    assert said == 'moves onto the new cam in time, with the line shaft at rest'
    cams = [axis.cam for axis in shop.axes + changed.axes]
    limits = [SlaveLimits.from_config(axis.design.config) for axis in shop.axes + changed.axes]
    axes.retarget(PathLimits.of(cams[3:], limits[3:], omega, math.radians(30.0)), False,
                  PathLimits.of(cams, limits, omega, math.radians(30.0)), False)
    theta = 30.0 * DEG + omega * 1.0
    rows, virtual = [], []
    for k in range(1, 3000):
        q = theta + omega * k * PERIOD * 1e-9
        commands = axes.command(MasterState((1000 + k) * PERIOD, q, omega, 0.0,
                                            omega * PERIOD * 1e-9, q))
        rows.append(commands.position)
        virtual.append(axes.virtual.omega)
    rows = np.vstack([before, rows])
    assert (0.31 - rows[:, 0] - rows[:, 2]).min() >= 0.015
    events = axes.events()
    assert any(event.startswith('jaw: moves onto its new cam') for event in events), events
    moving = np.flatnonzero(np.abs(np.diff(rows[:, 2])) > 0)
    at_rest = len(before) + np.flatnonzero(np.array(virtual) == 0.0)
    jaw_alone = np.intersect1d(moving, at_rest[:-1])
    assert jaw_alone.size > 10  # the jaw moved with theta_v at rest, the others standing
    assert np.all(np.diff(rows[jaw_alone[0]:jaw_alone[-1] + 1, [0, 1]], axis=0) == 0.0)
    assert axes.shaft.mode == LOCKED
    q = theta + omega * 2999 * PERIOD * 1e-9
    for name, position in zip(axes.names, rows[-1]):
        cam = changed.axis(name).cam
        want = float(cam.setpoints(q).position)
        turn = 2.0 * math.pi if name == 'knife' else 0.0
        shift = round((position - want) / turn) * turn if turn else 0.0
        assert position == pytest.approx(want + shift, abs=1e-12), name


def test_while_a_design_waits_for_a_common_place_the_line_shaft_keeps_both_cams_limits():
    # The jaw closes by a cycloid instead of a modified sine: the two designs share the dwells,
    # so the new one takes over at 220 deg, where the jaw's close ends. Until then the jaw may
    # run either cam: the line shaft's limits are those of both; then those of the new.
    shop, axes = machine_axes({})
    omega = 10.471975511965978
    start = 160.0 * DEG
    run(axes, start, 0.1, omega)
    values = read_parameters_file(CONFIG_DIR / 'machine.yaml')
    values['jaw.motion.laws'] = ['dwell', 'cycloidal', 'dwell', 'modified_sine', 'dwell']
    changed = machine_from_values(values)
    jaw = changed.axis('jaw')
    config = jaw.design.config
    said = axes.followers[2].change(jaw.cam, EngageConfig.from_parameters(config.parameters),
                                    SlaveLimits.from_config(config))
    assert said.startswith('pending: waits for cam angle')
    cams = [axis.cam for axis in shop.axes + changed.axes]
    limits = [SlaveLimits.from_config(axis.design.config) for axis in shop.axes + changed.axes]
    new = PathLimits.of(cams[3:], limits[3:], omega, math.radians(30.0))
    both = PathLimits.of(cams, limits, omega, math.radians(30.0))
    axes.retarget(new, True, both, False)  # one-way once on the new cams (a slave.direction)
    step = omega * PERIOD * 1e-9
    q = start + omega * 0.1 + step * np.arange(1, 200)
    pending, in_force, jaw_at = [], [], []
    for k, position in enumerate(q):
        commands = axes.command(MasterState((101 + k) * PERIOD, position, omega, 0.0, step,
                                            position))
        pending.append(axes.followers[2].handover is not None)
        in_force.append((axes.shaft.limits, axes.shaft.one_way))
        jaw_at.append(commands.position[2])
    took = pending.index(False)  # the handover: within a step of 220 deg (the designs agree
    assert abs(q[took] - 220.0 * DEG) <= step  # there to 1e-9 in position and slope)
    assert not any(pending[took:]) and axes.followers[2].cam is jaw.cam
    assert all(limits is both and one_way is False for limits, one_way in in_force[:took])
    assert all(limits is new and one_way is True for limits, one_way in in_force[took:])
    old = shop.axis('jaw').cam.setpoints(q[:took]).position
    np.testing.assert_allclose(jaw_at[:took], old, rtol=0, atol=1e-12)
    np.testing.assert_allclose(jaw_at[took:], jaw.cam.setpoints(q[took:]).position, rtol=0,
                               atol=1e-9)
