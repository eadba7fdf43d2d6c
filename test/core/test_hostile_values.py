"""Values that once got no clear answer: each refused in one line naming the key and the rule,
the same from a file (the CLI) as from the values a node serves; or computed without a warning.
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design_from_config import build_design
from cam_ros.core.ecam.slave_limits import SlaveLimits
from cam_ros.core.machine.served import machine_from_values
from cam_ros.core.report import design_report

CONFIG = Path(__file__).resolve().parents[2] / 'config'
DYNAMICS = read_parameters_file(CONFIG / 'machine_dynamics.yaml')  # lengths in mm, a spring
DEFAULT = read_parameters_file(CONFIG / 'default.yaml')  # lengths in cm, no dynamics


def refusal(values: dict) -> str:
    """Return the one line the config refuses values with; the node's path must say the same."""
    with pytest.raises(InvalidParameter) as from_file:
        parse_parameters(values)
    with pytest.raises(InvalidParameter) as served:
        machine_from_values(values)
    assert str(served.value) == str(from_file.value)
    assert '\n' not in str(from_file.value)
    return str(from_file.value)


@pytest.mark.parametrize('name, value, bound', [
    ('dynamics.damping_ratio', 5e-324, 'at least 1e-06'),
    ('dynamics.damping_ratio', 1e-300, 'at least 1e-06'),
    ('contact.face_width', 1e-300, 'at least 0.001 mm'),  # 1 um in the file's mm
    ('contact.face_width', 5e-324, 'at least 0.001 mm'),
    ('dynamics.mass', 1e-300, 'at least 1e-06'),
    ('contact.cam_modulus', 5e-324, 'at least 100000'),
    ('dynamics.train_natural_frequency', 1e-300, 'at least 0.001'),
    ('follower.roller_radius', 1e-300, 'at least 0.001 mm'),
    ('follower.base_radius', 1e-300, 'at least 0.001 mm'),
    ('limits.pressure_angle_return_deg', 1e-300, 'at least 1'),
])
def test_a_tiny_positive_value_is_refused_below_its_smallest_meaningful_one(name, value, bound):
    line = refusal({**DYNAMICS, name: value})
    assert line.startswith(f'{name} = {value!r}: must be 0 or {bound}'), line


@pytest.mark.parametrize('name, value', [
    ('dynamics.damping_ratio', 1e-6), ('contact.face_width', 1e-3), ('dynamics.mass', 1e-6),
    ('contact.cam_modulus', 1e5), ('dynamics.train_natural_frequency', 1e-3),
    ('follower.roller_radius', 1e-3), ('follower.base_radius', 1e-3),
    ('limits.pressure_angle_return_deg', 1.0), ('dynamics.train_damping_ratio', 5e-324),
    ('dynamics.spring_rate', 5e-324), ('limits.contact_stress', 5e-324),
])
def test_the_smallest_accepted_values_compute_without_a_numpy_warning(name, value):
    with warnings.catch_warnings():
        warnings.simplefilter('error')  # a RuntimeWarning fails the test
        design = build_design(parse_parameters({**DYNAMICS, name: value}))
        report = design_report(design)
        state = design.evaluate(np.linspace(0.0, 2.0 * math.pi, 37))
        design.warnings()
    assert report.dynamics is not None and np.all(np.isfinite(state.dynamics.contact_force))


def test_a_train_stiffness_giving_too_low_a_frequency_is_refused_with_it():
    line = refusal({**DYNAMICS, 'dynamics.train_stiffness': 1e-300})
    assert line.startswith('dynamics.train_stiffness = 1e-300: gives a natural frequency '), line
    assert 'must give at least 0.001 Hz' in line


@pytest.mark.parametrize('name, value', [
    ('dynamics.spring_rate', 2000.0), ('dynamics.spring_preload', 20.0),
    ('dynamics.damping_ratio', 0.05), ('dynamics.external_force', 5.0)])
def test_a_spring_preload_damping_or_load_without_a_mass_is_refused_by_name(name, value):
    values = {**DYNAMICS, 'dynamics.mass': 0.0, 'dynamics.spring_rate': 0.0,
              'dynamics.spring_preload': 0.0, 'dynamics.damping_ratio': 0.0, name: value}
    assert refusal(values) == (f'{name} = {value!r}: needs dynamics.mass > 0 (kg): it acts on '
                               'the moving follower train (or use 0.0)')


def test_the_shipped_dynamics_with_its_mass_set_to_zero_is_refused_not_silently_rigid():
    line = refusal({**DYNAMICS, 'dynamics.mass': 0.0})
    assert line.startswith('dynamics.spring_rate = 10000.0: needs dynamics.mass > 0'), line


@pytest.mark.parametrize('fractions', [[0.5, 0.5, 0.5], [0.2, 0.2], [1.5, -0.25, -0.25]])
def test_scca_fractions_that_are_no_split_of_the_rise_are_refused_without_an_scca_segment(
        fractions):
    line = refusal({**DEFAULT, 'motion.scca_fractions': fractions})
    assert line.startswith(f'motion.scca_fractions = {fractions!r}: must be 3 fractions b, c, '
                           'd in [0, 1] that add up to 1'), line


def test_scca_fractions_that_add_up_to_1_are_taken():
    assert parse_parameters({**DEFAULT, 'motion.scca_fractions': [0.25, 0.5, 0.25]})


@pytest.mark.parametrize('value', [5e-324, 1e-300])
@pytest.mark.parametrize('unit', ['cm', 'mm', 'm'])
def test_a_positive_slave_limit_is_a_limit_however_small(value, unit):
    values = {**DEFAULT, 'length_unit': unit, 'slave.max_velocity': value,
              'slave.max_acceleration': value, 'slave.max_jerk': value}
    design = build_design(parse_parameters(values))
    limits = SlaveLimits.from_config(design.config)
    assert limits.max_velocity > 0.0 and limits.max_acceleration > 0.0 and limits.max_jerk > 0.0
    assert limits.limited and not design.ok
    assert 'over slave.max_velocity' in design.slave_excess
    assert 'over slave.max_acceleration' in design.slave_excess


def test_a_zero_slave_limit_means_none():
    design = build_design(parse_parameters({**DEFAULT, 'slave.max_velocity': 0.0}))
    assert not SlaveLimits.from_config(design.config).limited and design.slave_excess == ''


def test_scca_fractions_of_an_scca_segment_are_refused_naming_the_segment():
    values = {**DEFAULT, 'motion.laws': ['dwell', 'scca', 'dwell', 'simple_harmonic'],
              'motion.scca_fractions': [0.5, 0.5, 0.5]}
    with pytest.raises(InvalidParameter) as built:
        build_design(parse_parameters(values))
    with pytest.raises(InvalidParameter) as served:
        machine_from_values(values)
    assert str(built.value) == str(served.value) == (
        'motion.scca_fractions = [0.5, 0.5, 0.5]: b + c + d = 1.5: the fractions must add up to '
        '1 (scca law of segment 1)')
