"""The parameters a recording carries: params file in force, parameter events as changes."""

import pytest
from rcl_interfaces.msg import Parameter, ParameterEvent, ParameterType, ParameterValue

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.recording import (open_recording, PARAMETER_EVENTS, parameter_changes, params_file,
                               Recorder)
from cam_ros.recording.parameters import initial_parameters, PARAMETERS_ATTACHMENT

from .recording_support import wait_until

# A design whose numbers have no short decimal form, in mm, with a via point.
VALUES = {
    'length_unit': 'mm', 'rotation': 'counterclockwise', 'cam_speed': 0.1 + 0.2,
    'follower.type': 'translating_roller', 'follower.base_radius': 55.0,
    'follower.roller_radius': 10.0 / 3.0, 'follower.offset': -1e-05,
    'motion.laws': ['polynomial', 'dwell', 'simple_harmonic'],
    'motion.start_deg': [0.0, 130.0, 200.0], 'motion.end_deg': [130.0, 200.0, 360.0],
    'motion.start_position': [0.0, 18.0, 18.0], 'motion.end_position': [18.0, 18.0, 0.0],
    'motion.via_segment': [0], 'motion.via_deg': [100.0], 'motion.via_position': [16.0],
    'motion.scca_fractions': [], 'output.sample_count': 720, 'recording.enabled': True,
    'recording.directory': '123',
}


def test_params_file_reproduces_the_values_and_the_design(tmp_path):
    path = tmp_path / 'in_force.yaml'
    path.write_text(params_file(VALUES, 'in force\nat start'))
    text = path.read_text()
    assert text.startswith('# in force\n# at start\n/**:\n  ros__parameters:\n')
    read = read_parameters_file(path)  # the CLI's and the core's loader
    expected = {name: value for name, value in VALUES.items() if value != []}
    assert read == expected  # exact floats, types kept (the string '123' stays a string)
    assert 'scca_fractions' not in text  # an empty list cannot be typed in a params file
    design, original = build_design(parse_parameters(read)), build_design(
        parse_parameters(VALUES))
    angles = [0.0, 1.0, 1.745, 2.2, 5.0]
    assert design.evaluate(angles).position.tolist() == original.evaluate(
        angles).position.tolist()
    assert '      laws: [polynomial, dwell, simple_harmonic]\n' in text  # lists in flow style


def test_initial_parameters_need_the_node_and_the_attachment(reference):
    # The reference recording has a config attachment but no parameters in force.
    assert initial_parameters(open_recording(reference.path)) == {}


def test_parameter_events_become_changes(reference):
    [change] = parameter_changes(open_recording(reference.path))
    assert (change.node, change.name, change.kind) == ('/reference_source',
                                                       reference.parameter_name, 'changed')
    assert change.old is None and change.new == pytest.approx(0.02)  # declared before recording
    recording = open_recording(reference.path)
    assert recording.start_ns <= change.time_ns <= recording.end_ns
    assert change.text() == f'{reference.parameter_name}: ? -> 0.02'


def event(node: str, kind: str, name: str, value: object) -> ParameterEvent:
    """Build a parameter event of one double or bool parameter."""
    if isinstance(value, bool):
        typed = ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=value)
    else:
        typed = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=float(value))
    return ParameterEvent(node=node, **{f'{kind}_parameters': [Parameter(name=name, value=typed)]})


def test_only_cam_nodes_changes_are_listed(ros, tmp_path):
    """The CLI's helper nodes announce ROS's own parameters: no change of a cam node."""
    path = tmp_path / 'cam.mcap'
    node = ros.node('fake_cam_recorder')
    try:
        publisher = node.create_publisher(ParameterEvent, PARAMETER_EVENTS.name,
                                          PARAMETER_EVENTS.qos)
        events = [event('/cam_ros_param_42', 'new', 'use_sim_time', False),
                  event('/cam_ros_param_42', 'new', 'start_type_description_service', True),
                  event('/cam', 'changed', 'follower.offset', 0.5),
                  event('/other_cam', 'changed', 'follower.base_radius', 40.0)]
        with Recorder(node, path, [PARAMETER_EVENTS], description={'node': '/cam'},
                      attachments={PARAMETERS_ATTACHMENT: params_file(VALUES)}) as recorder:
            assert wait_until(lambda: publisher.get_subscription_count() >= 1)
            for message in events:
                publisher.publish(message)
            assert wait_until(lambda: recorder.message_count >= len(events))
    finally:
        ros.drop(node)
    changes = [(c.node, c.name, c.old, c.new) for c in parameter_changes(open_recording(path))]
    assert changes == [('/cam', 'follower.offset', -1e-05, 0.5),
                       ('/other_cam', 'follower.base_radius', None, 40.0)]
