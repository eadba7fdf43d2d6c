"""The verdict of the design commands: a velocity jump fails it unless the config allows it."""
from __future__ import annotations

import json
import math

import pytest

from cli_support import run_cli, write_config

#: A dwell, then constant velocity 2 cm over 90-180 deg, dwell, harmonic return: ds/dtheta jumps
#: from 0 to 2 cm / (pi/2 rad) at 90 deg and back to 0 at 180 deg.
CONSTANT_VELOCITY_SLOPE = 0.02 / (math.pi / 2)  # m/rad


def constant_velocity_rise(parameters: dict) -> None:
    parameters['motion']['laws'] = ['dwell', 'constant_velocity', 'dwell', 'simple_harmonic']
    parameters['limits']['pressure_angle_deg'] = 45.0


@pytest.fixture
def jumping(tmp_path):
    return write_config(tmp_path, 'velocity_jump', constant_velocity_rise)


def test_a_velocity_jump_fails_report_sample_and_export(jumping, capsys, tmp_path):
    text = run_cli(capsys, 'report', jumping)
    assert text.code == 1
    assert 'infinite acceleration' in text.out
    assert 'meets its limits' not in text.out
    data = json.loads(run_cli(capsys, 'report', jumping, '--json').out)
    assert data['ok'] is False
    jumps = [w for w in data['warnings'] if w.startswith('ds/dtheta jumps')]
    assert len(jumps) == 2
    assert all('limits.allow_velocity_jumps' in w for w in jumps)
    assert f'{CONSTANT_VELOCITY_SLOPE:.6g}' in jumps[0]
    assert run_cli(capsys, 'sample', jumping, '--step-deg', '30').code == 1


def test_allowing_velocity_jumps_passes_the_same_design(tmp_path, capsys):
    def allowed(parameters: dict) -> None:
        constant_velocity_rise(parameters)
        parameters['limits']['allow_velocity_jumps'] = True
    path = write_config(tmp_path, 'allowed', allowed)
    run = run_cli(capsys, 'report', path, '--json')
    data = json.loads(run.out)
    assert run.code == 0 and data['ok'] is True
    jumps = [w for w in data['warnings'] if w.startswith('ds/dtheta jumps')]
    assert len(jumps) == 2 and not any('allow_velocity_jumps' in w for w in jumps)


def test_an_acceleration_jump_stays_a_warning(capsys):
    # The shipped default: harmonic return after a dwell, d2s/dtheta2 jumps at 240 and 360 deg.
    from cli_support import DEFAULT_CONFIG
    run = run_cli(capsys, 'report', DEFAULT_CONFIG, '--json')
    data = json.loads(run.out)
    assert run.code == 0 and data['ok'] is True
    assert any(w.startswith('d2s/dtheta2 jumps') for w in data['warnings'])
