"""cam_node as a real process: bad params files, -p overrides and arguments, --help, ~/reload.

A params file the node refuses must give exactly the CLI's one-line error (after the program's
prefix), exit 2, print no traceback and write nothing; the node must never start serving a
design other than the one the file gives.
"""
from __future__ import annotations

import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR
import rclpy
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from std_srvs.srv import Trigger

from cam_ros.cli import main as cli_main
from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.node.node import CamNode
from cam_ros.node.parameters import USAGE

DEFAULT = CONFIG_DIR / 'default.yaml'
DEFAULT_TEXT = DEFAULT.read_text()
NODE = [sys.executable, '-m', 'cam_ros.node']
RUN_TIMEOUT_S = 60.0
CALL_TIMEOUT_S = 10.0
WORKERS = 4
SAMPLE_ANGLES = np.radians([0.0, 95.0, 135.0, 175.0, 250.0, 330.0])


def edited(old: str, new: str) -> str:
    assert old in DEFAULT_TEXT, old
    return DEFAULT_TEXT.replace(old, new)


BAD_FILES = {
    # issue 18: a typo in an optional key used to serve offset 0 and say nothing
    'optional_key_typo': edited('      offset: 0.5', '      ofset: 0.5'),
    'limits_key_typo': edited('      pressure_angle_deg: 30.0', '      pressure_angle_deg: 30.0\n'
                              '      pressure_angle_limit_deg: 25.0'),
    'required_key_typo': edited('      roller_radius: 1.0', '      rollr_radius: 1.0'),
    'int_for_double': edited('base_radius: 4.0', 'base_radius: 4'),
    'yaml_syntax': edited('start_deg: [0.0, 90.0, 180.0, 240.0]', 'start_deg: [0.0, 90.0'),
    'ros_parameters_typo': edited('ros__parameters', 'ros_parameters'),
    'wrong_node_key': edited('/**:', 'cam_node:'),
    # issue 16: careless and hostile files
    'duplicate_key': edited('      roller_radius: 1.0', '      roller_radius: 1.0\n'
                            '      roller_radius: 3.5'),
    'alias_bomb': edited('    follower:\n', '    follower:\n      a0: &a0 [lol, lol, lol]\n'
                         + ''.join(f'      a{i}: &a{i} [*a{i - 1}, *a{i - 1}, *a{i - 1}]\n'
                                   for i in range(1, 30))),
    'huge_array': edited('start_deg: [0.0, 90.0, 180.0, 240.0]',
                         f'start_deg: [{", ".join(["0.0"] * 100_000)}]'),
}
EXPECTED = {  # the line both programs must give (after their prefixes), for the first cases
    'optional_key_typo': 'follower.ofset = 0.5: is not a cam parameter (did you mean '
                         'follower.offset?)',
    'limits_key_typo': 'limits.pressure_angle_limit_deg = 25.0: is not a cam parameter (did you '
                       'mean limits.pressure_angle_deg?)',
    'required_key_typo': 'follower.rollr_radius = 1.0: is not a cam parameter (did you mean '
                         'follower.roller_radius?)',
    'int_for_double': 'follower.base_radius = 4: must be a double (write 1.0, not 1)',
}


def run(command: list[str], cwd: Path) -> subprocess.CompletedProcess:
    """Run a command to its end, capturing its output."""
    return subprocess.run(command, capture_output=True, text=True, cwd=cwd,
                          timeout=RUN_TIMEOUT_S)


def cli_line(path: Path, capsys: pytest.CaptureFixture) -> str:
    """Return the CLI's one-line error for a config file, without its 'cam_ros report: '."""
    assert cli_main(['report', str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == '' and err.count('\n') == 1, err
    return err.rstrip('\n').removeprefix('cam_ros report: ')


def assert_one_line(result: subprocess.CompletedProcess, expected: str) -> None:
    """Check a run exited 2 with exactly 'cam_node: expected' on stderr and nothing else."""
    assert result.returncode == 2, (result.returncode, result.stderr)
    assert result.stdout == '', result.stdout
    assert result.stderr == f'cam_node: {expected}\n', result.stderr


def test_a_bad_params_file_gives_the_clis_line_and_exit_2(ros_domain, tmp_path, capsys):
    folders = {name: tmp_path / name for name in BAD_FILES}
    paths = {}
    for name, text in BAD_FILES.items():
        folders[name].mkdir()
        paths[name] = folders[name] / 'cam.yaml'
        paths[name].write_text(text)
    with ThreadPoolExecutor(WORKERS) as pool:
        results = dict(zip(BAD_FILES, pool.map(
            lambda name: run([*NODE, '--ros-args', '--params-file', str(paths[name])],
                             folders[name]), BAD_FILES)))
    for name, result in results.items():
        expected = cli_line(paths[name], capsys)
        assert expected == EXPECTED.get(name, expected), name
        assert len(expected) < 400, (name, expected)
        assert_one_line(result, expected)
        assert sorted(p.name for p in folders[name].iterdir()) == ['cam.yaml'], name


def test_a_missing_params_file_gives_the_clis_line(ros_domain, tmp_path, capsys):
    missing = tmp_path / 'missing.yaml'
    result = run([*NODE, '--ros-args', '--params-file', str(missing)], tmp_path)
    assert_one_line(result, cli_line(missing, capsys))
    assert 'cannot be read (No such file or directory)' in result.stderr


@pytest.mark.parametrize('override, expected', [
    ('follower.ofset:=0.5', 'follower.ofset = 0.5: is not a cam parameter (did you mean '
                            'follower.offset?)'),
    ('follower.base_radius:=4', 'follower.base_radius = 4: must be a double (write 1.0, not 1)'),
    ('follower.offset:=5.0', 'follower.offset = 5.0: needs |offset| < base_radius + '
                             'roller_radius = 5 cm'),
    ('cam:motion.laws:=[dwell]', 'motion.start_deg = [0.0, 90.0, 180.0, 240.0]: must have 1 '
                                 'entries, one per entry of motion.laws'),
    ('follower.offset', "-p = 'follower.offset': must be NAME:=VALUE"),
])
def test_a_bad_override_is_checked_like_the_file(ros_domain, tmp_path, override, expected):
    result = run([*NODE, '--ros-args', '--params-file', str(DEFAULT), '-p', override], tmp_path)
    assert_one_line(result, expected)


def test_help_prints_usage_and_exits_0_and_other_arguments_are_refused(ros_domain, tmp_path):
    result = run([*NODE, '--help'], tmp_path)
    assert (result.returncode, result.stderr) == (0, '')
    assert result.stdout.startswith('usage: cam_node [-h] [--ros-args [--params-file FILE]...')
    assert '\nexit codes:\n' in result.stdout
    result = run([*NODE, '--bogus', '--ros-args', '--params-file', str(DEFAULT)], tmp_path)
    assert_one_line(result, 'unrecognized arguments: --bogus (see cam_node --help)')


def endpoints(node) -> set[str]:
    """Return the names of node's topics and services, its own as ~/name."""
    names = {entity.topic_name for entity in (*node.publishers, *node.subscriptions)}
    names |= {service.srv_name for service in node.services}
    own = f'{node.get_fully_qualified_name()}/'
    return {f'~/{name[len(own):]}' if name.startswith(own) else name for name in names}


def test_help_lists_exactly_the_topics_and_services_of_both_modes(ros_context):
    listed = set(re.findall(r'^  ([~/]\S+) ', USAGE, re.MULTILINE))
    bare = rclpy.create_node('cam', context=ros_context)  # rclpy's own endpoints
    served = set()
    try:
        for source in ('clock', 'topic'):
            node = CamNode(DEFAULT, context=ros_context,
                           parameter_overrides=[Parameter('master.source', value=source)])
            try:
                served |= endpoints(node) - endpoints(bare)
            finally:
                node.destroy_node()
    finally:
        bare.destroy_node()
    assert {'~/dynamics', '~/master', '~/commands', '/diagnostics'} <= served
    assert listed == served


def design_with(**updates: object):
    """Return the default design with some parameters changed, built by the core alone."""
    values = read_parameters_file(DEFAULT)
    values.update(updates)
    return build_design(parse_parameters(values))


def assert_serves(client, design) -> None:
    """Check the node answers exactly as the core evaluates design."""
    response = client.call(EvaluateCam.Request(angles=list(SAMPLE_ANGLES)),
                           timeout_sec=CALL_TIMEOUT_S)
    assert response is not None and response.success, response
    np.testing.assert_array_equal(response.position, design.evaluate(SAMPLE_ANGLES).position)
    np.testing.assert_array_equal(response.pressure_angle,
                                  design.evaluate(SAMPLE_ANGLES).pressure_angle)


def test_later_params_files_and_the_node_section_override_earlier_ones(start_cam_node,
                                                                       tmp_path):
    second = tmp_path / 'second.yaml'
    second.write_text('/**:\n  ros__parameters:\n    follower:\n      offset: 0.0\n'
                      'cam2:\n  ros__parameters:\n    follower:\n      base_radius: 5.0\n'
                      'cam:\n  ros__parameters:\n    follower:\n      base_radius: 6.0\n')
    _, client = start_cam_node(DEFAULT, '--params-file', str(second), '-p',
                               'output.max_batch:=10', name='cam2')
    assert_serves(client, design_with(**{'follower.offset': 0.0, 'follower.base_radius': 5.0}))
    response = client.call(EvaluateCam.Request(angles=[0.0] * 11), timeout_sec=CALL_TIMEOUT_S)
    assert not response.success and 'output.max_batch = 10' in response.message


def test_reload_of_a_file_with_a_typo_answers_false_and_keeps_serving(start_cam_node, executor,
                                                                      tmp_path, capsys):
    live = tmp_path / 'live.yaml'
    live.write_text(DEFAULT_TEXT)
    process, client = start_cam_node(live)
    assert_serves(client, design_with())
    reload = executor.node('reloader').create_client(Trigger, '/cam/reload')

    live.write_text(BAD_FILES['optional_key_typo'])
    answer = reload.call(Trigger.Request(), timeout_sec=CALL_TIMEOUT_S)
    assert not answer.success
    assert answer.message == cli_line(live, capsys) == EXPECTED['optional_key_typo']
    assert_serves(client, design_with())
    live.write_text(BAD_FILES['alias_bomb'])
    answer = reload.call(Trigger.Request(), timeout_sec=CALL_TIMEOUT_S)
    assert not answer.success and 'anchors or aliases' in answer.message
    assert_serves(client, design_with())
    assert process.process.poll() is None

    live.write_text(edited('      offset: 0.5', '      offset: 0.0'))
    answer = reload.call(Trigger.Request(), timeout_sec=CALL_TIMEOUT_S)
    assert answer.success, answer.message
    assert_serves(client, design_with(**{'follower.offset': 0.0}))
    assert 'Traceback' not in process.log()


def test_use_sim_time_from_a_launch_params_file_reaches_the_node(start_cam_node, executor,
                                                                 tmp_path, capsys):
    # launch_ros writes parameters=[{'use_sim_time': True}] as a /** params file like this one.
    launch = tmp_path / 'launch_params.yaml'
    launch.write_text('/**:\n  ros__parameters:\n    use_sim_time: true\n')
    _, client = start_cam_node(DEFAULT, '--params-file', str(launch))
    assert_serves(client, design_with())
    parameters = AsyncParameterClient(executor.node('sim_time_client'), 'cam')
    assert parameters.wait_for_services(timeout_sec=CALL_TIMEOUT_S)
    future = parameters.get_parameters(['use_sim_time'])
    deadline = time.monotonic() + CALL_TIMEOUT_S
    while not future.done():
        assert time.monotonic() < deadline, 'get_parameters timed out'
        time.sleep(0.01)
    assert future.result().values[0].bool_value is True

    launch.write_text('/**:\n  ros__parameters:\n    use_sim_time: 1\n')
    result = run([*NODE, '--ros-args', '--params-file', str(DEFAULT), '--params-file',
                  str(launch)], tmp_path)
    assert_one_line(result, 'use_sim_time = 1: must be a bool')
    assert cli_line(launch, capsys).startswith('use_sim_time = 1: must be a bool')


@pytest.mark.parametrize('arguments, expected', [
    (['-r', 'bad_rule'], "invalid ROS arguments: failed to initialize rcl: Couldn't parse remap "
                         "rule: '-r bad_rule'."),
    (['--log-level', 'bogus'], "invalid ROS arguments: failed to initialize rcl: Couldn't parse "
                               "log level: '--log-level bogus'."),
    (['--params-file'], '--params-file = None: needs a value after it'),
])
def test_bad_ros_arguments_are_one_line_too(ros_domain, tmp_path, arguments, expected):
    result = run([*NODE, '--ros-args', *arguments], tmp_path)
    assert result.returncode == 2 and result.stdout == '', result
    assert result.stderr.count('\n') == 1 and 'Traceback' not in result.stderr, result.stderr
    assert result.stderr.startswith(f'cam_node: {expected}'), result.stderr


def test_a_machine_whose_pairs_collide_is_refused_by_name(ros_domain, tmp_path):
    # config/machine.yaml with the jaw shifted 60 deg earlier: its zone's 70.5 deg of margin to
    # the knife's, less 60, is 10.5 deg, under the pair's 20 (test_machine_node refuses a like
    # shift as a live update).
    result = run([*NODE, '--ros-args', '--params-file', str(CONFIG_DIR / 'machine.yaml'), '-p',
                  'jaw.master.offset_deg:=-60.0'], tmp_path)
    assert_one_line(result, result.stderr.removeprefix('cam_node: ').rstrip('\n'))
    assert result.stderr.startswith('cam_node: interference: zones jaw-knife: smallest margin '
                                    '10.53'), result.stderr
    assert result.stderr.rstrip().endswith('limit >= 20 deg: COLLIDES'), result.stderr
