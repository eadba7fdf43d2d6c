"""`cam_ros lifecycle get|set` against a real managed cam_node, in process and by exit code."""
from __future__ import annotations

import subprocess
import sys

from cli_support import DEFAULT_CONFIG, run_cli
from conftest import STOP_TIMEOUT_S
from ros.lifecycle_support import managed_node

from cam_ros.cli.arguments import TRANSITIONS
from cam_ros.commands.lifecycle import ENDS_IN

TYPO = ('      offset: 0.5', '      ofset: 0.5')
NOT_AVAILABLE = ('cam_ros lifecycle: /cam: activate is not available from unconfigured '
                 '(available: configure, shutdown)\n')
REFUSED = ('cam_ros lifecycle: /cam refused configure (still unconfigured): follower.ofset = '
           '0.5: is not a cam parameter (did you mean follower.offset?)\n')


def said(capsys, *argv: str) -> tuple[int, str, str]:
    """Run cam_ros in this process; return its exit code, stdout and stderr."""
    run = run_cli(capsys, *argv)
    return run.code, run.out, run.err


def test_the_transitions_set_takes_are_the_ones_it_knows_the_end_of():
    assert set(TRANSITIONS) == set(ENDS_IN)


def test_get_and_set_round_trip_with_the_nodes_reasons(executor, tmp_path, capsys):
    live = tmp_path / 'live.yaml'
    text = DEFAULT_CONFIG.read_text()
    live.write_text(text.replace(*TYPO))
    with managed_node(executor, tmp_path, live) as managed:
        assert said(capsys, 'lifecycle', 'get') == (0, 'unconfigured [1]\n', '')
        assert said(capsys, 'lifecycle', 'set', 'activate') == (1, '', NOT_AVAILABLE)
        assert said(capsys, 'lifecycle', 'set', 'configure') == (1, '', REFUSED)
        assert managed.process.process.poll() is None

        live.write_text(text)
        assert said(capsys, 'lifecycle', 'set', 'configure', '--node', 'cam') == (
            0, 'unconfigured -> inactive\n', '')
        assert said(capsys, 'lifecycle', 'get') == (0, 'inactive [2]\n', '')
        assert managed.state()[1] == 'inactive'

        command = [sys.executable, '-m', 'cam_ros.cli', 'lifecycle']
        done = subprocess.run([*command, 'set', 'activate'], capture_output=True, text=True,
                              timeout=60)
        assert (done.returncode, done.stdout, done.stderr) == (0, 'inactive -> active\n', '')
        done = subprocess.run([*command, 'set', 'bogus'], capture_output=True, text=True,
                              timeout=60)
        assert done.returncode == 2 and done.stdout == '' and done.stderr.count('\n') == 1
        assert "invalid choice: 'bogus'" in done.stderr
        done = subprocess.run([*command, 'get', '--node', '/nobody', '--timeout', '0.5'],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 1 and done.stdout == ''
        assert done.stderr.startswith('cam_ros lifecycle: service /nobody/get_state is not '
                                      'available within 0.5 s'), done.stderr

        assert said(capsys, 'lifecycle', 'set', 'shutdown') == (
            0, 'active -> finalized\n', '')
        assert managed.process.process.wait(timeout=STOP_TIMEOUT_S) == 0
