"""`cam_ros call` and `cam_ros echo` against a real cam_node (isolated DDS domain)."""
from __future__ import annotations

import csv
import io
import json
import math
import re
import time

import numpy as np
import pytest
import yaml
from cli_support import CONFIG_DIR, DEFAULT_CONFIG, follower_config, run_cli

from cam_ros.commands.common import load_design

SHORT_TIMEOUT_S = 0.5
NODE_TIMEOUT_S = 10.0
STREAM_TIMEOUT_S = 4.0  # discovery (up to ~3 s) plus a stream at 50 Hz


@pytest.fixture
def cam_node(start_cam_node):
    """Start cam_node on seed 000 and return its design."""
    start_cam_node(DEFAULT_CONFIG)
    return load_design(DEFAULT_CONFIG)


def test_call_prints_the_designs_values_as_json_and_as_a_table(cam_node, capsys):
    run = run_cli(capsys, 'call', '100', '130', '-30', '--deg', '--json',
                  '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    data = json.loads(run.out)
    angles = np.radians([100.0, 130.0, -30.0])
    np.testing.assert_array_equal(data['angle'], angles)
    expected = cam_node.evaluate(angles)
    for field in ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                  'radius_of_curvature'):
        np.testing.assert_array_equal(data[field], getattr(expected, field), err_msg=field)
    assert data['units']['position'] == 'm' and data['units']['jerk'] == 'm/s^3'
    assert 'contact_force' not in data and 'contact_force' not in data['units']  # no dynamics
    # Seed 000's table: the follower is 0.780 cm up at 130 deg.
    assert data['position'][1] == pytest.approx(0.780e-2, abs=5e-6)

    # The same call as a table: units in the header, one row per angle.
    run = run_cli(capsys, 'call', '0.5', '2', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    header, *rows = run.out.splitlines()
    for column in ('angle (deg)', 'angle (rad)', 'position (m)', 'velocity (m/s)',
                   'acceleration (m/s^2)', 'jerk (m/s^3)', 'pressure angle (deg)',
                   'radius of curvature (m)'):
        assert column in header
    assert len(rows) == 2
    expected = cam_node.evaluate([0.5, 2.0])
    cells = rows[1].split()
    assert float(cells[0]) == pytest.approx(math.degrees(2.0), abs=1e-4)
    assert float(cells[2]) == pytest.approx(expected.position[1], rel=1e-5)
    assert float(cells[6]) == pytest.approx(math.degrees(expected.pressure_angle[1]), abs=1e-4)
    assert float(cells[7]) == pytest.approx(expected.radius_of_curvature[1], rel=1e-5)
    assert len(cells) == 8 and 'contact' not in header


def test_call_prints_the_dynamics_arrays_of_a_design_with_dynamics(start_cam_node, capsys):
    config = CONFIG_DIR / 'machine_dynamics.yaml'
    start_cam_node(config)
    run = run_cli(capsys, 'call', '37', '95', '233', '--deg', '--json',
                  '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    data = json.loads(run.out)
    forces = load_design(config).evaluate(np.radians([37.0, 95.0, 233.0])).dynamics
    units = {'contact_force': 'N', 'camshaft_torque': 'Nm', 'contact_stress': 'Pa'}
    for field, unit in units.items():
        assert data['units'][field] == unit
        np.testing.assert_array_equal(data[field], getattr(forces, field), err_msg=field)

    run = run_cli(capsys, 'call', '95', '--deg', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    header, row = run.out.splitlines()
    assert re.split(r'\s{2,}', header.strip())[-3:] == [
        'contact force (N)', 'camshaft torque (Nm)', 'contact stress (Pa)']
    cells = [float(cell) for cell in row.split()[-3:]]
    forces = load_design(config).evaluate([math.radians(95.0)]).dynamics
    for cell, field in zip(cells, units):
        assert cell == pytest.approx(getattr(forces, field)[0], rel=1e-5), field


def test_call_reports_units_of_an_oscillating_follower(start_cam_node, tmp_path, capsys):
    start_cam_node(follower_config(tmp_path, 'oscillating_roller'))
    run = run_cli(capsys, 'call', '2', '--json', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    assert json.loads(run.out)['units']['velocity'] == 'rad/s'


def test_call_reports_units_of_a_rotary_slave(start_cam_node, capsys):
    start_cam_node(CONFIG_DIR / 'rotary_knife.yaml')  # follower.type none, length_unit deg
    run = run_cli(capsys, 'call', '2', '--json', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    assert json.loads(run.out)['units']['velocity'] == 'rad/s'


def test_call_refused_by_the_node_exits_1_with_its_message(start_cam_node, capsys):
    start_cam_node(DEFAULT_CONFIG, '-p', 'output.max_batch:=2')
    run = run_cli(capsys, 'call', '1', '2', '3', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 1 and run.out == ''
    assert run.err.startswith('cam_ros call: /cam/evaluate refused: ')
    assert 'output.max_batch = 2' in run.err and len(run.err.splitlines()) == 1


def test_call_without_a_service_exits_1_after_the_timeout(ros_domain, capsys):
    run = run_cli(capsys, 'call', '1', '--service', '/nobody/evaluate',
                  '--timeout', SHORT_TIMEOUT_S)
    assert run.code == 1 and run.out == ''
    assert run.err == ('cam_ros call: service /nobody/evaluate is not available within 0.5 s '
                       f'(ROS_DOMAIN_ID={ros_domain}; similar services available: '
                       'none discovered yet)\n')


def test_not_available_names_the_domain_and_similar_names(cam_node, ros_domain, capsys):
    # 5 s: under load, a fresh participant can take over 2 s to discover the node's services.
    run = run_cli(capsys, 'call', '1', '--service', '/cma/evaluate', '--timeout', 5.0)
    assert run.code == 1 and run.out == ''
    assert run.err.startswith('cam_ros call: service /cma/evaluate is not available within 5 s '
                              f'(ROS_DOMAIN_ID={ros_domain}; similar services available: ')
    assert '/cam/evaluate' in run.err and len(run.err.splitlines()) == 1
    run = run_cli(capsys, 'echo', '/cam/joint_state', '--timeout', 5.0)
    assert run.code == 1 and run.out == ''
    assert run.err.startswith('cam_ros echo: no publisher of /cam/joint_state within 5 s '
                              f'(ROS_DOMAIN_ID={ros_domain}; similar topics available: ')
    assert '/cam/joint_states' in run.err


@pytest.mark.parametrize('argv, fragment', [
    (['call'], 'required: ANGLE'),
    (['call', 'x'], "argument ANGLE: 'x': must be a finite number"),
    (['call', 'nan'], "'nan': must be a finite number"),
    (['call', '1', '--timeout', '0'], "argument --timeout: '0': must be a finite number > 0"),
    (['echo'], 'required: TOPIC'),
    (['echo', '/x', '--count', '0'], "argument --count: '0': must be an integer >= 1"),
])
def test_bad_ros_arguments_exit_2(argv, fragment, capsys):
    run = run_cli(capsys, *argv)
    assert run.code == 2 and run.out == ''
    assert run.err.splitlines() == [run.err.strip()] and fragment in run.err
    assert run.err.startswith(f'cam_ros {argv[0]}: ')


def test_echo_once_receives_latched_messages_as_yaml(cam_node, capsys):
    run = run_cli(capsys, 'echo', '/cam/pressure_angle', '--once', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    documents = [doc for doc in yaml.safe_load_all(run.out) if doc is not None]
    assert len(documents) == 1  # the text is YAML: one message, then '---'
    message = documents[0]
    assert [dim['label'] for dim in message['layout']['dim']] == [
        'cam_angle_rad,pressure_angle_rad', 'sample']
    profile = cam_node.profile(cam_node.config.sample_count)
    np.testing.assert_array_equal(
        message['data'], np.concatenate([profile.angle, profile.pressure_angle]))

    # A latched message with nested message sequences.
    run = run_cli(capsys, 'echo', '/cam/profile', '--once', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    message = yaml.safe_load(run.out.split('\n---\n')[0])
    assert message['joint_names'] == ['follower'] and message['header']['frame_id'] == 'cam'
    points = message['points']
    assert len(points) == cam_node.config.sample_count
    np.testing.assert_array_equal([p['positions'][0] for p in points], profile.position)
    assert points[90]['time_from_start'] == {'sec': 0, 'nanosec': 250_000_000}  # 90 deg at 1 Hz


def test_echo_csv_flattens_streamed_messages(cam_node, capsys):
    run = run_cli(capsys, 'echo', 'cam/joint_states', '--csv', '--count', '3',
                  '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    rows = list(csv.reader(io.StringIO(run.out)))
    assert rows[0] == ['header.stamp.sec', 'header.stamp.nanosec', 'position[0]', 'position[1]',
                       'velocity[0]', 'velocity[1]']
    values = np.array(rows[1:], dtype=float)
    assert values.shape == (3, 6)
    # Each message pairs the cam joint (-theta: seed 000 turns clockwise, about -z) with the
    # follower position at theta.
    np.testing.assert_allclose(values[:, 3], cam_node.evaluate(-values[:, 2]).position,
                               rtol=1e-12, atol=1e-15)
    assert np.all(values[:, 4] == -cam_node.config.cam_speed)

    # Without a count, the stream ends at the timeout: never before it, and what it printed was
    # published within it (by the messages' own stamps, whatever the machine's load).
    started = time.monotonic()
    run = run_cli(capsys, 'echo', '/cam/state_extras', '--csv', '--timeout', STREAM_TIMEOUT_S)
    assert time.monotonic() - started >= STREAM_TIMEOUT_S
    assert run.code == 0, run.err
    rows = list(csv.reader(io.StringIO(run.out)))
    assert rows[0] == ['header.stamp.sec', 'header.stamp.nanosec', 'vector.x', 'vector.y',
                       'vector.z']
    assert len(rows) > 1  # whatever arrived after discovery (which can take ~3 s)
    stamps = np.array([int(sec) + int(nanosec) * 1e-9 for sec, nanosec, *_ in rows[1:]])
    assert stamps[-1] - stamps[0] <= STREAM_TIMEOUT_S, stamps


def test_echo_gives_up_after_the_timeout_when_nobody_publishes(ros_domain, capsys):
    run = run_cli(capsys, 'echo', '/nobody/here', '--timeout', SHORT_TIMEOUT_S)
    assert run.code == 1 and run.out == ''
    assert run.err == ('cam_ros echo: no publisher of /nobody/here within 0.5 s '
                       f'(ROS_DOMAIN_ID={ros_domain}; similar topics available: '
                       'none discovered yet)\n')
