"""Moves off the cams (core/ecam/moves.py): one axis onto its cam in time, within its limits.

Every limit is checked on the command's own positions on a fine time grid: a position difference
over an interval is the mean velocity over it and a second difference the mean acceleration, so
neither can pass a limit the command keeps (beyond round-off). Durations are checked against the
closed forms of a time-optimal trapezoid, triangle and jerk-limited double S.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ruckig import InputParameter, Ruckig, Trajectory

from cam_ros.core import read_parameters_file
from cam_ros.core.ecam import moves as moves_module
from cam_ros.core.ecam.moves import AxisState, Bounds, MasterMotion, Move, on_cam, plan_move
from cam_ros.core.ecam.slave_limits import CamPeaks, PLAN_MARGIN, SlaveLimits
from cam_ros.core.machine.move_check import axis_limits
from cam_ros.core.machine.served import machine_from_values

KNIFE = CONFIG_DIR / 'rotary_knife.yaml'
DEFAULT = CONFIG_DIR / 'default.yaml'
DEG = math.pi / 180.0
CM = 0.01
#: Round-off allowed on a limit (relative).
SLACK = 1e-9


def axis(path, **changes):
    """Return (cam, limits, unit, nominal master speed) of a params file with changes."""
    values = read_parameters_file(path)
    values.update(changes)
    (one,) = machine_from_values(values).axes  # a single cam: a machine of one axis
    limits, unit, nominal = axis_limits(one)
    return one.cam, limits, unit, nominal


def knife(**changes):
    """The issue's knife: one-way, 720 deg/s, 6000 deg/s^2, its cam at 1 rev/s at cam_speed."""
    return axis(KNIFE, **{'slave.max_velocity': 720.0, 'slave.max_acceleration': 6000.0,
                          'slave.direction': 'positive', 'cam_speed': 2.0 * math.pi, **changes})


def planned(cam, limits, unit, nominal, start, master) -> Move:
    move = plan_move(cam, limits, start, master, nominal, unit)
    assert isinstance(move, Move), move
    return move


def cam_at(cam, theta):
    """Return the cam's y, y', y'', y''' per rad of master at master positions."""
    d = cam.derivatives(np.asarray(theta, dtype=float))
    return d.y, d.dy, d.d2y, d.d3y


def assert_within(move: Move, limits: SlaveLimits, samples: int = 200_001) -> np.ndarray:
    """Check the command's own differences against the limits and the direction."""
    t = np.linspace(0.0, move.duration, samples)
    position = move.at(t).position
    step = t[1] - t[0]
    velocity = np.diff(position) / step
    acceleration = np.diff(position, 2) / step ** 2
    if limits.max_velocity:
        assert np.abs(velocity).max() <= limits.max_velocity * (1.0 + SLACK)
    if limits.max_acceleration:
        # a second difference of round-off (1e-16 of the position) over step^2
        noise = 8.0 * np.spacing(np.abs(position).max()) / step ** 2
        assert np.abs(acceleration).max() <= limits.max_acceleration * (1.0 + SLACK) + noise
    if limits.direction:
        assert (limits.direction * np.diff(position)).min() >= -1e-12
    return t


def test_the_knife_from_rest_is_the_closed_form_trapezoid_and_never_turns_back():
    # The issue: a one-way knife 311 deg behind its cam at master rest planned a 30-turn blend.
    cam, limits, unit, nominal = knife()
    theta = 1.0
    y = float(cam.derivatives(theta).y)
    move = planned(cam, limits, unit, nominal, AxisState(y - 311.0 * DEG), MasterMotion(theta))
    v, a = limits.max_velocity, limits.max_acceleration
    distance = 311.0 * DEG
    assert distance >= v * v / a  # it reaches 720 deg/s: a trapezoid
    assert move.duration == pytest.approx(distance / v + v / a, rel=3.0 * PLAN_MARGIN)
    assert move.duration == pytest.approx(0.551944, abs=1e-6)  # 311/720 + 720/6000 s
    assert move.turns == 0  # the cam ahead of it: never the one 49 deg behind
    assert_within(move, limits)
    peaks = move.peaks
    assert peaks.velocity == pytest.approx(v, rel=2e-6) and peaks.velocity <= v
    assert peaks.acceleration == pytest.approx(a, rel=2e-6) and peaks.acceleration <= a


def test_the_knife_with_the_master_at_1_rev_per_s_finishes_within_its_limits():
    cam, limits, unit, nominal = knife()
    theta = 1.0
    y = float(cam.derivatives(theta).y)
    master = MasterMotion(theta, nominal)
    move = planned(cam, limits, unit, nominal, AxisState(y - 311.0 * DEG), master)
    # It lets the cam come up to it (the nearer turn, 49 deg ahead of it) and runs up to speed:
    assert move.turns == -1
    assert 0.15 < move.duration < 0.25  # 0.1989 s, where the blend took 30 turns
    t = assert_within(move, limits)
    # independently: v = y' w + de from the cam's derivatives and the command's positions
    _, dy, d2y, _ = cam_at(move.cam, master.at(t))
    e = move.at(t).position - cam_at(move.cam, master.at(t))[0]
    de = np.gradient(e, t)
    assert (dy * master.omega + de).min() >= -1e-6
    assert np.abs(dy * master.omega + de).max() <= limits.max_velocity * (1 + 1e-6)
    # on its cam at the end: position, velocity and acceleration the cam's
    end = move.at(np.array([move.duration, move.duration + 0.1]))
    y_end, dy_end, d2y_end, _ = cam_at(move.cam, master.at([move.duration, move.duration + 0.1]))
    np.testing.assert_array_equal(end.position, y_end)
    np.testing.assert_array_equal(end.velocity, dy_end * master.omega)
    np.testing.assert_array_equal(end.acceleration, d2y_end * master.omega ** 2)


@pytest.mark.parametrize('distance_cm', [0.3, 2.0, 6.0])
def test_a_rest_to_rest_move_without_a_jerk_limit_is_the_time_optimal_trapezoid(distance_cm):
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.max_velocity': 20.0,
                                                  'slave.max_acceleration': 400.0})
    y = float(cam.derivatives(0.3).y)
    move = planned(cam, limits, unit, nominal, AxisState(y + distance_cm * CM),
                   MasterMotion(0.3))
    d, v, a = distance_cm * CM, limits.max_velocity, limits.max_acceleration
    expected = d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)
    assert move.duration == pytest.approx(expected, rel=3.0 * PLAN_MARGIN)
    assert_within(move, limits)


def double_s(d: float, v: float, a: float, j: float) -> float:
    """Return the duration of the time-optimal rest-to-rest jerk-limited move (Biagiotti and
    Melchiorri, Trajectory Planning for Automatic Machines and Robots, 3.4)."""
    if v * j >= a * a:
        tj, ta = a / j, a / j + v / a
    else:
        tj = math.sqrt(v / j)
        ta = 2.0 * tj
    if d / v - ta >= 0.0:  # the velocity limit is reached
        return d / v + ta
    tj = a / j
    ta = (a * a / j + math.sqrt((a * a / j) ** 2 + 4.0 * a * d)) / (2.0 * a)
    if ta < 2.0 * tj:  # neither limit reached
        tj = (d / (2.0 * j)) ** (1.0 / 3.0)
        ta = 2.0 * tj
    return 2.0 * ta


@pytest.mark.parametrize('distance_cm', [0.05, 0.5, 6.0])
def test_a_jerk_limited_rest_to_rest_move_is_the_double_s(distance_cm):
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.max_velocity': 20.0,
                                                  'slave.max_acceleration': 400.0,
                                                  'slave.max_jerk': 40000.0})
    y = float(cam.derivatives(0.3).y)
    move = planned(cam, limits, unit, nominal, AxisState(y - distance_cm * CM),
                   MasterMotion(0.3))
    v, a, j = limits.max_velocity, limits.max_acceleration, limits.max_jerk
    assert move.duration == pytest.approx(double_s(distance_cm * CM, v, a, j), rel=4e-6)
    assert_within(move, limits)
    t = np.linspace(0.0, move.duration, 2001)  # third differences: coarser, or round-off rules
    jerk = np.diff(move.at(t).position, 3) / (t[1] - t[0]) ** 3
    assert np.abs(jerk).max() <= j * (1.0 + 1e-6)
    assert move.peaks.jerk <= j


def test_a_move_starts_where_the_axis_is_moving_and_keeps_its_acceleration_with_a_jerk_limit():
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.max_velocity': 20.0,
                                                  'slave.max_acceleration': 400.0,
                                                  'slave.max_jerk': 40000.0})
    start = AxisState(0.05, -0.1, 1.5)  # m, m/s, m/s^2 (limits 0.2 m/s, 4 m/s^2, 400 m/s^3)
    master = MasterMotion(2.0, 6.0)
    move = planned(cam, limits, unit, nominal, start, master)
    first = move.at(np.zeros(1))
    assert (first.position[0], first.velocity[0]) == pytest.approx((0.05, -0.1), abs=1e-15)
    assert first.acceleration[0] == pytest.approx(1.5, abs=1e-12)
    # and continuous just after: velocity and acceleration by finite differences
    h = 1e-5
    p = move.at(np.array([0.0, h, 2.0 * h])).position
    assert (p[1] - p[0]) / h == pytest.approx(-0.1, abs=1e-4)
    assert (p[2] - 2.0 * p[1] + p[0]) / h ** 2 == pytest.approx(1.5, abs=1e-2)
    assert_within(move, limits)
    # the move's own derivatives are those of its positions
    t = np.linspace(0.0, move.duration, 4001)
    got = move.at(t)
    np.testing.assert_allclose(np.gradient(got.position, t)[1:-1], got.velocity[1:-1],
                               atol=2e-3 * np.abs(got.velocity).max())


def test_the_vectorised_move_is_ruckigs_own_trajectory():
    cam, limits, unit, nominal = knife(**{'slave.max_jerk': 100000.0})
    master = MasterMotion(0.7, 0.4)
    move = planned(cam, limits, unit, nominal, AxisState(-2.0, 3.0, 0.0), master)
    d = cam.derivatives(0.7)
    given = InputParameter(1)
    given.current_position = [-2.0 - float(move.cam.derivatives(0.7).y)]
    given.current_velocity = [3.0 - float(d.dy) * 0.4]
    given.current_acceleration = [-float(d.d2y) * 0.16]
    given.min_velocity, given.max_velocity = [move.bounds.min_velocity], [move.bounds.max_velocity]
    given.max_acceleration, given.max_jerk = [move.bounds.max_acceleration], [move.bounds.max_jerk]
    trajectory = Trajectory(1)
    Ruckig(1).calculate(given, trajectory)
    assert move.duration == pytest.approx(trajectory.duration, rel=1e-12)
    times = np.random.default_rng(4).uniform(0.0, move.duration, 50)
    e, de, dde, _ = move.relative(times)
    for time, values in zip(times, zip(e, de, dde)):
        expected = [item[0] for item in trajectory.at_time(float(time))]
        np.testing.assert_allclose(values, expected, rtol=1e-9, atol=1e-9)


def test_an_axis_without_a_direction_takes_the_nearest_turn():
    cam, limits, unit, nominal = knife(**{'slave.direction': 'any'})
    y = float(cam.derivatives(0.0).y)
    move = planned(cam, limits, unit, nominal, AxisState(y - 311.0 * DEG), MasterMotion(0.0))
    assert move.turns == -1  # back 49 deg, not on 311
    assert float(move.at([move.duration]).position[0]) == pytest.approx(y - 2.0 * math.pi)
    a = limits.max_acceleration
    assert 49.0 * DEG < limits.max_velocity ** 2 / a  # a triangle: 720 deg/s is not reached
    assert move.duration == pytest.approx(2.0 * math.sqrt(49.0 * DEG / a), rel=3.0 * PLAN_MARGIN)


def test_an_axis_without_limits_moves_no_harder_than_its_cam_at_cam_speed():
    cam, limits, unit, nominal = axis(DEFAULT)
    assert not limits.limited
    own = CamPeaks.of(cam).at(nominal, 0.0, 0)
    move = planned(cam, limits, unit, nominal, AxisState(0.05), MasterMotion(1.0))
    assert move.peaks.velocity <= own.velocity * (1.0 + SLACK)
    assert move.peaks.acceleration <= own.acceleration * (1.0 + SLACK)
    expected = 0.05 - float(cam.derivatives(1.0).y)  # a trapezoid at the cam's own peaks
    v, a = own.velocity, own.acceleration
    assert move.duration == pytest.approx(expected / v + v / a if expected >= v * v / a
                                          else 2.0 * math.sqrt(expected / a), rel=1e-9)


def test_a_move_that_cannot_be_made_says_why_in_one_line():
    cam, limits, unit, nominal = knife()
    y = float(cam.derivatives(0.0).y)
    # the cam itself at twice its speed passes 720 deg/s
    why = plan_move(cam, limits, AxisState(y), MasterMotion(0.0, 2.0 * nominal), nominal, unit)
    assert isinstance(why, str) and '\n' not in why
    assert 'its cam itself' in why and 'over slave.max_velocity' in why and '720 deg/s' in why
    # an axis already over its velocity limit
    why = plan_move(cam, limits, AxisState(y, 13.0), MasterMotion(0.0), nominal, unit)
    assert 'starts over its limits: velocity 13 rad/s' in why
    # a one-way linear axis whose cam is behind it at master rest
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.direction': 'positive'})
    y = float(cam.derivatives(2.0).y)
    why = plan_move(cam, limits, AxisState(y + 0.01), MasterMotion(2.0), nominal, unit)
    assert why == ('its cam is 0.01 m (1 cm) behind it with the master at rest: it cannot reach '
                   'it without moving against slave.direction')


def test_a_move_on_its_cam_already_takes_no_time():
    cam, limits, unit, nominal = knife()
    master = MasterMotion(0.4, nominal)
    d = cam.derivatives(0.4)
    move = planned(cam, limits, unit, nominal,
                   AxisState(float(d.y), float(d.dy) * nominal, float(d.d2y) * nominal ** 2),
                   master)
    assert move.duration == 0.0
    assert on_cam(cam, limits, master).duration == 0.0
    t = np.linspace(0.0, 1.0, 11)
    np.testing.assert_array_equal(move.at(t).position, cam.derivatives(master.at(t)).y)


def test_a_delayed_move_holds_its_start_in_the_cams_frame():
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.max_velocity': 20.0,
                                                  'slave.max_acceleration': 400.0})
    move = planned(cam, limits, unit, nominal, AxisState(0.04), MasterMotion(2.0))
    later = move.delayed(0.25)
    assert later.duration == pytest.approx(move.duration + 0.25)
    waiting = later.at(np.linspace(0.0, 0.25, 50))
    np.testing.assert_array_equal(waiting.position, 0.04)
    np.testing.assert_array_equal(waiting.velocity, 0.0)
    t = np.linspace(0.0, move.duration, 101)
    np.testing.assert_allclose(later.at(t + 0.25).position, move.at(t).position, atol=1e-15)
    # with the master moving, an axis at rest is not at rest relative to its cam: no waiting
    moving = planned(cam, limits, unit, nominal, AxisState(0.04), MasterMotion(2.0, 3.0))
    assert not moving.waits
    with pytest.raises(ValueError, match='cannot wait'):
        moving.delayed(0.1)


def test_the_recheck_replans_when_the_bounds_let_the_command_pass_a_limit(monkeypatch):
    # Bounds that forget the cam's own share: cam + e passes the limits; the re-check on the
    # real command shrinks them and plans again until the command keeps every limit.
    cam, limits, unit, nominal = knife()
    calls = []
    loose = Bounds(0.0, limits.max_velocity, limits.max_acceleration, math.inf)
    original = moves_module._ruckig

    def counted(relative, bounds):
        calls.append(bounds)
        return original(relative, bounds)
    monkeypatch.setattr(moves_module, '_bounds', lambda *args: loose)
    monkeypatch.setattr(moves_module, '_ruckig', counted)
    y = float(cam.derivatives(1.0).y)
    master = MasterMotion(1.0, 0.5 * nominal)
    move = planned(cam, limits, unit, nominal, AxisState(y - 100.0 * DEG, 0.0), master)
    assert len(calls) > 1 and calls[-1].max_velocity < limits.max_velocity
    assert move.peaks.velocity <= limits.max_velocity
    assert move.peaks.acceleration <= limits.max_acceleration
    assert_within(move, limits)
