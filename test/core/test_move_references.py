"""Moves off the cams (core/ecam/moves.py) against references written out here: the cam's own
third derivative on a dense scan, ruckig with the bounds the module's docstring states (the cam's
peaks found by a dense scan), the command's extremes on a dense time grid, the master positions
of the cam's joints from its segments, and the closed-form triangle of a rest-to-rest move.
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ruckig import InputParameter, Ruckig, Trajectory

from cam_ros.core import read_parameters_file
from cam_ros.core.ecam import moves as moves_module
from cam_ros.core.ecam.moves import AxisState, Bounds, cam_jerk, MasterMotion, Move, plan_move
from cam_ros.core.ecam.slave_limits import PLAN_MARGIN
from cam_ros.core.machine.move_check import axis_limits
from cam_ros.core.machine.served import machine_from_values

KNIFE = CONFIG_DIR / 'rotary_knife.yaml'
DEFAULT = CONFIG_DIR / 'default.yaml'
DEG = math.pi / 180.0
#: Points of a dense scan over one master cycle.
SCAN = 2_000_001


def axis(path, **changes):
    """Return (cam, limits, unit, nominal master speed) of a params file with changes."""
    values = read_parameters_file(path)
    values.update(changes)
    (one,) = machine_from_values(values).axes
    limits, unit, nominal = axis_limits(one)
    return one.cam, limits, unit, nominal


def knife(**changes):
    """test_moves' knife: one-way, 720 deg/s, 6000 deg/s^2, a jerk limit, 1 rev/s of cam."""
    return axis(KNIFE, **{'slave.max_velocity': 720.0, 'slave.max_acceleration': 6000.0,
                          'slave.max_jerk': 200000.0, 'slave.direction': 'positive',
                          'cam_speed': 2.0 * math.pi, **changes})


def planned(cam, limits, unit, nominal, start, master) -> Move:
    move = plan_move(cam, limits, start, master, nominal, unit)
    assert isinstance(move, Move), move
    return move


def scanned(cam) -> dict[str, float]:
    """Return the cam's least and largest y', largest |y''| and |y'''| per rad of master, on a
    dense scan of one master cycle."""
    low = cam.mapping.master_offset
    q = np.linspace(low, low + 2.0 * math.pi * cam.mapping.master_scaling, SCAN)
    d = cam.derivatives(q)
    dy = np.asarray(d.dy, dtype=float)
    return {'least': float(dy.min()), 'most': float(dy.max()),
            'bend': float(np.abs(np.asarray(d.d2y, dtype=float)).max()),
            'jerk': float(np.abs(np.asarray(d.d3y, dtype=float)).max())}


def documented_bounds(cam, limits, omega: float) -> Bounds:
    """The module's bounds on e written out: each limit PLAN_MARGIN below, less the cam's own
    peak at omega; one-way: never against the direction."""
    peaks, keep = scanned(cam), 1.0 - PLAN_MARGIN
    steepest = max(-peaks['least'], peaks['most'])
    velocity = limits.max_velocity * keep - steepest * abs(omega)
    low, high = -velocity, velocity
    if limits.direction > 0:
        low = max(low, -min(peaks['least'], peaks['most']) * omega)
    elif limits.direction < 0:
        high = min(high, -max(peaks['least'], peaks['most']) * omega)
    jerk = limits.max_jerk * keep - peaks['jerk'] * abs(omega) ** 3 if limits.max_jerk \
        else math.inf
    return Bounds(low, high, limits.max_acceleration * keep - peaks['bend'] * omega ** 2, jerk)


def ruckig_duration(relative, bounds: Bounds) -> float:
    """Return ruckig's time-optimal duration from relative (e, de, dde) to rest at 0."""
    given = InputParameter(1)
    given.current_position, given.current_velocity, given.current_acceleration = (
        [value] for value in relative)
    given.min_velocity, given.max_velocity = [bounds.min_velocity], [bounds.max_velocity]
    given.max_acceleration, given.max_jerk = [bounds.max_acceleration], [bounds.max_jerk]
    trajectory = Trajectory(1)
    Ruckig(1).calculate(given, trajectory)
    return float(trajectory.duration)


def relative_start(move: Move, start: AxisState, master: MasterMotion) -> tuple[float, ...]:
    """Return the start's offset, velocity and acceleration relative to the cam joined."""
    d, w = move.cam.derivatives(master.theta), master.omega
    return (start.position - float(d.y), start.velocity - float(d.dy) * w,
            start.acceleration - float(d.d2y) * w * w)


HARMONIC = {'motion.laws': ['simple_harmonic', 'simple_harmonic'],
            'motion.start_deg': [0.0, 100.0], 'motion.end_deg': [100.0, 360.0],
            'motion.start_position': [0.0, 20.0], 'motion.end_position': [20.0, 0.0],
            'motion.start_velocity': [math.nan, math.nan],
            'motion.end_velocity': [math.nan, math.nan]}


@pytest.mark.parametrize('path, changes', [
    (KNIFE, {}), (KNIFE, {'master.offset_deg': 40.0}), (DEFAULT, {}),
    (DEFAULT, HARMONIC)])  # the last's jerk peaks inside its rise, not at a joint
def test_the_cams_jerk_is_the_largest_third_derivative_of_a_dense_scan(path, changes):
    cam = axis(path, **changes)[0]
    reference = scanned(cam)['jerk']
    found = cam_jerk(cam)
    assert reference * (1.0 - 1e-9) <= found <= reference * (1.0 + 1e-6)


def test_a_cam_jerkier_than_the_limit_is_refused_with_its_own_jerk_in_the_figures():
    cam, limits, unit, nominal = knife(**{'slave.max_jerk': 200.0})
    omega = 0.5 * nominal
    y = float(cam.derivatives(0.3).y)
    why = plan_move(cam, limits, AxisState(y), MasterMotion(0.3, omega), nominal, unit)
    assert isinstance(why, str)
    number = r'([0-9.e+-]+)'
    said = re.search(rf'jerk {number} rad/s\^3 \({number} deg/s\^3\) over slave.max_jerk '
                     rf'{number} rad/s\^3 \({number} deg/s\^3\)', why)
    assert said, why
    jerk = scanned(cam)['jerk'] * omega ** 3
    assert float(said[1]) == pytest.approx(jerk, rel=1e-5)
    assert float(said[2]) == pytest.approx(math.degrees(jerk), rel=1e-5)
    assert float(said[3]) == pytest.approx(limits.max_jerk, rel=1e-5)
    assert float(said[4]) == pytest.approx(200.0, rel=1e-5)


@pytest.mark.parametrize('start_deg, speed, jerk', [(0.0, 3.0, 2000.0), (20.0, None, 0.0)])
def test_a_move_off_a_moving_cam_is_ruckigs_least_time_within_the_documented_bounds(
        start_deg, speed, jerk):
    """A knife behind its cam and catching up with a jerk limit (the cam's own jerk takes a
    share of it), and one 20 deg ahead of its cam at the cam's speed that must slow down and let
    the cam come up to it, never turning back (the direction's bound binds)."""
    cam, limits, unit, nominal = knife(**{'slave.max_jerk': jerk})
    master = MasterMotion(0.7, 0.5 * nominal)
    d = cam.derivatives(master.theta)
    velocity = float(d.dy) * master.omega if speed is None else speed
    start = AxisState(float(d.y) + start_deg * DEG, velocity)
    move = planned(cam, limits, unit, nominal, start, master)
    bounds = documented_bounds(cam, limits, master.omega)
    if jerk:
        assert bounds.max_jerk < 0.9 * limits.max_jerk
    expected = ruckig_duration(relative_start(move, start, master), bounds)
    assert move.duration == pytest.approx(expected, rel=1e-6)
    t = np.linspace(0.0, move.duration, 200_001)
    assert np.diff(move.at(t).position).min() >= -1e-12  # never backward


def test_a_negative_only_knife_above_its_cam_at_rest_moves_down_in_the_closed_form_triangle():
    cam, limits, unit, nominal = knife(**{'slave.direction': 'negative', 'slave.max_jerk': 0.0})
    y = float(cam.derivatives(1.0).y)
    move = planned(cam, limits, unit, nominal, AxisState(y + 30.0 * DEG), MasterMotion(1.0))
    a = limits.max_acceleration
    assert 30.0 * DEG < limits.max_velocity ** 2 / a  # 720 deg/s is not reached
    assert move.duration == pytest.approx(2.0 * math.sqrt(30.0 * DEG / a), rel=3 * PLAN_MARGIN)
    t = np.linspace(0.0, move.duration, 20_001)
    assert np.diff(move.at(t).position).max() <= 1e-12  # never up


def test_bounds_that_let_a_one_way_axis_turn_back_are_replanned_until_it_never_does(
        monkeypatch):
    # The knife 20 deg ahead of its cam at the cam's speed, with a velocity bound on e a little
    # below the one that keeps it from turning back: the re-check on the command finds it going
    # back and raises the bound by as much, until it does not (onto the cam behind it).
    cam, limits, unit, nominal = knife(**{'slave.max_jerk': 0.0})
    master = MasterMotion(0.7, 0.5 * nominal)
    calls = []
    original = moves_module._ruckig

    def counted(relative, bounds):
        calls.append(bounds)
        return original(relative, bounds)
    documented = documented_bounds(cam, limits, master.omega)
    loose = documented._replace(min_velocity=documented.min_velocity - 0.3)
    monkeypatch.setattr(moves_module, '_bounds', lambda *args: loose)
    monkeypatch.setattr(moves_module, '_ruckig', counted)
    d = cam.derivatives(master.theta)
    start = AxisState(float(d.y) + 20.0 * DEG, float(d.dy) * master.omega)
    move = planned(cam, limits, unit, nominal, start, master)
    assert move.turns == 0  # (the cam 340 deg ahead is planned too: the longer move)
    assert any(bounds.min_velocity > loose.min_velocity for bounds in calls)
    t = np.linspace(0.0, move.duration, 200_001)
    assert np.diff(move.at(t).position).min() >= -1e-12


def test_after_its_end_a_move_commands_its_cam_exactly_jerk_included():
    cam, limits, unit, nominal = knife()
    master = MasterMotion(0.7, 0.4)
    move = planned(cam, limits, unit, nominal, AxisState(-2.0, 3.0, 0.0), master)
    after = move.duration + np.array([0.0, 0.01, 0.3])
    d, w = move.cam.derivatives(master.at(after)), master.omega
    position, velocity, acceleration, jerk = move.commands(after)
    np.testing.assert_array_equal(position, d.y)
    np.testing.assert_array_equal(velocity, d.dy * w)
    np.testing.assert_array_equal(acceleration, d.d2y * w ** 2)
    np.testing.assert_array_equal(jerk, d.d3y * w ** 3)
    for part in move.relative(after):
        np.testing.assert_array_equal(part, 0.0)


def test_a_moves_breaks_are_where_the_master_crosses_the_cams_joints():
    cam, limits, unit, nominal = knife(**{'master.offset_deg': 25.0})
    master = MasterMotion(0.4, nominal)  # m of web: the joints at 0.436 m and 0.447 m ahead
    move = planned(cam, limits, unit, nominal, AxisState(-2.0, 3.0, 0.0), master)
    mapping = cam.mapping
    turns = np.arange(-2, 4)[:, np.newaxis] * 2.0 * math.pi
    joints = np.array([segment.start for segment in cam.program.segments])
    q = (mapping.master_offset + mapping.master_scaling * (joints + turns)).reshape(-1)
    times = (q - master.theta) / master.omega
    crossed = times[(times >= 0.0) & (times <= move.duration)]
    assert crossed.size >= 2
    found = move.breaks()
    for time in crossed:
        assert np.abs(found - time).min() <= 1e-12, time


@pytest.mark.parametrize('path, changes, start, master', [
    (KNIFE, {'slave.max_velocity': 720.0, 'slave.max_acceleration': 6000.0,
             'slave.max_jerk': 200000.0, 'slave.direction': 'positive',
             'cam_speed': 2.0 * math.pi}, AxisState(-2.0, 3.0, 0.0), MasterMotion(0.7, 0.38)),
    (DEFAULT, {'slave.max_velocity': 20.0, 'slave.max_acceleration': 400.0,
               'slave.max_jerk': 40000.0}, AxisState(0.05, -0.1, 1.5), MasterMotion(2.0, 6.0))])
def test_a_moves_peaks_are_the_extremes_of_its_commands_on_a_dense_time_grid(
        path, changes, start, master):
    cam, limits, unit, nominal = axis(path, **changes)
    move = planned(cam, limits, unit, nominal, start, master)
    t = np.linspace(0.0, move.duration, 1_000_001)
    _, velocity, acceleration, jerk = move.commands(t)
    peaks, step = move.peaks, t[1] - t[0]
    # Never below the scan's; above it by no more than the next derivative over a step (the
    # jerk is flat at its peaks: constant pieces plus the cam's own, small).
    for found, values, rate in ((peaks.velocity, velocity, np.abs(acceleration).max()),
                                (peaks.acceleration, acceleration, np.abs(jerk).max()),
                                (peaks.jerk, jerk, 1e-6 * np.abs(jerk).max() / step)):
        reference = float(np.abs(values).max())
        assert reference * (1.0 - 1e-12) <= found <= reference + rate * step
    backward = float((-limits.direction * velocity).max())
    assert peaks.backward == pytest.approx(backward, rel=1e-6, abs=1e-12)


def test_refusals_of_a_jerk_limited_start_over_its_acceleration_and_of_a_cam_ahead_say_so():
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.max_velocity': 20.0,
                                                  'slave.max_acceleration': 400.0,
                                                  'slave.max_jerk': 40000.0})
    y = float(cam.derivatives(2.0).y)
    # with a jerk limit its acceleration cannot step: 5 m/s^2 is over the 4 m/s^2 limit
    why = plan_move(cam, limits, AxisState(y, 0.0, 5.0), MasterMotion(2.0), nominal, unit)
    assert why == ('starts over its limits: acceleration 5 m/s^2 (500 cm/s^2) over '
                   'slave.max_acceleration 4 m/s^2 (400 cm/s^2)')
    # a negative-only axis whose cam is 1 cm above it with the master at rest
    cam, limits, unit, nominal = axis(DEFAULT, **{'slave.direction': 'negative'})
    why = plan_move(cam, limits, AxisState(y - 0.01), MasterMotion(2.0), nominal, unit)
    assert why == ('its cam is 0.01 m (1 cm) ahead of it with the master at rest: it cannot '
                   'reach it without moving against slave.direction')
