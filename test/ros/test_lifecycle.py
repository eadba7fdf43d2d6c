"""cam_node as a managed node, a real process: states, transitions, what each state serves.

The transitions offered in each state are checked against the ROS 2 managed-node state machine
written out in lifecycle_support.ALLOWED (lifecycle_msgs' ids), the design served against the
core's evaluation of the file, the state topic's pace against nothing at all while inactive.
"""
from __future__ import annotations

import time

import numpy as np
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR, SERVICE_TIMEOUT_S, STOP_TIMEOUT_S, wait_for_service
from lifecycle_msgs.msg import State, Transition
from lifecycle_support import ALLOWED, call, managed_node
from rcl_interfaces.srv import ListParameters, SetParameters
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState
from test_node import Inbox

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.recording import open_recording

DEFAULT = CONFIG_DIR / 'default.yaml'
ANGLES = np.radians([0.0, 95.0, 135.0, 250.0])
ROS_OWN = {'use_sim_time', 'start_type_description_service', 'autostart'}
QUIET_S = 0.6  # 30 periods of the 50 Hz state: silence proves it is off
TYPO = ('      offset: 0.5', '      ofset: 0.5')
TYPO_LINE = ('configure failed: follower.ofset = 0.5: is not a cam parameter (did you mean '
             'follower.offset?)')


def design(**updates):
    """Return the default file's design with updates, built by the core alone."""
    values = read_parameters_file(DEFAULT)
    values.update(updates)
    return build_design(parse_parameters(values))


def parameters(managed) -> set[str]:
    """Return the names of the node's parameters."""
    client = managed.node.create_client(ListParameters, '/cam/list_parameters')
    assert client.wait_for_service(timeout_sec=SERVICE_TIMEOUT_S)
    return set(call(client, ListParameters.Request()).result.names)


def until(predicate, what: str, timeout: float = SERVICE_TIMEOUT_S) -> None:
    """Wait until predicate() holds (the graph takes a moment to show a change)."""
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, what
        time.sleep(0.05)


def ended(managed) -> int:
    """Wait for the node process to end by itself; return its exit code."""
    code = managed.process.process.wait(timeout=STOP_TIMEOUT_S)
    assert 'Traceback' not in managed.process.log(), managed.process.log()
    return code


def test_autostart_false_waits_unconfigured_and_each_state_serves_what_it_should(
        executor, tmp_path):
    folder = tmp_path / 'recordings'
    with managed_node(executor, tmp_path, DEFAULT, '-p', 'recording.enabled:=true', '-p',
                      f'recording.directory:={folder}') as managed:
        walk_the_states(managed, folder)


def walk_the_states(managed, folder) -> None:
    """Take a clock-driven node (recording from configure on) through every state."""
    joints = Inbox(managed.node, JointState, '/cam/joint_states', QoSProfile(depth=1000))
    unconfigured = (State.PRIMARY_STATE_UNCONFIGURED, 'unconfigured')
    assert managed.state() == unconfigured
    assert managed.available() == ALLOWED[State.PRIMARY_STATE_UNCONFIGURED]
    assert '/cam/evaluate' not in managed.services()
    assert {'/cam/change_state', '/cam/get_available_transitions'} <= managed.services()
    assert parameters(managed) == ROS_OWN  # the cam parameters come with configure

    # Asked by id for a transition unconfigured lacks: refused, said, and the node lives on.
    assert not managed.change(number=Transition.TRANSITION_ACTIVATE)
    assert not managed.change('deactivate')
    assert managed.state() == unconfigured
    until(lambda: 'transition deactivate is not available' in managed.process.log(), 'no line')
    assert ('transition 3 is not available from unconfigured (available: configure, '
            'shutdown)') in managed.process.log()

    assert managed.change('configure')
    assert managed.state() == (State.PRIMARY_STATE_INACTIVE, 'inactive')
    assert managed.available() == ALLOWED[State.PRIMARY_STATE_INACTIVE]
    assert 'cam_speed' in parameters(managed) and ROS_OWN <= parameters(managed)
    evaluate = managed.node.create_client(EvaluateCam, '/cam/evaluate')
    wait_for_service(evaluate, managed.process, SERVICE_TIMEOUT_S)
    answer = call(evaluate, EvaluateCam.Request(angles=list(ANGLES)))
    np.testing.assert_array_equal(answer.position, design().evaluate(ANGLES).position)
    time.sleep(QUIET_S)
    assert joints.messages == []  # inactive: the clock's state is not published
    update = managed.node.create_client(SetParameters, '/cam/set_parameters')
    assert update.wait_for_service(timeout_sec=SERVICE_TIMEOUT_S)
    radius = Parameter('follower.base_radius', value=4.5).to_parameter_msg()
    assert call(update, SetParameters.Request(parameters=[radius])).results[0].successful
    answer = call(evaluate, EvaluateCam.Request(angles=list(ANGLES)))
    np.testing.assert_array_equal(answer.pressure_angle, design(
        **{'follower.base_radius': 4.5}).evaluate(ANGLES).pressure_angle)

    assert managed.change('activate')
    assert managed.state() == (State.PRIMARY_STATE_ACTIVE, 'active')
    assert managed.available() == ALLOWED[State.PRIMARY_STATE_ACTIVE]
    joints.wait(10)

    assert managed.change('deactivate')
    time.sleep(0.1)  # let the last messages in
    count = len(joints.messages)
    time.sleep(QUIET_S)
    assert len(joints.messages) == count
    assert managed.change('cleanup')
    assert managed.state() == unconfigured
    [recording] = folder.glob('*.mcap')  # started by configure, closed by cleanup
    assert open_recording(recording).complete
    assert 'recording stopped (cleanup)' in managed.process.log()
    until(lambda: '/cam/evaluate' not in managed.services(), '~/evaluate still served')
    assert parameters(managed) == ROS_OWN
    assert '/cam/joint_states' not in dict(managed.node.get_publisher_names_and_types_by_node(
        'cam', '/'))

    assert managed.change('shutdown')  # from unconfigured: the process ends, exit 0
    assert ended(managed) == 0
    assert 'finalized' in managed.process.log()


def test_a_refused_configure_leaves_the_node_unconfigured_and_a_fixed_file_configures(
        executor, tmp_path):
    live = tmp_path / 'live.yaml'
    text = DEFAULT.read_text()
    assert TYPO[0] in text
    live.write_text(text.replace(*TYPO))
    with managed_node(executor, tmp_path, live, '-p', 'cam_speed:=3.0') as managed:
        refuse_then_configure(managed, live, text)


def refuse_then_configure(managed, live, text: str) -> None:
    """Configure a file with a typo (refused), then the file fixed (served), then shut down."""
    assert not managed.change('configure')
    assert managed.state() == (State.PRIMARY_STATE_UNCONFIGURED, 'unconfigured')
    assert managed.process.process.poll() is None
    until(lambda: TYPO_LINE in managed.process.log(), f'no line {TYPO_LINE!r}')
    assert parameters(managed) == ROS_OWN  # nothing declared by the failed configure

    live.write_text(text.replace('base_radius: 4.0', 'base_radius: 4.5'))  # fixed, and changed
    assert managed.change('configure')
    evaluate = managed.node.create_client(EvaluateCam, '/cam/evaluate')
    wait_for_service(evaluate, managed.process, SERVICE_TIMEOUT_S)
    answer = call(evaluate, EvaluateCam.Request(angles=list(ANGLES)))
    served = design(**{'follower.base_radius': 4.5, 'cam_speed': 3.0})  # the -p kept
    for field in ('pressure_angle', 'velocity'):  # the file's radius, the override's speed
        np.testing.assert_array_equal(getattr(answer, field),
                                      getattr(served.evaluate(ANGLES), field))
        assert not np.array_equal(getattr(answer, field), getattr(design().evaluate(ANGLES),
                                                                  field))

    assert managed.change('shutdown')  # from inactive
    assert ended(managed) == 0
    assert managed.process.log().count('configure failed') == 1
