"""An axis's slave.* limits read in SI from the units a user types them in: an oscillating
arm's in degrees, a translating follower's in its length unit."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from cam_ros.core import parse_parameters, read_parameters_file
from cam_ros.core.ecam.slave_limits import SlaveLimits

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
ARM = {'follower.type': 'oscillating_roller', 'follower.pivot_distance': 10.0,
       'follower.arm_length': 8.0, 'motion.start_position': [0.0, 0.0, 12.0, 12.0],
       'motion.end_position': [0.0, 12.0, 12.0, 0.0]}
LIMITS = {'slave.max_velocity': 90.0, 'slave.max_acceleration': 1800.0,
          'slave.max_jerk': 36000.0, 'slave.direction': 'negative'}


def limits(**changes) -> SlaveLimits:
    """Return the slave limits of config/default.yaml (length unit cm) with changes."""
    values = read_parameters_file(DEFAULT)
    values.update(LIMITS, **changes)
    return SlaveLimits.from_config(parse_parameters(values))


def test_an_oscillating_arms_limits_are_typed_in_degrees():
    said = limits(**ARM)
    assert (said.max_velocity, said.max_acceleration, said.max_jerk) == pytest.approx(
        (math.pi / 2, 10 * math.pi, 200 * math.pi), rel=1e-15)
    assert said.direction == -1 and said.turn == 0.0


def test_a_translating_followers_limits_are_typed_in_its_length_unit():
    said = limits()  # cm: 90 cm/s is 0.9 m/s
    assert (said.max_velocity, said.max_acceleration, said.max_jerk) == pytest.approx(
        (0.9, 18.0, 360.0), rel=1e-15)
