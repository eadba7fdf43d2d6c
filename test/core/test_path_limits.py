"""The master limits of a machine (path_limits) against independent computations."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters
from cam_ros.core.ecam.line_shaft import LineShaft
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.path_limits import MARGIN, PathLimits
from cam_ros.core.ecam.slave_limits import SlaveLimits

from line_shaft_support import DT, line, NOMINAL, run, toppra_stop_time

MACHINE = line()


def slopes(theta: float, step: float = 1e-5) -> tuple[np.ndarray, np.ndarray]:
    """Return every axis's y' and y'' at theta by central differences of the positions."""
    y = MACHINE.positions(np.array([theta - step, theta, theta + step]))
    return (y[2] - y[0]) / (2 * step), (y[2] - 2 * y[1] + y[0]) / step ** 2


def usage(theta: float, omega: float, alpha: float) -> np.ndarray:
    """Return each axis's |acceleration| over its limit less MARGIN at a master state."""
    first, second = slopes(theta)
    limit = np.array([lim.max_acceleration for lim in MACHINE.limits]) * (1 - MARGIN)
    return np.abs(second * omega ** 2 + first * alpha) / limit


@pytest.mark.parametrize('theta', np.linspace(0.05, 6.2, 23))
def test_the_admissible_accelerations_are_where_an_axis_reaches_its_limit(theta):
    path = MACHINE.path
    for omega in (0.0, 0.5 * NOMINAL, NOMINAL):
        cap, lower, upper = path.admissible(theta, omega)
        if omega > cap:
            continue
        for alpha in (lower, upper):
            used = usage(theta, omega, alpha)
            assert used.max() == pytest.approx(1.0, abs=1e-4)
        assert usage(theta, omega, upper + 0.01 * (upper - lower)).max() > 1.0
        assert usage(theta, omega, lower - 0.01 * (upper - lower)).max() > 1.0


@pytest.mark.parametrize('theta', np.linspace(0.05, 6.2, 23))
def test_the_maximum_velocity_curve_is_where_the_bands_close_or_a_velocity_limit(theta):
    cap = float(MACHINE.path.speed_limit(theta)[0])
    first, _ = slopes(theta)
    velocity = np.array([lim.max_velocity for lim in MACHINE.limits]) * (1 - MARGIN)
    with np.errstate(divide='ignore'):
        fastest = float((velocity / np.abs(first)).min())
    below, above = (MACHINE.path.admissible(theta, cap * factor) for factor in (0.999, 1.001))
    if cap < fastest * (1 - 1e-9):  # the bands part just above the curve
        assert below[1] <= below[2] and above[1] > above[2]
    else:
        assert cap == pytest.approx(fastest, rel=1e-9)


def test_the_grid_band_is_on_the_safe_side_of_the_exact_one():
    path = MACHINE.path
    for theta in np.linspace(0.0, 2 * math.pi, 301):
        _, lower, upper = path.admissible(theta, NOMINAL)
        grid_lower, grid_upper = path.band(theta, NOMINAL)
        assert grid_lower >= lower - 1e-9 * abs(lower) and grid_upper <= upper + 1e-9 * upper


@pytest.mark.parametrize('start', [0.3, 1.9, 3.0, 4.4, 5.6])
def test_a_stop_from_cam_speed_is_within_ten_percent_of_toppras_time_optimal_stop(start):
    """Run locked at cam_speed, then halt: the stop's time against toppra's shortest time over
    the same travel (the max-deceleration stop is time-optimal; toppra is independent)."""
    shaft = LineShaft(MACHINE.path, one_way=True)
    warm = round(start / NOMINAL / DT)
    states, modes, _ = run(shaft, lambda t: 0.0 if t > 0 else NOMINAL / DT, warm * DT + 0.8,
                           events={warm: lambda s: s.halt('test')})
    assert modes[warm - 1] == 'locked'
    stopped = next(k for k in range(warm, len(states)) if states[k].omega == 0.0)
    begin = states[warm - 1]
    ours = (stopped - warm + 1) * DT  # rest is reached within the last step
    reference = toppra_stop_time(MACHINE, begin.theta, states[stopped].theta, begin.omega)
    assert ours <= 1.10 * reference + DT
    assert ours >= 0.99 * reference - DT  # not harder than the limits allow


def test_a_constant_velocity_axis_stops_at_its_acceleration_limit_in_closed_form():
    """y = k theta: |k alpha| <= A, so a stop from w0 takes w0 k / (A (1 - MARGIN))."""
    design = build_design(parse_parameters({
        'length_unit': 'deg', 'follower.type': 'none', 'cam_speed': 10.0,
        'motion.laws': ['constant_velocity'], 'motion.start_deg': [0.0],
        'motion.end_deg': [360.0], 'motion.start_position': [0.0],
        'motion.end_position': [720.0]}))
    limits = SlaveLimits(max_acceleration=50.0)
    path = PathLimits.of([design.electronic_cam], [limits], 10.0, math.radians(30))
    assert np.all(path.forward == path.forward[0])  # the same everywhere: no limit curve
    shaft = LineShaft(path, one_way=False)
    shaft.master(MasterState(0, 0.0, 10.0, 0.0, 0.0, 0.0))
    shaft.halt('test')
    expected = 10.0 * 2.0 / (50.0 * (1 - MARGIN))  # k = 2 (720 deg per turn)
    steps = 0
    while shaft.state.omega > 0.0:
        steps += 1
        shaft.tick(round(steps * DT * 1e9))
    assert (steps - 1) * DT < expected <= steps * DT
    travel = 10.0 * 10.0 / (2 * 50.0 * (1 - MARGIN) / 2.0)
    assert shaft.state.theta == pytest.approx(travel, rel=1e-9)


def test_without_acceleration_limits_the_master_stops_over_the_engage_distance():
    design = build_design(parse_parameters({
        'length_unit': 'mm', 'follower.type': 'none', 'cam_speed': 10.0,
        'motion.laws': ['dwell'], 'motion.start_deg': [0.0], 'motion.end_deg': [360.0],
        'motion.start_position': [0.0], 'motion.end_position': [0.0]}))
    distance = math.radians(30.0)
    path = PathLimits.of([design.electronic_cam], [SlaveLimits()], 10.0, distance)
    deceleration = 100.0 / (2 * distance) * (1 - MARGIN)
    assert path.master_acceleration == pytest.approx(deceleration)
    assert path.band(1.0, 10.0) == (-math.inf, math.inf)  # a master followed is not limited
    shaft = LineShaft(path, one_way=False)
    shaft.master(MasterState(0, 0.0, 10.0, 0.0, 0.0, 0.0))
    shaft.halt('test')
    steps = 0
    while shaft.state.omega > 0.0:
        steps += 1
        shaft.tick(round(steps * DT * 1e9))
    assert (steps - 1) * DT < 10.0 / deceleration <= steps * DT
    assert shaft.state.theta == pytest.approx(distance / (1 - MARGIN), rel=1e-9)
