"""The installed `cam_ros` executable, run as a user runs it (separate processes)."""
from __future__ import annotations

import json
import subprocess

from cli_support import console_script, DEFAULT_CONFIG, REPO, write_config

from cam_ros.commands.common import load_design

PROCESS_TIMEOUT_S = 60.0
CALL_TIMEOUT_S = 10.0
EXIT_BROKEN_PIPE = 141


def cam_ros(*argv: object) -> subprocess.CompletedProcess:
    """Run the console script in the repository and capture its output."""
    return subprocess.run([console_script(), *(str(arg) for arg in argv)], cwd=REPO,
                          capture_output=True, text=True, timeout=PROCESS_TIMEOUT_S)


def test_report_json_of_the_default_config():
    result = cam_ros('report', 'config/default.yaml', '--json')
    assert result.returncode == 0, result.stderr
    assert result.stderr == ''
    data = json.loads(result.stdout)
    assert data['ok'] is True and data['segments'][1]['peak_velocity'] == 0.16


def test_invalid_config_prints_one_line_and_exits_2(tmp_path):
    config = write_config(tmp_path, 'bad', lambda p: p['motion']['laws'].__setitem__(3, 'shm'))
    result = cam_ros('export', config, '-o', tmp_path / 'cam.dxf')
    assert result.returncode == 2 and result.stdout == ''
    assert result.stderr.count('\n') == 1
    assert result.stderr.startswith("cam_ros export: motion.laws[3] (shm): law = 'shm': ")


def test_plot_needs_no_display(tmp_path):
    target = tmp_path / 'cam.svg'
    result = subprocess.run([console_script(), 'plot', str(DEFAULT_CONFIG), '-o', str(target)],
                            capture_output=True, text=True, timeout=PROCESS_TIMEOUT_S,
                            env={'PATH': '/usr/bin:/bin', 'MPLBACKEND': 'TkAgg'})
    assert result.returncode == 0, result.stderr
    assert target.read_text().startswith('<?xml')


def test_a_closed_output_pipe_stops_quietly():
    process = subprocess.Popen([console_script(), 'sample', str(DEFAULT_CONFIG), '--csv',
                                '--step-deg', '0.001'], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    header = process.stdout.readline()
    process.stdout.close()
    assert process.wait(timeout=PROCESS_TIMEOUT_S) == EXIT_BROKEN_PIPE
    assert header.startswith('angle_rad,position_m,')
    assert process.stderr.read() == ''


def test_call_a_running_cam_node(start_cam_node):
    start_cam_node(DEFAULT_CONFIG)
    result = cam_ros('call', '130', '--deg', '--json', '--timeout', CALL_TIMEOUT_S)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    expected = load_design(DEFAULT_CONFIG).evaluate(data['angle'])
    assert data['position'] == expected.position.tolist()
    assert data['radius_of_curvature'] == expected.radius_of_curvature.tolist()
