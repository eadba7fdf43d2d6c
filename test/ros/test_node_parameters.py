"""cam_node's command line and parameter sources, without starting ROS."""
from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CONFIG_DIR
from rcl_interfaces.msg import ParameterType

from cam_ros.core import InvalidParameter, read_parameters_file
from cam_ros.core.config.parameters import PARAMETERS, SPECS
from cam_ros.node.parameters import (declared_value, descriptor, parse_command_line,
                                     ParameterSources, reload_parameters)

DEFAULT = CONFIG_DIR / 'default.yaml'
FALLBACK = Path('/fallback.yaml')


def test_parameter_arguments_are_taken_out_and_the_rest_goes_to_rclpy():
    command = parse_command_line(
        ['cam_node', 'extra', '--ros-args', '-r', '__node:=left', '--params-file', 'a.yaml',
         '--log-level', 'debug', '-p', 'follower.offset:=0.0', '--params-file', 'b.yaml',
         '--enable-stdout-logs', '--', 'more', '--ros-args', '--param', 'cam_speed:=1.0',
         '-r', '__ns:=/robot'], FALLBACK)
    assert command.sources == ParameterSources(
        (Path('a.yaml'), Path('b.yaml')), ('follower.offset:=0.0', 'cam_speed:=1.0'), 'left',
        '/robot')
    assert command.sources.full_name == '/robot/left'
    assert command.ros_args == ['cam_node', '--ros-args', '-r', '__node:=left', '--log-level',
                                'debug', '--enable-stdout-logs', '-r', '__ns:=/robot']
    assert command.user_args == ['extra', 'more']


def test_without_a_params_file_the_default_is_read_and_rclpy_gets_no_ros_arguments():
    command = parse_command_line(['cam_node'], FALLBACK)
    assert command.sources.files == (FALLBACK,)
    assert command.ros_args == ['cam_node']
    with pytest.raises(InvalidParameter, match=r"^--params-file = None: needs a value after it$"):
        parse_command_line(['cam_node', '--ros-args', '--params-file'], FALLBACK)


def test_a_remap_for_another_node_leaves_the_name():
    command = parse_command_line(['cam_node', '--ros-args', '-r', 'other:__node:=x', '-r',
                                  'cam:__node:=right', '-r', '/cam/evaluate:=/e'], FALLBACK)
    assert command.sources.node_name == 'right'


def test_sources_read_files_in_order_then_overrides_for_this_node(tmp_path):
    later = tmp_path / 'later.yaml'
    later.write_text('/**:\n  ros__parameters:\n    follower: {offset: 0.25, base_radius: 4.5}\n')
    values = ParameterSources((DEFAULT, later), ('follower.offset:=0.0',
                                                 'other:follower.offset:=9.0',
                                                 'cam:motion.laws:=[dwell, scca]')).read()
    assert (values['follower.offset'], values['follower.base_radius']) == (0.0, 4.5)
    assert values['motion.laws'] == ['dwell', 'scca']
    assert values['follower.roller_radius'] == 1.0  # from the first file
    with pytest.raises(InvalidParameter, match=r"^-p = 'follower.offset': must be NAME:=VALUE$"):
        ParameterSources((DEFAULT,), ('follower.offset',)).read()
    with pytest.raises(InvalidParameter, match=r"^x = '\[1': is not valid YAML at line 1"):
        ParameterSources((DEFAULT,), ('x:=[1',)).read()


def test_declared_values_and_descriptors_follow_the_specs():
    by_name = {spec.name: spec for spec in PARAMETERS}
    given = {'follower.offset': 0.5, 'motion.via_deg': []}
    assert declared_value(by_name['follower.offset'], given) == 0.5
    assert declared_value(by_name['output.sample_count'], given) == 360  # the default
    assert declared_value(by_name['motion.via_deg'], given) is None  # not a byte array
    assert declared_value(by_name['follower.base_radius'], {}) is None  # required, not given
    rate = descriptor(by_name['output.state_rate_hz'])
    assert rate.dynamic_typing and rate.type == ParameterType.PARAMETER_DOUBLE
    assert (rate.floating_point_range[0].from_value, rate.floating_point_range[0].to_value) == (
        0.1, 1000.0)


def test_a_reload_sets_only_real_changes_and_never_the_recording_switch():
    given = read_parameters_file(DEFAULT)
    current = {**given, 'recording.enabled': True, 'motion.via_deg': [10.0]}
    current.update({spec.name: spec.default for spec in PARAMETERS
                    if spec.name not in given and spec.default != []})
    del current['follower.base_radius']  # set nowhere, required: only ever the file's value
    assert 'motion.via_segment' not in current  # declared by type, never given a value
    changes = {param.name: param for param in reload_parameters(
        {**given, 'follower.offset': 0.0, 'follower.base_radius': 4.0}, current, SPECS)}
    assert sorted(changes) == ['follower.base_radius', 'follower.offset', 'motion.via_deg']
    assert changes['follower.offset'].value == 0.0
    assert changes['motion.via_deg'].value == []  # back to the default: a change
    assert changes['motion.via_deg'].type_.value == ParameterType.PARAMETER_DOUBLE_ARRAY
    assert reload_parameters(given, {**current, 'follower.base_radius': 4.0,
                                     'motion.via_deg': []}, SPECS) == []
    assert 'follower.base_radius' not in {
        param.name for param in reload_parameters({}, current, SPECS)}  # required: no default
