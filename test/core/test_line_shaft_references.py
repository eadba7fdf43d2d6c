"""The line shaft's virtual master in the cases test_line_shaft leaves: an idle halt, a halt before
the first sample, a follow() waiting for the master's next sample, a two-way machine following
its master back, and a stop and a catch-up on a machine whose band is narrower than 1 rad/s^2.
Every limit is checked on theta_v's own positions (second differences: the mean acceleration
over two steps), every rule against the module's documented behaviour."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters
from cam_ros.core.ecam.line_shaft import (AT_REST, DISENGAGED, FILTERED, INACTIVE, LineShaft,
                                          LOCKED, LOST, STOPPING)
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.path_limits import MARGIN, PathLimits
from cam_ros.core.ecam.slave_limits import SlaveLimits

from line_shaft_support import DT, line, NOMINAL, run, within

MACHINE = line()


def steady(t: float) -> float:
    """Cam speed from the first sample on."""
    return NOMINAL / DT if t == 0.0 else 0.0


def test_an_idle_halt_rests_at_once_where_it_is():
    shaft = LineShaft(MACHINE.path, one_way=True)
    run(shaft, steady, 0.5)
    where = shaft.state.theta
    shaft.halt(DISENGAGED, idle=True)
    assert shaft.mode == AT_REST and shaft.why == DISENGAGED
    assert (shaft.state.theta, shaft.state.omega, shaft.state.alpha) == (where, 0.0, 0.0)
    for k in range(1, 20):
        state = shaft.tick(shaft.state.stamp_ns + round(k * DT * 1e9))
        assert (state.theta, state.omega, state.alpha) == (where, 0.0, 0.0)


def test_halted_before_its_first_sample_the_virtual_master_starts_at_rest_there():
    shaft = LineShaft(MACHINE.path, one_way=False)
    shaft.halt(INACTIVE)
    state = shaft.master(MasterState(10, 1.0, 2.0, 3.0, 0.0, 7.5))
    assert (state.theta, state.omega, state.alpha) == (7.5, 0.0, 0.0)
    assert shaft.mode == AT_REST


def test_after_follow_the_virtual_master_waits_for_the_masters_next_sample():
    # A loss stops theta_v on the clock; follow() then takes the master's phase from its next
    # sample: until one comes, the clock does not move theta_v (the last sample is stale).
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, _ = run(shaft, steady, 3.0, events={100: lambda s: s.halt(LOST)},
                           silent=range(100, 750))
    assert modes[-1] == AT_REST
    rest = states[-1]
    shaft.follow()
    for k in range(1, 50):
        state = shaft.tick(rest.stamp_ns + round(k * DT * 1e9))
        assert (state.theta, state.omega) == (rest.theta, 0.0)


def test_a_two_way_machine_follows_its_master_turning_back_hard_within_every_limit():
    shaft = LineShaft(MACHINE.path, one_way=False)

    def back(t: float) -> float:  # to cam speed, and from 1 s at 300 rad/s^2 to -cam speed
        if t == 0.0:
            return NOMINAL / DT
        return -300.0 if 1.0 <= t < 1.0 + 2.0 * NOMINAL / 300.0 else 0.0
    states, modes, tracks = run(shaft, back, 4.0)
    assert FILTERED in modes and modes[-1] == LOCKED
    assert shaft.filtered == modes.count(FILTERED)  # the steps it was not the master
    within(MACHINE, states)
    theta = np.array([state.theta for state in states])
    assert np.diff(theta)[-100:].max() < 0.0  # running backward with the master
    lagged = (tracks[-1] - theta[-1]) / (2.0 * math.pi)
    assert abs(lagged - round(lagged)) < 1e-9


def test_a_catch_up_on_a_narrow_band_locks_within_the_acceleration_limit():
    """y = 2 theta limited to 0.5 rad/s^2: the master may accelerate 0.2475 rad/s^2 at most.
    After a silence the virtual master catches up with a master at 1 rad/s and locks."""
    design = build_design(parse_parameters({
        'length_unit': 'deg', 'follower.type': 'none', 'cam_speed': 1.0,
        'motion.laws': ['constant_velocity'], 'motion.start_deg': [0.0],
        'motion.end_deg': [360.0], 'motion.start_position': [0.0],
        'motion.end_position': [720.0]}))
    limit = 0.5
    path = PathLimits.of([design.electronic_cam], [SlaveLimits(max_acceleration=limit)], 1.0,
                         math.radians(30.0))
    shaft = LineShaft(path, one_way=False)
    states, modes, _ = run(shaft, lambda t: 1.0 / DT if t == 0.0 else 0.0, 14.0,
                           events={100: lambda s: s.halt(LOST), 400: lambda s: s.follow()},
                           silent=range(100, 400))
    assert FILTERED in modes[400:] and modes[-1] == LOCKED
    theta = np.array([state.theta for state in states])
    acceleration = 2.0 * np.diff(theta[1:], 2) / DT ** 2  # the axis's: y'' = 2 theta''
    assert np.abs(acceleration).max() <= limit * (1.0 - MARGIN) * (1.0 + 1e-9)
    # The stop, at the limit: theta_v's own acceleration is -A (1 - MARGIN) / 2, as reported.
    stopping = [state for state, mode in zip(states[101:400], modes[101:400])
                if mode == STOPPING]
    assert len(stopping) > 100
    for state in stopping[1:-1]:
        assert state.alpha == pytest.approx(-limit * (1.0 - MARGIN) / 2.0, rel=1e-9)
