"""`cam_ros sample`: CSV, JSON and table agree with design.evaluate and with calculus."""
from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest
from cli_support import (assert_one_error_line, DEFAULT_CONFIG, follower_config, FOLLOWERS, OMEGA,
                         run_cli, seed_000_motion, seed_000_roller, SHIPPED_CONFIGS,
                         write_config)

from cam_ros.commands.common import load_design

FIELDS = ('angle', 'position', 'velocity', 'acceleration', 'jerk', 'dposition_dangle',
          'd2position_dangle2', 'd3position_dangle3', 'pressure_angle', 'radius_of_curvature')
STATE_FIELDS = ('angle', 'position', 'velocity', 'acceleration', 'jerk', 'ds', 'd2s', 'd3s',
                'pressure_angle', 'radius_of_curvature')
TRANSLATING_HEADER = ('angle_rad,position_m,velocity_m_per_s,acceleration_m_per_s2,'
                      'jerk_m_per_s3,dposition_dangle_m_per_rad,d2position_dangle2_m_per_rad2,'
                      'd3position_dangle3_m_per_rad3,pressure_angle_rad,radius_of_curvature_m')
FINE_STEP_DEG = 0.01
#: Central differences at 0.01 deg: error ~ h^2/6 * (next derivative), relative to its peak.
DIFFERENCE_TOLERANCE = 1e-6
JOINT_MARGIN_DEG = 0.05  # difference quotients straddling a joint are left out
CLOSED_FORM_TOLERANCE = 1e-12


def sample_csv(capsys, config, step) -> tuple[list[str], np.ndarray]:
    """Run `cam_ros sample --csv` on a design that meets its limits; return header, values."""
    run = run_cli(capsys, 'sample', config, '--step-deg', step, '--csv')
    assert run.code == 0 and run.err == ''
    rows = list(csv.reader(io.StringIO(run.out)))
    return rows[0], np.array(rows[1:], dtype=float)


def test_csv_header_has_units_and_values_equal_design_evaluate(capsys):
    header, values = sample_csv(capsys, DEFAULT_CONFIG, 7.5)
    assert ','.join(header) == TRANSLATING_HEADER
    angles = np.radians(np.arange(0.0, 360.0, 7.5))
    assert values.shape == (48, len(FIELDS))
    state = load_design(DEFAULT_CONFIG).evaluate(angles)
    for column, field in enumerate(STATE_FIELDS):
        np.testing.assert_array_equal(values[:, column], getattr(state, field), err_msg=field)


def test_json_equals_csv_and_states_units(capsys):
    _, values = sample_csv(capsys, DEFAULT_CONFIG, 10.0)
    run = run_cli(capsys, 'sample', DEFAULT_CONFIG, '--step-deg', '10', '--json')
    assert run.code == 0
    data = json.loads(run.out)
    assert data['units'] == {'angle': 'rad', 'position': 'm', 'velocity': 'm/s',
                             'acceleration': 'm/s^2', 'jerk': 'm/s^3', 'dposition_dangle': 'm/rad',
                             'd2position_dangle2': 'm/rad^2', 'd3position_dangle3': 'm/rad^3',
                             'pressure_angle': 'rad', 'radius_of_curvature': 'm'}
    for column, name in enumerate(FIELDS):
        np.testing.assert_array_equal(data[name], values[:, column], err_msg=name)


def test_samples_match_seed_000_in_closed_form(capsys):
    _, values = sample_csv(capsys, DEFAULT_CONFIG, 0.5)
    theta = values[:, 0]
    s, ds, d2s, d3s = seed_000_motion(theta)
    phi, rho = seed_000_roller(theta)
    expected = (s, ds * OMEGA, d2s * OMEGA ** 2, d3s * OMEGA ** 3, ds, d2s, d3s, phi, rho)
    for column, reference in enumerate(expected, start=1):
        np.testing.assert_allclose(values[:, column], reference, rtol=CLOSED_FORM_TOLERANCE,
                                   atol=CLOSED_FORM_TOLERANCE, err_msg=FIELDS[column])


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
def test_each_array_is_the_finite_difference_of_the_one_before(kind, tmp_path, capsys):
    config = follower_config(tmp_path, kind)
    _, values = sample_csv(capsys, config, FINE_STEP_DEG)
    theta = values[:, 0]
    joints = [math.radians(angle) for angle in (0.0, 90.0, 180.0, 240.0, 360.0)]
    smooth = np.all([np.abs(theta - joint) > math.radians(JOINT_MARGIN_DEG)
                     for joint in joints], axis=0)[1:-1]
    step = theta[1] - theta[0]
    column = {name: values[:, index] for index, name in enumerate(FIELDS)}
    chain = (('position', 'dposition_dangle'), ('dposition_dangle', 'd2position_dangle2'),
             ('d2position_dangle2', 'd3position_dangle3'))
    for low, high in chain:
        quotient = (column[low][2:] - column[low][:-2]) / (2 * step)
        scale = np.abs(column[high]).max()
        np.testing.assert_allclose(quotient[smooth], column[high][1:-1][smooth],
                                   atol=DIFFERENCE_TOLERANCE * scale, err_msg=high)
    speed = load_design(config).config.cam_speed
    for timed, per_angle, power in (('velocity', 'dposition_dangle', 1),
                                    ('acceleration', 'd2position_dangle2', 2),
                                    ('jerk', 'd3position_dangle3', 3)):
        np.testing.assert_allclose(column[timed], column[per_angle] * speed ** power,
                                   rtol=CLOSED_FORM_TOLERANCE, err_msg=timed)


def test_oscillating_follower_positions_are_in_rad(tmp_path, capsys):
    header, values = sample_csv(capsys, follower_config(tmp_path, 'oscillating_roller'), 90.0)
    assert header[1:5] == ['position_rad', 'velocity_rad_per_s', 'acceleration_rad_per_s2',
                           'jerk_rad_per_s3']
    assert values[2, 1] == pytest.approx(math.radians(15.0))  # the 15 deg stroke at 180 deg


def test_table_has_one_row_per_angle_and_units_in_the_header(capsys):
    run = run_cli(capsys, 'sample', DEFAULT_CONFIG, '--step-deg', '30')
    assert run.code == 0
    lines = run.out.splitlines()
    assert len(lines) == 1 + 12
    assert lines[0].split('  ')[0] == 'angle (rad)' and 'velocity (m/s)' in lines[0]
    assert float(lines[4].split()[0]) == pytest.approx(math.pi / 2, rel=1e-5)


def test_default_step_is_one_degree(capsys):
    run = run_cli(capsys, 'sample', DEFAULT_CONFIG, '--csv')
    assert run.code == 0 and len(run.out.splitlines()) == 1 + 360


@pytest.mark.parametrize('step', ['0', '-1', '400', 'nan', 'abc'])
def test_bad_step_exits_2(step, capsys):
    run = run_cli(capsys, 'sample', DEFAULT_CONFIG, '--step-deg', step)
    assert_one_error_line(run, 'sample', '--step-deg', repr(step), 'must be')


def test_json_and_csv_exclude_each_other(capsys):
    run = run_cli(capsys, 'sample', DEFAULT_CONFIG, '--json', '--csv')
    assert_one_error_line(run, 'sample', 'not allowed with argument')


@pytest.mark.parametrize('config', SHIPPED_CONFIGS, ids=lambda path: path.name)
def test_every_shipped_config_samples(config, capsys):
    run = run_cli(capsys, 'sample', config, '--step-deg', 5, '--csv')
    design = load_design(config)
    assert run.code == (0 if design.ok else 1)
    # A design violating its limits is still sampled; stderr says why, one warning per line.
    assert all(line.startswith('cam_ros sample: warning: ') for line in run.err.splitlines())
    assert len(run.err.splitlines()) == (0 if design.ok else len(design.warnings()))
    rows = list(csv.reader(io.StringIO(run.out)))
    values = np.array(rows[1:], dtype=float)
    columns = len(FIELDS) + (3 if design.dynamics else 0)  # contact force, torque, stress
    assert len(rows[0]) == columns and values.shape == (72, columns)
    np.testing.assert_array_equal(values[:, 1], design.evaluate(values[:, 0]).position)


@pytest.mark.filterwarnings('error')  # no NumPy RuntimeWarning on the way
def test_an_undamped_train_at_resonance_samples_and_says_it_is_unbounded(tmp_path, capsys):
    def edit(parameters):
        parameters['dynamics'] = {'train_natural_frequency': 6.0, 'train_damping_ratio': 0.0}
    run = run_cli(capsys, 'sample', write_config(tmp_path, 'resonant', edit), '--step-deg', 90)
    assert run.code == 1 and len(run.out.splitlines()) == 1 + 4
    [line] = [line for line in run.err.splitlines() if 'resonates' in line]
    assert line == ('cam_ros sample: warning: the undamped follower train resonates: fn 6 Hz is '
                    "6 x the cam frequency, so harmonic 6 of the cam's motion drives it at its "
                    "natural frequency and the output's vibration grows without bound (no "
                    'steady state); give dynamics.train_damping_ratio > 0 or move fn off the '
                    'multiple')
