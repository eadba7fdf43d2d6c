"""`cam_ros report`'s Slave limits: one line per limited axis (a single cam is the machine of
one axis), the same numbers in --json, checked against seed 000's closed forms."""
from __future__ import annotations

import json
import math

import pytest
from cli_support import CONFIG_DIR, DEFAULT_CONFIG, run_cli

from cam_ros.core.rounding import ceil_sig, floor_sig

OMEGA = 2.0 * math.pi
H = 0.02  # m
#: Seed 000: cycloidal rise of H over 90 deg, simple harmonic return over 120 deg (closed forms).
PEAK_SLOPE = 2.0 * H / (math.pi / 2.0)  # m/rad, the cycloid's 2 h / beta
PEAK_BEND = 2.0 * math.pi * H / (math.pi / 2.0) ** 2  # m/rad^2, 2 pi h / beta^2
RETURN_SLOPE = math.pi * H / (2.0 * (2.0 * math.pi / 3.0))  # m/rad, pi h / (2 beta)


def limited(tmp_path, text: str, extra: str) -> str:
    path = tmp_path / 'limited.yaml'
    path.write_text(text + extra)
    return str(path)


def section(out: str) -> list[str]:
    """Return the lines of the Slave limits section (title, header, rows)."""
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith('Slave limits'))
    end = next(i for i in range(start, len(lines)) if not lines[i].strip())
    return lines[start:end]


def test_a_single_cam_reports_its_limits_in_one_line_and_in_json(tmp_path, capsys):
    config = limited(tmp_path, DEFAULT_CONFIG.read_text(),
                     '    slave:\n      max_velocity: 20.0\n      max_acceleration: 300.0\n'
                     '      direction: positive\n    master:\n      max_speed: 8.0\n')
    run = run_cli(capsys, 'report', config)
    title, header, row = section(run.out)
    assert 'master accel allowed rad/s^2' in header
    cells = row.split()
    assert cells[:2] == ['follower', 'm']
    v_cam, v_max = PEAK_SLOPE * OMEGA, PEAK_SLOPE * 8.0
    a_cam, a_max = PEAK_BEND * OMEGA ** 2, PEAK_BEND * 64.0
    assert (f'{ceil_sig(v_cam)} ok / {ceil_sig(v_max)} EXCEEDS' in row
            and f'{ceil_sig(a_cam)} ok / {ceil_sig(a_max)} EXCEEDS' in row)
    assert f'positive: EXCEEDS (back at {ceil_sig(RETURN_SLOPE * OMEGA)} m/s)' in row
    data = json.loads(run_cli(capsys, 'report', config, '--json').out)['slave_limits']
    assert data['at_cam_speed']['peak_velocity'] == pytest.approx(v_cam, rel=1e-12)
    assert data['at_max_speed']['peak_acceleration'] == pytest.approx(a_max, rel=1e-12)
    assert data['at_max_speed']['velocity_ok'] is False and data['ok'] is False
    assert data['max_velocity'] == pytest.approx(0.2) and data['direction'] == 'positive'
    assert f'{floor_sig(data["max_master_acceleration"])} at ' in row
    assert data['max_master_acceleration_note'] is None and data['direction_ok'] is False
    assert data['backward_velocity'] == pytest.approx(RETURN_SLOPE * OMEGA, rel=1e-9)


def test_an_unlimited_design_has_no_slave_limits_section(capsys):
    run = run_cli(capsys, 'report', DEFAULT_CONFIG)
    assert 'Slave limits' not in run.out
    assert json.loads(run_cli(capsys, 'report', DEFAULT_CONFIG, '--json').out)[
        'slave_limits'] is None


def test_a_machine_reports_one_line_per_limited_axis_in_one_section(tmp_path, capsys):
    text = (CONFIG_DIR / 'machine.yaml').read_text()
    text = text.replace('      slave:\n        offset: -20.0\n',
                        '      slave:\n        offset: -20.0\n        max_velocity: 800.0\n'
                        '        max_acceleration: 2000.0\n        direction: positive\n')
    text = text.replace('      joint: line_shaft\n', '      joint: line_shaft\n'
                        '      max_speed: 12.0\n')
    config = limited(tmp_path, text, '')
    run = run_cli(capsys, 'report', config)
    assert run.out.count('Slave limits') == 1
    title, header, row = section(run.out)
    assert row.split()[:3] == ['knife', 'rad', '10.472']  # 100 cycles/min; 12 rad/s given
    assert 'positive: ok' in row and 'EXCEEDS' in row  # 800 deg/s: over at 12 rad/s only
    axes = json.loads(run_cli(capsys, 'report', config, '--json').out)['axes']
    limits = {axis['name']: axis['slave_limits'] for axis in axes}
    assert limits['feeder'] is None and limits['jaw'] is None
    knife = limits['knife']
    assert knife['at_cam_speed']['velocity_ok'] is True
    assert knife['at_max_speed']['velocity_ok'] is False
    ratio = knife['at_max_speed']['peak_velocity'] / knife['at_cam_speed']['peak_velocity']
    assert ratio == pytest.approx(12.0 / (100.0 / 60.0 * 2.0 * math.pi), rel=1e-12)
