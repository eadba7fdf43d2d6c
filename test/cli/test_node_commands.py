"""`cam_ros record`, `reload` and `param get|set|list` against a real cam_node."""
from __future__ import annotations

import time

import pytest
import yaml
from cli_support import DEFAULT_CONFIG, load_parameters, run_cli

from cam_ros.core import build_design, CamError, parse_parameters, read_parameters_file
from cam_ros.recording import open_recording

NODE_TIMEOUT_S = 10.0
SHORT_TIMEOUT_S = 0.5
RECORD_AFTER_RELOAD_S = 0.5


@pytest.fixture
def cam_node(start_cam_node, tmp_path):
    """Start cam_node on seed 000, recording into tmp_path/runs; return that folder."""
    folder = tmp_path / 'runs'
    start_cam_node(DEFAULT_CONFIG, '-p', f'recording.directory:={folder}')
    return folder


def param(capsys, *argv):
    return run_cli(capsys, 'param', *argv, '--timeout', NODE_TIMEOUT_S)


def node_reason(**updates) -> str:
    """Return the core's reason for refusing seed 000 with updates (what the node answers)."""
    values = read_parameters_file(DEFAULT_CONFIG)
    values.update(updates)
    with pytest.raises(CamError) as refused:
        build_design(parse_parameters(values))
    return str(refused.value)


def test_param_get_and_list_read_the_node(cam_node, capsys):
    run = param(capsys, 'get', 'follower.base_radius', 'motion.laws', 'motion.via_deg')
    assert run.code == 0, run.err
    assert yaml.safe_load(run.out) == {
        'follower.base_radius': 4.0, 'motion.laws': load_parameters()['motion']['laws'],
        'motion.via_deg': None}  # declared by type, never given a value
    run = param(capsys, 'list')
    assert run.code == 0, run.err
    listed = yaml.safe_load(run.out)
    assert list(listed) == sorted(listed)
    assert listed['follower.offset'] == 0.5 and listed['length_unit'] == 'cm'
    assert listed['use_sim_time'] is False  # every parameter, not only the cam's
    run = param(capsys, 'get', 'follower.rollr_radius')
    assert run.code == 2 and run.out == ''
    assert run.err == ("cam_ros param: NAME = 'follower.rollr_radius': is not a parameter of "
                       '/cam (did you mean follower.roller_radius?)\n')


def test_param_set_is_atomic_and_prints_the_nodes_reason(cam_node, capsys):
    run = param(capsys, 'set', 'follower.base_radius', '5.5', 'follower.offset', '7.0')
    assert run.code == 1 and run.out == ''
    reason = node_reason(**{'follower.base_radius': 5.5, 'follower.offset': 7.0})
    assert run.err == f'cam_ros param: /cam rejected the update: {reason}\n'
    run = param(capsys, 'get', 'follower.base_radius', 'follower.offset')
    assert yaml.safe_load(run.out) == {'follower.base_radius': 4.0, 'follower.offset': 0.5}

    run = param(capsys, 'set', 'follower.base_radius', '5.5', 'follower.offset', '0.0')
    assert run.code == 0, run.err
    assert run.out == 'follower.base_radius: 5.5\nfollower.offset: 0.0\n'
    run = param(capsys, 'get', 'follower.base_radius', 'follower.offset')
    assert yaml.safe_load(run.out) == {'follower.base_radius': 5.5, 'follower.offset': 0.0}

    run = param(capsys, 'set', 'follower.base_radius')
    assert run.code == 2 and 'give a value for every name' in run.err


def test_record_on_off_and_reload(cam_node, capsys):
    run = run_cli(capsys, 'record', 'on', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    [path] = cam_node.glob('*.mcap')
    assert run.out == f'recording to {path}\n'
    run = run_cli(capsys, 'record', 'off', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    assert run.out.startswith('stopped; ') and run.out.endswith(f' messages in {path}\n')
    assert open_recording(path).complete

    assert param(capsys, 'set', 'follower.base_radius', '6.0').code == 0
    run = run_cli(capsys, 'reload', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0, run.err
    assert run.out == f'reloaded {DEFAULT_CONFIG}\n'
    run = param(capsys, 'get', 'follower.base_radius')
    assert yaml.safe_load(run.out) == {'follower.base_radius': 4.0}


def recording_enabled(capsys) -> bool:
    """Return what the node says its recording.enabled parameter is."""
    run = param(capsys, 'get', 'recording.enabled')
    assert run.code == 0, run.err
    return yaml.safe_load(run.out)['recording.enabled']


def test_record_and_recording_enabled_are_one_switch_that_a_reload_leaves_alone(
        start_cam_node, tmp_path, capsys):
    folder, other = tmp_path / 'runs', tmp_path / 'other'
    process, _ = start_cam_node(DEFAULT_CONFIG, '-p', f'recording.directory:={folder}')
    assert recording_enabled(capsys) is False
    assert run_cli(capsys, 'record', 'on', '--timeout', NODE_TIMEOUT_S).code == 0
    [path] = folder.glob('*.mcap')
    assert recording_enabled(capsys) is True

    run = run_cli(capsys, 'reload', '--timeout', NODE_TIMEOUT_S)  # the file says false
    assert run.code == 0 and run.out == f'reloaded {DEFAULT_CONFIG}\n', run
    reloaded_ns = time.time_ns()
    assert recording_enabled(capsys) is True
    time.sleep(RECORD_AFTER_RELOAD_S)
    run = run_cli(capsys, 'record', 'off', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 0 and run.out.startswith('stopped; '), run
    assert run.out.endswith(f' messages in {path}\n')
    stopped_text = run.out.removeprefix('stopped; ').rstrip('\n')
    assert recording_enabled(capsys) is False
    recording = open_recording(path)
    assert recording.complete
    states = [m.message.header.stamp for m in recording.messages(['/cam/joint_states'])]
    assert states[-1].sec * 10**9 + states[-1].nanosec > reloaded_ns  # it ran past the reload

    # Setting the parameter starts and stops as well; ~/record then says the same.
    run = param(capsys, 'set', 'recording.directory', str(other), 'recording.enabled', 'true')
    assert run.code == 0, run.err
    [second] = other.glob('*.mcap')
    run = run_cli(capsys, 'record', 'on', '--timeout', NODE_TIMEOUT_S)
    assert run.out == f'already recording to {second}\n'
    assert param(capsys, 'set', 'recording.enabled', 'false').code == 0
    assert run_cli(capsys, 'record', 'off', '--timeout', NODE_TIMEOUT_S).out == 'not recording\n'
    assert open_recording(second).complete

    log = process.log()  # every start and stop, with its cause
    assert f'recording to {path} (asked on ~/record)' in log
    assert f'recording stopped (asked on ~/record): {stopped_text}' in log
    assert f'recording to {second} (recording.enabled set to true)' in log
    assert 'recording stopped (recording.enabled set to false): ' in log
    assert log.count('recording stopped') == 2 and log.count('recording to ') == 2


def test_a_recording_that_cannot_start_leaves_recording_enabled_false(
        start_cam_node, tmp_path, capsys):
    blocker = tmp_path / 'a_file'
    blocker.write_text('not a folder')
    process, _ = start_cam_node(DEFAULT_CONFIG, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={blocker}')
    assert recording_enabled(capsys) is False  # the start-up recording failed
    assert param(capsys, 'set', 'recording.enabled', 'true').code == 0
    assert recording_enabled(capsys) is False
    run = run_cli(capsys, 'record', 'on', '--timeout', NODE_TIMEOUT_S)
    assert run.code == 1 and f'cannot create recording {blocker}/cam_' in run.err, run
    assert recording_enabled(capsys) is False
    assert process.log().count(f'recording not started: cannot create recording {blocker}') == 3


@pytest.mark.parametrize('argv', [['record', 'on'], ['reload'], ['param', 'list']])
def test_a_missing_node_exits_1_naming_the_domain(argv, ros_domain, capsys):
    run = run_cli(capsys, *argv, '--node', 'nobody', '--timeout', SHORT_TIMEOUT_S)
    assert run.code == 1 and run.out == ''
    service = {'record': 'record', 'reload': 'reload', 'param': 'list_parameters'}[argv[0]]
    assert run.err == (f'cam_ros {argv[0]}: service /nobody/{service} is not available within '
                       f'0.5 s (ROS_DOMAIN_ID={ros_domain}; similar services available: '
                       'none discovered yet)\n')
