"""The braking curve and the grid band of path_limits against references: the closed form of a
stop at a constant deceleration before a velocity-limited stretch (a brute-force minimum over a
dense scan), toppra's controllable sets for a line limited in velocity and acceleration, and the
exact admissible band just either side of every joint."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters
from cam_ros.core.ecam.path_limits import GRID, MARGIN, PathLimits
from cam_ros.core.ecam.slave_limits import SlaveLimits

import toppra
import toppra.algorithm
import toppra.constraint

from line_shaft_support import CamPath, line, NOMINAL

SPEED = 10.0  # rad/s at cam_speed
DISTANCE = math.radians(30.0)  # the engage distance
V = 0.05  # m/s, the only limit: no axis limits acceleration


def velocity_limited():
    """A 20 mm harmonic rise and return limited to 50 mm/s only: the master stops at its own
    deceleration, SPEED^2 / (2 DISTANCE) less the margin."""
    design = build_design(parse_parameters({
        'length_unit': 'mm', 'follower.type': 'none', 'cam_speed': SPEED,
        'motion.laws': ['simple_harmonic', 'simple_harmonic'], 'motion.start_deg': [0.0, 180.0],
        'motion.end_deg': [180.0, 360.0], 'motion.start_position': [0.0, 20.0],
        'motion.end_position': [20.0, 0.0]}))
    cam = design.electronic_cam
    return cam, PathLimits.of([cam], [SlaveLimits(max_velocity=V)], SPEED, DISTANCE)


def braking_reference(cam, theta: np.ndarray, direction: float) -> np.ndarray:
    """Return the largest s = w^2 at theta from which a stop at the master's deceleration D
    never passes the velocity limit: min over theta' ahead (a cycle, dense; a sampled minimum
    is never below the true one) of V^2 / y'(theta')^2 + 2 D |theta' - theta|."""
    deceleration = SPEED ** 2 / (2.0 * DISTANCE) * (1.0 - MARGIN)
    ahead = np.linspace(0.0, 2.0 * math.pi, 100_001)
    q = theta[:, np.newaxis] + direction * ahead
    slope = np.asarray(cam.derivatives(q.reshape(-1)).dy, dtype=float).reshape(q.shape)
    with np.errstate(divide='ignore'):
        cap = (V * (1.0 - MARGIN)) ** 2 / slope ** 2
    return (cap + 2.0 * deceleration * ahead).min(axis=1)


@pytest.mark.parametrize('direction', [1.0, -1.0])
def test_the_braking_curve_is_the_stop_at_the_masters_own_deceleration_before_the_limit(
        direction):
    cam, path = velocity_limited()
    theta = np.linspace(0.01, 2.0 * math.pi - 0.01, 24)
    reference = braking_reference(cam, theta, direction)
    found = np.array([path.stoppable(q, direction) for q in theta]) ** 2
    deceleration = path.master_acceleration
    assert deceleration == pytest.approx(SPEED ** 2 / (2.0 * DISTANCE) * (1.0 - MARGIN))
    # The stop below the limit where it binds (on the way toward the steep middles) ...
    assert (reference < (V * (1.0 - MARGIN)) ** 2 / np.asarray(
        cam.derivatives(theta).dy, dtype=float) ** 2 * 0.99).sum() >= 6
    # ... on the safe side of the exact stop, and below it by no more than the grid's window
    # (up to WINDOW + 1 cells of the grid read on the safe side) costs at that deceleration.
    cell = 2.0 * math.pi / GRID
    assert np.all(found <= reference * (1.0 + 1e-9))
    assert np.all(found >= reference - 2.0 * deceleration * 6.0 * cell - 1e-6 * reference)


def test_the_grid_band_is_on_the_safe_side_just_either_side_of_every_joint():
    machine = line()
    path = machine.path
    joints = np.unique(np.concatenate([cam.breaks(0.0, path.cycle) for cam in machine.cams]))
    for joint in joints:
        for theta in (joint - 3e-9, joint + 3e-9):
            theta %= path.cycle
            for omega in (0.0, 0.5 * NOMINAL, NOMINAL):
                cap, lower, upper = path.admissible(theta, omega)
                if omega > cap:
                    continue
                grid_lower, grid_upper = path.band(theta, omega)
                assert grid_lower >= lower - 1e-9 * abs(lower), (joint, theta, omega)
                assert grid_upper <= upper + 1e-9 * abs(upper), (joint, theta, omega)


def test_the_braking_curve_of_a_limited_line_is_toppras_controllable_set():
    """toppra's controllable sets (TOPP-RA's backward pass, an independent implementation) over
    a cycle and a half with any final speed: the largest speed at each point from which the
    master can brake, within every axis's limits less the margin, to rest (it may then stand)."""
    machine = line()
    toppra.setup_logging('ERROR')
    start, end = 0.0, 3.0 * math.pi
    keep = 1.0 - MARGIN
    velocity = np.array([[-lim.max_velocity, lim.max_velocity] for lim in machine.limits])
    acceleration = np.array([[-lim.max_acceleration, lim.max_acceleration]
                             for lim in machine.limits])
    grid = np.linspace(start, end, 3 * GRID // 2 + 1)
    instance = toppra.algorithm.TOPPRA(
        [toppra.constraint.JointVelocityConstraint(velocity * keep),
         toppra.constraint.JointAccelerationConstraint(acceleration * keep)],
        CamPath(machine, start, end), gridpoints=grid)
    controllable = instance.compute_controllable_sets(0.0, 1e6)[:, 1]
    first = grid < 2.0 * math.pi
    found = np.array([machine.path.stoppable(q, 1.0) for q in grid[first]]) ** 2
    reference = controllable[first]
    assert np.all(np.isfinite(reference))
    cap = machine.path.speed_limit(grid[first]) ** 2
    assert np.mean(reference < 0.95 * cap) > 0.2  # braking binds over much of the cycle
    # Both collocations of the same constraints on grids of the same spacing: within 1 %, and
    # the grid's safe-side reading never more than 1e-3 above toppra's (measured 0.9954-1.0001).
    ratio = found / reference
    assert ratio.min() >= 0.99 and ratio.max() <= 1.001


@pytest.mark.parametrize('before, after', [(0.01, 0.03), (0.003, None), (0.5, 0.2)])
def test_the_band_over_a_step_across_the_cycle_start_is_the_exact_band_of_the_points_covered(
        before, after):
    """From before the cycle's end to after its start (None: half a cell past it): the band is
    the narrowest exact band (admissible) at the grid points from the one at or before theta to
    the one at or after theta + travel, both sides of the wrap (a harmonic cam limited in
    velocity and acceleration, the cycle start 20 deg into its rise: no joint there, the band
    narrowing across it)."""
    design = build_design(parse_parameters({
        'length_unit': 'mm', 'follower.type': 'none', 'cam_speed': SPEED,
        'motion.laws': ['simple_harmonic', 'simple_harmonic'], 'motion.start_deg': [0.0, 100.0],
        'motion.end_deg': [100.0, 360.0], 'motion.start_position': [0.0, 20.0],
        'motion.end_position': [20.0, 0.0], 'master.offset_deg': 340.0}))
    path = PathLimits.of([design.electronic_cam], [SlaveLimits(0.5, 2.0)], SPEED, DISTANCE)
    grid, cycle = path.theta, path.cycle
    end = 0.5 * grid[1] if after is None else after
    theta, travel = cycle - before, before + end
    covered = np.concatenate([grid[grid >= grid[grid <= theta].max()],
                              grid[grid <= grid[grid >= end].min()]])
    for omega in (0.0, 0.5 * SPEED, SPEED):
        exact = np.array([path.admissible(q, omega)[1:] for q in covered])
        lower, upper = path.band(theta, omega, travel)
        assert lower == pytest.approx(exact[:, 0].max(), rel=1e-9, abs=1e-9)
        assert upper == pytest.approx(exact[:, 1].min(), rel=1e-9, abs=1e-9)


def test_without_acceleration_limits_a_stop_from_above_cam_speed_takes_the_engage_distance():
    """The master's own limit stops its speed as the stop begins over the engage distance d:
    from 1.5 x cam speed at 15^2 / (2 d) (1 - MARGIN) (closed form)."""
    cam, path = velocity_limited()
    speed = 1.5 * SPEED
    deceleration = speed ** 2 / (2.0 * DISTANCE) * (1.0 - MARGIN)
    assert path.master_limit(speed) == pytest.approx(deceleration, rel=1e-12)
    assert path.master_limit(0.5 * SPEED) == path.master_acceleration  # at least cam speed's
