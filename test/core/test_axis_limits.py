"""An axis against its slave.* limits (core/ecam/axis_limits.py): peaks at cam_speed and at
master.max_speed, and the largest master acceleration allowed, against closed forms and an
independent dense-grid brute force."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design_from_config import build_design
from cam_ros.core.report import design_report

DEFAULT = read_parameters_file(Path(__file__).resolve().parents[2] / 'config' / 'default.yaml')
H = 0.02  # m, the harmonic stroke
OMEGA = 2.0 * math.pi  # rad/s of cam


def harmonic(**updates: object) -> dict:
    """A motion-only axis (m): s = H/2 (1 - cos theta), rise 0-180 deg, return 180-360 deg."""
    return {'length_unit': 'm', 'cam_speed': OMEGA, 'follower.type': 'none',
            'motion.laws': ['simple_harmonic', 'simple_harmonic'],
            'motion.start_deg': [0.0, 180.0], 'motion.end_deg': [180.0, 360.0],
            'motion.start_position': [0.0, H], 'motion.end_position': [H, 0.0], **updates}


def check(values: dict):
    return design_report(build_design(parse_parameters(values))).slave_limits


@pytest.mark.parametrize('limit', [0.5, 1.0, 3.0])
def test_the_harmonic_axis_meets_its_closed_form(limit):
    found = check(harmonic(**{'slave.max_velocity': 1.0, 'slave.max_acceleration': limit,
                              'master.max_speed': 9.0}))
    r = H / 2.0  # y = r (1 - cos q): y' = r sin q, y'' = r cos q
    assert found.cam_speed.master_speed == OMEGA
    assert found.cam_speed.velocity == pytest.approx(r * OMEGA, rel=1e-12)
    assert found.cam_speed.acceleration == pytest.approx(r * OMEGA ** 2, rel=1e-12)
    assert found.max_speed.velocity == pytest.approx(r * 9.0, rel=1e-12)
    assert found.max_speed.acceleration == pytest.approx(r * 81.0, rel=1e-12)
    # min over q of (A - r |cos q| w^2) / (r |sin q|): at cos q = r w^2 / A,
    # sqrt((A / r)^2 - w^4)
    assert found.master_acceleration == pytest.approx(
        math.sqrt((limit / r) ** 2 - OMEGA ** 4), rel=1e-9)
    q = found.master_acceleration_at
    assert abs(math.cos(q)) == pytest.approx(r * OMEGA ** 2 / limit, rel=1e-6)
    assert found.cam_speed.acceleration_ok(found.limits) is True
    assert found.max_speed.acceleration_ok(found.limits) is (r * 81.0 <= limit)
    assert found.ok is (r * 81.0 <= limit)


def test_a_cam_over_the_limit_at_constant_speed_allows_no_master_acceleration():
    r = H / 2.0
    found = check(harmonic(**{'slave.max_acceleration': 0.9 * r * OMEGA ** 2}))
    assert found.master_acceleration == -math.inf and not found.ok
    assert found.cam_speed.acceleration_ok(found.limits) is False
    assert found.max_speed is None  # master.max_speed not given
    assert found.cam_speed.velocity_ok(found.limits) is None  # no velocity limit


@pytest.mark.parametrize('mapping', [{}, {'master.scaling': 2.0, 'slave.scaling': -1.5}])
def test_the_largest_master_acceleration_is_the_brute_force_minimum_refined(mapping):
    limit = 4.0  # m/s^2: above the cam's own 2.01 (3.02 scaled by 1.5)
    values = {**DEFAULT, 'slave.max_acceleration': limit * 100.0, **mapping}  # cm/s^2
    found = check(values)
    design = build_design(parse_parameters(values))
    k, m = mapping.get('slave.scaling', 1.0), mapping.get('master.scaling', 1.0)
    omega = OMEGA * m  # the master speed that turns the cam at cam_speed
    theta = np.linspace(0.0, 2.0 * math.pi, 4_000_001)
    motion = design.program.evaluate(theta)
    slope, bend = np.abs(k * motion.ds / m), np.abs(k * motion.d2s / m ** 2)
    with np.errstate(divide='ignore'):
        bound = (limit - bend * omega ** 2) / slope
    grid = float(np.min(bound))
    assert found.master_acceleration <= grid * (1.0 + 1e-15)  # refined: never above the grid
    assert found.master_acceleration == pytest.approx(grid, rel=1e-9)
    assert found.cam_speed.velocity == pytest.approx(float(np.max(slope)) * omega, rel=1e-9)
    assert found.cam_speed.acceleration == pytest.approx(float(np.max(bend)) * omega ** 2,
                                                         rel=1e-9)
    # At that master acceleration the brute-force peak acceleration reaches the limit, not over.
    peak = np.max(np.abs(bend * omega ** 2) + slope * found.master_acceleration)
    assert peak == pytest.approx(limit, rel=1e-9) and peak <= limit * (1.0 + 1e-12)


def test_direction_is_judged_by_the_velocity_against_it():
    found = check({**DEFAULT, 'slave.direction': 'positive'})
    assert found.master_acceleration is None  # no acceleration limit
    assert found.direction_ok is False and found.backward == pytest.approx(
        (H / 2.0) * 1.5 * OMEGA, rel=1e-9)  # the 2 cm harmonic return over 120 deg
    assert check(harmonic(**{'slave.direction': 'any', 'slave.max_velocity': 1.0})
                 ).direction_ok is None


def test_an_unlimited_axis_has_no_slave_limits_check():
    assert check(DEFAULT) is None
