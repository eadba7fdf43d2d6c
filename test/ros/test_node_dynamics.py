"""cam_node serving a design with follower dynamics: evaluate fields, ~/dynamics, efforts, MCAP."""
from __future__ import annotations

import signal
import time

import numpy as np
import yaml
from conftest import CONFIG_DIR
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from test_node import evaluate, Inbox

from cam_ros.core import build_design, load_config

MACHINE = CONFIG_DIR / 'machine_dynamics.yaml'  # counter-clockwise: cam joint = theta
DEFAULT = CONFIG_DIR / 'default.yaml'
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
ANGLES = np.radians([0.0, 37.0, 95.0, 150.0, 233.0, 300.0])
DYNAMICS_FIELDS = ('contact_force', 'camshaft_torque', 'contact_stress')


def test_dynamics_in_evaluate_latched_topic_joint_efforts_and_recording(
        start_cam_node, executor, tmp_path):
    folder = tmp_path / 'runs'
    process, client = start_cam_node(MACHINE, '-p', 'recording.enabled:=true',
                                     '-p', f'recording.directory:={folder}')
    design = build_design(load_config(MACHINE))
    forces = design.evaluate(ANGLES).dynamics
    response = evaluate(client, ANGLES)
    assert response.success, response.message
    for field in DYNAMICS_FIELDS:
        np.testing.assert_array_equal(getattr(response, field), getattr(forces, field))
    assert np.all(np.array(response.contact_force) > 0.0)  # the example stays on its cam

    listener = executor.node('dynamics_listener')
    table = Inbox(listener, Float64MultiArray, '/cam/dynamics', LATCHED).wait()[0]
    count = design.config.sample_count
    assert [d.size for d in table.layout.dim] == [4, count]
    assert table.layout.dim[0].label == ('cam_angle_rad,contact_force_N,camshaft_torque_Nm,'
                                         'contact_stress_Pa')
    profile = design.profile(count)
    rows = np.array(table.data).reshape(4, count)
    np.testing.assert_array_equal(rows[0], profile.angle)
    for row, field in zip(rows[1:], DYNAMICS_FIELDS):
        np.testing.assert_array_equal(row, getattr(profile.dynamics, field))

    states = Inbox(listener, JointState, '/cam/joint_states', QoSProfile(depth=50)).wait(5)
    theta = np.array([state.position[0] for state in states])
    expected = design.evaluate(theta).dynamics
    np.testing.assert_allclose([state.effort[0] for state in states], expected.camshaft_torque,
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose([state.effort[1] for state in states], expected.contact_force,
                               rtol=1e-12)
    time.sleep(0.3)
    assert process.stop(signal.SIGINT) == 0, process.log()

    from mcap_ros2.reader import read_ros2_messages
    path = next(folder.glob('*.mcap'))
    (recorded,) = [m.ros_msg for m in read_ros2_messages(str(path), topics=['/cam/dynamics'])]
    np.testing.assert_array_equal(np.array(recorded.data), np.array(table.data))
    efforts = [m.ros_msg.effort for m in read_ros2_messages(str(path),
                                                            topics=['/cam/joint_states'])]
    assert efforts and all(len(effort) == 2 for effort in efforts)


def test_a_design_without_dynamics_answers_empty_arrays(start_cam_node, executor):
    _, client = start_cam_node(DEFAULT)
    response = evaluate(client, ANGLES)
    assert response.success and len(response.position) == ANGLES.size
    for field in DYNAMICS_FIELDS:
        assert len(getattr(response, field)) == 0
    listener = executor.node('dynamics_listener')
    table = Inbox(listener, Float64MultiArray, '/cam/dynamics', LATCHED).wait()[0]
    assert len(table.data) == 0 and [d.size for d in table.layout.dim] == [0, 0]
    state = Inbox(listener, JointState, '/cam/joint_states', QoSProfile(depth=5)).wait()[0]
    assert len(state.effort) == 0


def test_a_clockwise_cam_publishes_minus_the_camshaft_torque_and_logs_its_jump(
        start_cam_node, executor, tmp_path):
    parameters = yaml.safe_load(MACHINE.read_text())
    cam = parameters['/**']['ros__parameters']
    cam['rotation'], cam['cam_speed'] = 'clockwise', 80.0  # over its jump speed (about 62 rad/s)
    config = tmp_path / 'clockwise.yaml'
    config.write_text(yaml.safe_dump(parameters))
    process, _ = start_cam_node(config)
    design = build_design(load_config(config))
    listener = executor.node('clockwise_listener')
    states = Inbox(listener, JointState, '/cam/joint_states', QoSProfile(depth=50)).wait(20)
    cam_joint = np.array([state.position[0] for state in states])
    assert np.all(cam_joint <= 0.0)  # q = -theta: the cam turns about -z
    expected = design.evaluate(-cam_joint).dynamics  # the core's angle theta = -q
    assert np.abs(expected.camshaft_torque).max() > 1.0  # not only dwells: the sign is seen
    np.testing.assert_allclose([state.effort[0] for state in states], -expected.camshaft_torque,
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose([state.effort[1] for state in states], expected.contact_force,
                               rtol=1e-12, atol=1e-9)
    warnings = design.warnings()
    assert any(warning.startswith('the follower leaves the cam between') for warning in warnings)
    log = process.log()
    assert all(warning in log for warning in warnings), log
