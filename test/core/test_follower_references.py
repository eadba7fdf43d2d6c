"""A follower's commands against their own differences and closed forms: a jerk-limited move's
acceleration and jerk, the setpoints ahead during a move, a stop and a hold, a rotary slave's
next_cycle start a whole turn away, a design change while waiting for the cycle start."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core.ecam.follow import (ENGAGED, ENGAGING, EngageConfig, Follower, HOLDING,
                                      STOPPING, WAITING_CYCLE)
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.moves import MasterMotion
from cam_ros.core.ecam.slave_limits import SlaveLimits

from line_shaft_support import line, NOMINAL

DT = 0.001
MS = 10 ** 6
FEEDER, KNIFE, JAW = line().cams


def rest(k: int, theta: float) -> MasterState:
    """The virtual master resting at theta, sample k (1 ms apart)."""
    return MasterState(k * MS, theta, 0.0, 0.0, 0.0, theta)


def moving_follower(limits: SlaveLimits, present: float, theta: float) -> Follower:
    """A follower on the feeder's cam, its ramp move planned and begun at sample 0."""
    follower = Follower(FEEDER, EngageConfig(nominal_speed=NOMINAL), engage=True, limits=limits)
    follower.present = present
    assert follower.needs_move
    found = follower.move_request(MasterMotion(theta, 0.0)).plan()
    assert not isinstance(found, str), found
    follower.begin_move(found, rest(0, theta))
    assert follower.phase == ENGAGING and follower.move is not None
    return follower


def test_a_jerk_limited_move_commands_the_derivatives_of_its_own_positions():
    # Velocity, acceleration and jerk commanded during a move (the master at rest: the move's
    # own) against central differences of the commands one level up: exact for a piecewise
    # cubic away from its jerk switches, within J dt / 2 across one.
    limits = SlaveLimits(2.5, 40.0, max_jerk=2000.0)
    theta = 1.0
    follower = moving_follower(limits, float(FEEDER.derivatives(theta).y) - 0.1, theta)
    points = []
    for k in range(2000):
        points.append(follower.command(rest(k, theta)))
        if follower.phase == ENGAGED:
            break
    assert follower.phase == ENGAGED and len(points) > 100
    p, v, a, j = (np.array([float(getattr(point, name)) for point in points])
                  for name in ('position', 'velocity', 'acceleration', 'jerk'))
    assert np.abs(j).max() > 0.5 * limits.max_jerk  # a jerk-limited profile
    np.testing.assert_allclose((p[2:] - p[:-2]) / (2 * DT), v[1:-1], rtol=0,
                               atol=limits.max_jerk * DT ** 2)
    np.testing.assert_allclose((v[2:] - v[:-2]) / (2 * DT), a[1:-1], rtol=0,
                               atol=limits.max_jerk * DT)
    steady = (j[:-2] == j[1:-1]) & (j[1:-1] == j[2:])
    assert np.count_nonzero(steady & (j[1:-1] != 0.0)) > 20
    np.testing.assert_allclose(((a[2:] - a[:-2]) / (2 * DT))[steady], j[1:-1][steady], rtol=0,
                               atol=1e-6 * limits.max_jerk)


def test_the_setpoints_ahead_during_a_move_are_the_commands_to_come():
    # ahead() at a sample predicts, at the master's speed (here at rest), what command() gives
    # at the later samples; its velocity is the central difference of its positions.
    limits = SlaveLimits(2.5, 40.0, max_jerk=2000.0)
    theta = 1.0
    follower = moving_follower(limits, float(FEEDER.derivatives(theta).y) + 0.05, theta)
    follower.command(rest(0, theta))
    times = DT * np.arange(60)
    ahead = follower.ahead(rest(0, theta), times)
    later = [follower.command(rest(k, theta)) for k in range(60)]
    assert follower.phase == ENGAGING
    np.testing.assert_allclose(ahead.position, [point.position for point in later], rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(ahead.velocity, [point.velocity for point in later], rtol=0,
                               atol=1e-9)
    np.testing.assert_allclose((ahead.position[2:] - ahead.position[:-2]) / (2 * DT),
                               ahead.velocity[1:-1], rtol=0, atol=limits.max_jerk * DT ** 2)


def test_the_setpoints_ahead_of_a_holding_slave_are_its_held_position_at_rest():
    follower = Follower(FEEDER, EngageConfig(), engage=False)
    follower.present = 0.037
    point = follower.command(rest(0, 2.0))
    assert follower.phase == HOLDING and point.position == 0.037
    ahead = follower.ahead(MasterState(0, 2.0, NOMINAL, 0.0, 0.0, 2.0), DT * np.arange(5))
    assert list(ahead.position) == [0.037] * 5 and not np.any(ahead.velocity)


def test_the_setpoints_ahead_of_a_stop_follow_the_constant_deceleration_in_closed_form():
    # A one-way knife running forward whose master turns back stops from its last command at
    # slave.max_acceleration A: p(t) = p0 + v0 t - A t^2 / 2 until t = v0 / A, then at rest at
    # p0 + v0^2 / (2 A); t counted from the last sample before the turn (the stop's start).
    limits = SlaveLimits(0.0, 30.0, 1)
    follower = Follower(KNIFE, EngageConfig(mode='immediate'), engage=True, limits=limits)
    step = NOMINAL * DT
    for k in range(5):
        theta = 2.0 + k * step
        last = follower.command(MasterState(k * MS, theta, NOMINAL, 0.0, step, theta))
    p0, v0 = last.position, last.velocity
    assert follower.phase == ENGAGED and v0 > 1.0
    theta -= step
    follower.command(MasterState(5 * MS, theta, -NOMINAL, 0.0, -step, theta))
    assert follower.phase == STOPPING
    times = 0.01 * np.arange(60)
    ahead = follower.ahead(MasterState(5 * MS, theta, -NOMINAL, 0.0, -step, theta), times)
    a = limits.max_acceleration
    assert v0 / a < times[-1]
    t = np.minimum(DT + times, v0 / a)
    np.testing.assert_allclose(ahead.position, p0 + v0 * t - 0.5 * a * t ** 2, rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(ahead.velocity, v0 - a * t, rtol=0, atol=1e-12)
    assert ahead.position[-1] == pytest.approx(p0 + v0 ** 2 / (2 * a), abs=1e-12)
    commanded = [follower.command(MasterState(k * MS, theta, 0.0, 0.0, 0.0, theta)).position
                 for k in range(6, 400)]
    t = np.minimum(DT * np.arange(2, 396), v0 / a)
    np.testing.assert_allclose(commanded, p0 + v0 * t - 0.5 * a * t ** 2, rtol=0, atol=1e-12)
    assert follower.phase == HOLDING


#: The feeder's cam on a rotary slave at 100 times its stroke: at rest at cam angle 0, 6.5 rad
#: (more than half a turn) on at cam angle 1 rad.
WINDER = ElectronicCam(FEEDER.program, CamMapping(slave_scaling=100.0))


def test_next_cycle_on_a_rotary_slave_a_whole_turn_from_the_cam_start_waits_then_runs_on():
    # The cam at angle 0 commands y0 at rest; a slave held at y0 + 2 pi (one turn on) engages
    # there without a step and runs the cam one turn on: y(q) + 2 pi, exactly.
    limits = SlaveLimits(turn=2 * math.pi)
    follower = Follower(WINDER, EngageConfig(mode='next_cycle'), engage=False, limits=limits)
    y0 = float(WINDER.slave(0.0)[0])
    follower.present = y0 + 2 * math.pi
    assert follower.engage()[0], follower.reason
    step = NOMINAL * DT
    q = 2 * math.pi - 10 * step + step * np.arange(40)
    positions = []
    for k, theta in enumerate(q):
        point = follower.command(MasterState(k * MS, float(theta), NOMINAL, 0.0, step,
                                             float(theta)))
        positions.append(float(point.position))
        assert follower.phase == (WAITING_CYCLE if theta < 2 * math.pi else ENGAGED)
        assert point.cam_angle == pytest.approx(math.fmod(theta, 2 * math.pi), abs=1e-12)
    want = np.where(q < 2 * math.pi, y0, np.asarray(WINDER.derivatives(q).y)) + 2 * math.pi
    np.testing.assert_allclose(positions, want, rtol=0, atol=1e-12)


def test_a_design_change_while_waiting_for_the_cycle_start_is_checked_again_never_a_step():
    # Waiting at the feeder's start, the slave gets a design 5 mm higher: next_cycle cannot
    # start from the held position there (refused), and it holds across the cycle start.
    follower = Follower(FEEDER, EngageConfig(mode='next_cycle'), engage=True)
    follower.present = float(FEEDER.slave(0.0)[0])
    step = NOMINAL * DT
    state = MasterState(0, 6.0, NOMINAL, 0.0, step, 6.0)
    follower.command(state)
    assert follower.phase == WAITING_CYCLE
    higher = ElectronicCam(FEEDER.program, CamMapping(slave_offset=0.005))
    follower.change(higher, EngageConfig(mode='next_cycle'))
    q = 6.0 + step * np.arange(1, 400)
    positions = [float(follower.command(MasterState(k * MS, float(theta), NOMINAL, 0.0, step,
                                                    float(theta))).position)
                 for k, theta in enumerate(q, 1)]
    assert follower.phase == HOLDING and 'next_cycle cannot engage' in follower.reason
    assert positions == [follower.present] * len(q)


def test_a_new_design_taken_at_rest_is_joined_no_faster_or_harder_than_it_at_cam_speed():
    # Without limits a move onto the cam is bounded by the new cam's own peaks at cam_speed:
    # from a dense scan of the jaw, V = max |y'| w and A = max |y''| w^2; with no jerk limit the
    # least time over a distance d is d / V + V / A (a trapezoid), or 2 sqrt(d / A).
    follower = Follower(FEEDER, EngageConfig(nominal_speed=NOMINAL), engage=False)
    follower.present = 0.3
    follower.change(JAW, EngageConfig(nominal_speed=NOMINAL))
    assert follower.engage()[0] and follower.needs_move
    theta = 3.0
    move = follower.move_request(MasterMotion(theta, 0.0)).plan()
    dense = JAW.derivatives(np.linspace(0.0, 2 * math.pi, 400_001))
    fastest, hardest = np.abs(dense.dy).max() * NOMINAL, np.abs(dense.d2y).max() * NOMINAL ** 2
    distance = abs(float(JAW.derivatives(theta).y) - 0.3)
    least = distance / fastest + fastest / hardest if distance >= fastest ** 2 / hardest \
        else 2.0 * math.sqrt(distance / hardest)
    assert move.duration == pytest.approx(least, rel=1e-5)
