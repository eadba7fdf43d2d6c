"""The design layer: config -> program + follower, errors in config terms, evaluation."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter, build_design, cam_geometry, check_angles
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'


def values(name: str = 'default.yaml', **updates: object) -> dict:
    flat = read_parameters_file(CONFIG_DIR / name)
    flat.update(updates)
    return flat


def design(name: str = 'default.yaml', **updates: object):
    return build_design(parse_parameters(values(name, **updates)))


def test_evaluate_is_program_plus_geometry_at_any_angles_in_any_order():
    cam = design()
    angles = np.array([5.0, -1.0, 0.3, 13.0, 2 * math.pi])
    state = cam.evaluate(angles)
    theta = np.mod(angles, 2 * math.pi)
    motion = cam.program.evaluate(theta)
    omega = cam.config.cam_speed
    np.testing.assert_array_equal(state.position, motion.s)
    np.testing.assert_allclose(state.velocity, omega * motion.ds, rtol=1e-15)
    np.testing.assert_allclose(state.acceleration, omega ** 2 * motion.d2s, rtol=1e-15)
    np.testing.assert_allclose(state.jerk, omega ** 3 * motion.d3s, rtol=1e-15)
    order = np.argsort(theta)
    shape = cam_geometry(cam.follower, theta[order], motion.s[order], motion.ds[order],
                         motion.d2s[order], clockwise=True)
    np.testing.assert_allclose(state.pressure_angle[order], shape.pressure_angle, rtol=1e-14)
    single = cam.evaluate([angles[1]])
    assert single.position[0] == state.position[1]


@pytest.mark.parametrize('updates, parameter, fragment', [
    ({'motion.start_deg': [0.0, 95.0, 180.0, 240.0]}, 'motion.start_deg[1]', 'gap'),
    ({'motion.start_deg': [0.0, 85.0, 180.0, 240.0]}, 'motion.start_deg[1]', 'overlap'),
    ({'motion.end_deg': [90.0, 180.0, 240.0, 350.0]}, 'motion.end_deg[3]', '360 deg'),
    ({'motion.end_position': [0.0, 2.0, 2.5, 0.0]}, 'motion.end_position[2]', 'dwell'),
    ({'motion.start_position': [0.0, 0.0, 2.0, 2.5]}, 'motion.start_position[3]',
     'cannot jump'),
    ({'motion.laws': ['dwell', 'cycloid', 'dwell', 'simple_harmonic']}, 'motion.laws[1]',
     'must be one of'),
    ({'motion.laws': ['dwell', 'via_point', 'dwell', 'simple_harmonic']}, 'motion.laws[1]',
     'exactly one via point'),
    ({'motion.via_segment': [3], 'motion.via_deg': [300.0], 'motion.via_position': [1.0]},
     'motion.via_segment[0]', 'takes no via points'),
    ({'follower.offset': 5.0}, 'follower.offset', 'base_radius + roller_radius'),
])
def test_design_errors_name_the_config_parameter(updates, parameter, fragment):
    with pytest.raises(InvalidParameter) as caught:
        design(**updates)
    assert str(caught.value).startswith(parameter), str(caught.value)
    assert fragment in str(caught.value)


def test_polynomial_segment_passes_its_via_point():
    cam = design(**{'motion.laws': ['dwell', 'polynomial', 'dwell', 'simple_harmonic'],
                    'motion.via_segment': [1], 'motion.via_deg': [135.0],
                    'motion.via_position': [1.2]})
    assert cam.evaluate(np.radians([135.0])).position[0] == pytest.approx(0.012, abs=1e-12)
    # 3-4-5 ends: at rest with zero acceleration where it meets the dwells.
    edge = cam.evaluate(np.radians([90.0, 180.0]))
    np.testing.assert_allclose(edge.velocity, 0.0, atol=1e-12)
    np.testing.assert_allclose(edge.acceleration, 0.0, atol=1e-9)


def test_via_point_config_passes_seed_002_points():
    cam = design('seed_via_point.yaml')
    state = cam.evaluate(np.radians([0.0, 100.0, 130.0, 170.0, 200.0, 300.0]))
    np.testing.assert_allclose(state.position, [0.0, 0.16, 0.18, 0.18, 0.16, 0.0], atol=1e-12)
    assert state.velocity[1] > 0.0 and state.velocity[4] < 0.0  # passes without stopping


@pytest.mark.parametrize('angles, fragment', [
    ([], 'empty'), ([0.0, math.nan], 'angles[1]'), ([math.inf], 'finite'),
    ([0.0] * 4, 'output.max_batch = 3'),
])
def test_check_angles_explains_what_is_wrong(angles, fragment):
    problem = check_angles(np.array(angles, dtype=float), 3)
    assert problem is not None and fragment in problem


def test_check_angles_accepts_good_batches():
    assert check_angles(np.array([0.0, 100.0, -7.0]), 3) is None


def test_flat_face_seed_is_undercut_between_table_rows():
    # Seed 000 picks a 3.2 cm base circle from a 10-degree table of -(f + f''), whose largest
    # entry is 3.147 cm at 160 deg; the true maximum lies between rows, at about 156.6 deg:
    # u = 0.74, f = 2 (u - sin(2 pi u) / (2 pi)), f'' = (16 / pi) sin(2 pi u) (cm).
    u = np.linspace(0.6, 0.9, 30001)
    need = -(2 * (u - np.sin(2 * np.pi * u) / (2 * np.pi)) + 16 / np.pi * np.sin(2 * np.pi * u))
    assert need.max() > 3.2  # so rho = Rb + f + f'' < 0 somewhere for Rb = 3.2 cm
    cam = design('seed_flat.yaml')
    assert cam.check.undercut
    worst = 90.0 + 90.0 * u[np.argmax(need)]
    assert math.degrees(cam.check.min_radius_at) == pytest.approx(worst, abs=0.1)
    assert cam.check.min_radius == pytest.approx((3.2 - need.max()) / 100, abs=1e-7)
