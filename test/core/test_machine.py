"""A machine built: every axis commanded through its own MC_CamIn coupling on the one master."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.machine import build_machine, load_machine, parse_machine

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
MACHINE = read_parameters_file(CONFIG_DIR / 'machine.yaml')
TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0


def cycloidal(u: np.ndarray) -> np.ndarray:
    """Return the cycloidal rise fraction at u in [0, 1]."""
    return u - np.sin(TWO_PI * u) / TWO_PI


def feeder_s(theta: np.ndarray) -> np.ndarray:
    """Return the shipped pusher's position (m) at its cam angle (rad), written out."""
    d = np.degrees(theta)
    forward = 0.2 * cycloidal(np.clip(d / 140.0, 0.0, 1.0))
    back = 0.2 * cycloidal(np.clip((d - 200.0) / 120.0, 0.0, 1.0))
    return forward - back


def coupled(q, q0, m, k, y0, s, advance=0.0):
    """MC_CamIn: theta = ((q - q0) / m) mod 2 pi, y = k (s(theta) + advance turns) + y0."""
    turns = (q - q0) / m
    return k * (s(np.mod(turns, TWO_PI)) + advance * np.floor(turns / TWO_PI)) + y0


def test_the_shipped_machine_commands_each_axis_through_its_coupling():
    machine = load_machine(CONFIG_DIR / 'machine.yaml')
    q = np.linspace(-3.0 * TWO_PI, 3.0 * TWO_PI, 200001)
    positions = machine.positions(q)
    assert positions.shape == (q.size, 3)
    np.testing.assert_allclose(positions[:, 0], coupled(q, 0.0, 1.0, 1.0, 0.0, feeder_s),
                               rtol=0.0, atol=1e-15)
    knife = machine.axis('knife').design.program
    expected = coupled(q, 100.0 * DEG, 1.0, 1.0, -20.0 * DEG, lambda t: knife.evaluate(t).s,
                       advance=TWO_PI)
    np.testing.assert_allclose(positions[:, 1], expected, rtol=0.0, atol=1e-12)
    jaw = machine.axis('jaw').design.program
    np.testing.assert_allclose(positions[:, 2],
                               coupled(q, 0.0, 1.0, 1.0, 0.0, lambda t: jaw.evaluate(t).s),
                               rtol=0.0, atol=0.0)


def test_offsets_and_scalings_couple_as_mc_camin():
    values = {**MACHINE, 'feeder.master.scaling': 0.5, 'feeder.master.offset_deg': 30.0,
              'feeder.slave.scaling': -1.5, 'feeder.slave.offset': 10.0}
    machine = build_machine(parse_machine(values))
    q = np.linspace(-TWO_PI, TWO_PI, 100001)
    np.testing.assert_allclose(machine.positions(q)[:, 0],
                               coupled(q, 30.0 * DEG, 0.5, -1.5, 0.010, feeder_s),
                               rtol=0.0, atol=1e-15)
    # Two feeder cycles per machine cycle: periodic over one machine turn.
    np.testing.assert_allclose(machine.positions(q + TWO_PI)[:, 0], machine.positions(q)[:, 0],
                               rtol=0.0, atol=1e-14)


def test_setpoints_are_the_derivatives_of_the_positions_at_the_machine_speed():
    machine = load_machine(CONFIG_DIR / 'machine.yaml')
    omega, h = 10.471975511965978, 1e-6
    q = np.linspace(0.3, 6.0, 997)  # away from the knife's cut (a velocity kink at 100 deg)
    q = q[np.abs(q - 100.0 * DEG) > 0.2]
    for index, setpoints in enumerate(machine.setpoints(q, omega)):
        slope = (machine.positions(q + h)[:, index] - machine.positions(q - h)[:, index]) / (2 * h)
        np.testing.assert_allclose(setpoints.velocity, slope * omega, rtol=0.0,
                                   atol=1e-6 * max(1.0, np.abs(slope).max() * omega))
        np.testing.assert_array_equal(setpoints.position, machine.positions(q)[:, index])
    # The acceleration at a steady master (alpha 0 unless given), and with a master's alpha.
    h2, alpha = 1e-4, -4.0
    for index, (steady, speeding_up) in enumerate(zip(machine.setpoints(q, omega),
                                                      machine.setpoints(q, omega, alpha))):
        breaks = machine.axes[index].cam.breaks(0.0, 7.0)
        smooth = np.abs(q[:, np.newaxis] - breaks).min(axis=1) > 2 * h2  # no joint in reach
        y = [machine.positions(q[smooth] + step)[:, index] for step in (-h2, 0.0, h2)]
        slope, curvature = (y[2] - y[0]) / (2 * h2), (y[2] - 2 * y[1] + y[0]) / h2 ** 2
        scale = max(1.0, np.abs(curvature).max() * omega ** 2)
        np.testing.assert_allclose(steady.acceleration[smooth], curvature * omega ** 2, rtol=0.0,
                                   atol=1e-5 * scale)
        np.testing.assert_allclose(speeding_up.acceleration[smooth],
                                   curvature * omega ** 2 + slope * alpha, rtol=0.0,
                                   atol=1e-5 * scale)
        assert np.abs(slope * alpha).max() > 1e-3 * scale  # alpha shows in the figure


def test_a_scalar_angle_gives_one_position_per_axis():
    machine = load_machine(CONFIG_DIR / 'machine.yaml')
    assert machine.positions(1.0).shape == (3,)
    np.testing.assert_array_equal(machine.positions(1.0), machine.positions([1.0])[0])


def test_an_unknown_axis_is_refused():
    with pytest.raises(InvalidParameter, match=r"^axis = 'feed': is not an axis"):
        load_machine(CONFIG_DIR / 'machine.yaml').axis('feed')
