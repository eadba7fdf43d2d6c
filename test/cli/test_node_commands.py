"""`cam_ros record`, `reload` and `param get|set|list` against a real cam_node."""
from __future__ import annotations

import pytest
import yaml
from cli_support import DEFAULT_CONFIG, load_parameters, run_cli

from cam_ros.core import build_design, CamError, parse_parameters, read_parameters_file
from cam_ros.recording import open_recording

NODE_TIMEOUT_S = 10.0
SHORT_TIMEOUT_S = 0.5


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


@pytest.mark.parametrize('argv', [['record', 'on'], ['reload'], ['param', 'list']])
def test_a_missing_node_exits_1_naming_the_domain(argv, ros_domain, capsys):
    run = run_cli(capsys, *argv, '--node', 'nobody', '--timeout', SHORT_TIMEOUT_S)
    assert run.code == 1 and run.out == ''
    service = {'record': 'record', 'reload': 'reload', 'param': 'list_parameters'}[argv[0]]
    assert run.err == (f'cam_ros {argv[0]}: service /nobody/{service} is not available within '
                       f'0.5 s (ROS_DOMAIN_ID={ros_domain}; similar services available: '
                       'none discovered yet)\n')
