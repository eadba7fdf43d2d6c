"""The message printer of `cam_ros echo`: its text is YAML that reads back to the message."""
from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from sensor_msgs.msg import Image, Imu, JointState
from std_msgs.msg import Bool, Byte, Char, Float64MultiArray, MultiArrayDimension, String
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.commands.message_text import message_text, numeric_fields


def as_data(message):
    """Return a message as plain Python data, written independently of the printer."""
    if hasattr(type(message), 'get_fields_and_field_types'):
        return {name: as_data(getattr(message, name))
                for name in type(message).get_fields_and_field_types()}
    if isinstance(message, bytes) and len(message) == 1:
        return message[0]
    if isinstance(message, (list, tuple, np.ndarray)) or hasattr(message, 'tolist'):
        items = message.tolist() if hasattr(message, 'tolist') else message
        return [as_data(item) for item in items]
    return message


def trajectory() -> JointTrajectory:
    message = JointTrajectory(joint_names=['follower', 'cam'])
    message.header.frame_id = 'cam'
    message.points = [JointTrajectoryPoint(positions=[0.1 * k, -1e-300], velocities=[],
                                           accelerations=[math.pi]) for k in range(3)]
    message.points[2].time_from_start.nanosec = 5
    return message


MESSAGES = {
    'nested_sequences': trajectory(),
    'fixed_arrays': Imu(orientation_covariance=np.arange(9.0)),
    'uint8_array': Image(height=2, encoding='mono8', data=[0, 7, 255]),
    'octet': Byte(data=b'\x07'),
    'char': Char(data=65),
    'bool': Bool(data=True),
    'empty_arrays': JointState(),
    'float_forms': Float64MultiArray(data=[1.5, -2.0, 1e20, -1e-300, 5e-324, math.inf,
                                           -math.inf, 0.1 + 0.2]),
}
STRINGS = ['', 'plain', 'two words', 'a: b', ' padded ', 'true', 'null', '1.5', '- item',
           '[x]', "it's", 'say "hi"', 'line\nbreak', '#comment', 'cam_angle_rad,pressure_rad']


@pytest.mark.parametrize('name', sorted(MESSAGES))
def test_text_reads_back_as_yaml_to_the_message(name):
    message = MESSAGES[name]
    assert yaml.safe_load(message_text(message)) == as_data(message)


@pytest.mark.parametrize('text', STRINGS)
def test_any_string_reads_back_unchanged(text):
    message = Float64MultiArray()
    message.layout.dim = [MultiArrayDimension(label=text, size=1, stride=1)]
    assert yaml.safe_load(message_text(message))['layout']['dim'][0]['label'] == text
    assert yaml.safe_load(message_text(String(data=text))) == {'data': text}


def test_not_a_number_reads_back_as_nan():
    data = yaml.safe_load(message_text(Float64MultiArray(data=[math.nan])))['data']
    assert math.isnan(data[0])


def test_nested_sequences_are_indented_like_ros2_topic_echo():
    lines = message_text(trajectory()).splitlines()
    start = lines.index('points:')
    assert lines[start + 1:start + 4] == ['- positions:', '  - 0.0', '  - -1.0e-300']
    assert '  velocities: []' in lines


def test_numeric_fields_flatten_every_number_with_its_path():
    fields = dict(numeric_fields(trajectory()))
    assert fields['header.stamp.sec'] == 0
    assert fields['points[1].positions[0]'] == 0.1
    assert fields['points[2].accelerations[0]'] == math.pi
    assert fields['points[2].time_from_start.nanosec'] == 5
    assert not any(name.startswith(('joint_names', 'header.frame_id')) for name in fields)
    assert dict(numeric_fields(Bool(data=True))) == {'data': 1}
    assert dict(numeric_fields(Byte(data=b'\x07'))) == {'data': 7}
    assert list(numeric_fields(Image(data=[3, 4])))[-2:] == [('data[0]', 3), ('data[1]', 4)]
