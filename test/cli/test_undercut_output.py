"""An undercut cam with dynamics: every design command says so plainly and prints no warnings."""
from __future__ import annotations

import json
import subprocess

import pytest
from cli_support import console_script, write_config


def undercut_with_dynamics(parameters: dict) -> None:
    # Seed 000's motion on a flat face with a 3.2 cm base circle is undercut near 155 deg
    # (config/seed_flat.yaml); with a follower train the contact stress is undefined there.
    parameters['follower'] = {'type': 'translating_flat', 'base_radius': 3.2}
    parameters['limits']['min_radius_of_curvature'] = 0.0
    parameters['limits']['contact_stress'] = 1.0e9
    parameters['dynamics'] = {'mass': 1.0, 'spring_rate': 1000.0, 'spring_preload': 50.0}
    parameters['contact'] = {'face_width': 1.0}


@pytest.fixture(scope='module')
def config(tmp_path_factory):
    return write_config(tmp_path_factory.mktemp('undercut'), 'undercut', undercut_with_dynamics)


def run(*argv) -> subprocess.CompletedProcess:
    return subprocess.run([console_script(), *map(str, argv)], capture_output=True, text=True,
                          timeout=120)


@pytest.mark.parametrize('command', [
    ['report'], ['report', '--json'], ['sample', '--step-deg', '1'], ['sample', '--json'],
    ['plot', '-o', 'cam.png'], ['export', '-o', 'cam.dxf'],
    ['export', '-o', 'table.csv', '--cam-table']])
def test_no_command_prints_anything_but_its_own_lines_on_stderr(config, tmp_path, command):
    argv = [command[0], config, *[str(tmp_path / a) if a.endswith(('.png', '.dxf', '.csv'))
                                  else a for a in command[1:]]]
    result = run(*argv)
    assert result.returncode == 1  # undercut: the verdict fails, the output is still written
    others = [line for line in result.stderr.splitlines()
              if not line.startswith(f'cam_ros {command[0]}: warning: ')]
    assert others == []


def test_the_report_says_undefined_not_inf_or_nan(config):
    text = run('report', config).stdout
    line = next(line for line in text.splitlines() if line.startswith('Contact stress'))
    assert 'undefined (undercut) from 15' in line and 'VIOLATED' in line
    assert 'inf' not in text.split() and 'nan' not in text.lower().split()
    data = json.loads(run('report', config, '--json').stdout)
    assert data['contact_stress_max'] is None and data['contact_stress_ok'] is False
    assert any('undefined (undercut)' in warning for warning in data['warnings'])
