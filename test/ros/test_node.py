"""cam_node as a real process on a private domain, exercised by a separate rclpy client."""
from __future__ import annotations

import math
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import MarkerArray

from cam_ros.core import build_design, parse_parameters, read_parameters_file

CALL_TIMEOUT_S = 10.0
TOPIC_TIMEOUT_S = 10.0
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
DEFAULT = CONFIG_DIR / 'default.yaml'
SAMPLE_ANGLES = np.radians([0.0, 95.0, 135.0, 175.0, 250.0, 330.0])
STATE_RATE_HZ = 20.0
STATE_MESSAGES = 40  # two seconds of state, however long the machine takes to deliver them
STATE_TIMEOUT_S = 30.0
#: The median interval between stamps is the timer's period within this (one late callback
#: shortens the next interval as much as it lengthens its own).
PERIOD_TOLERANCE = 0.1


def evaluate(client, angles) -> EvaluateCam.Response:
    """Call the evaluate service and return the response."""
    response = client.call(EvaluateCam.Request(angles=list(angles)), timeout_sec=CALL_TIMEOUT_S)
    assert response is not None, 'no response from /evaluate'
    return response


def design_with(**updates):
    """Return the default design with some parameters changed (independently of the node)."""
    values = read_parameters_file(DEFAULT)
    values.update(updates)
    return build_design(parse_parameters(values))


def assert_serves(response, design, angles=SAMPLE_ANGLES):
    assert response.success, response.message
    expected = design.evaluate(angles)
    for field in ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                  'radius_of_curvature'):
        np.testing.assert_array_equal(getattr(response, field), getattr(expected, field))


class Inbox:
    """Collect messages of one topic from a subscription made in the test's executor."""

    def __init__(self, node, msg_type, topic, qos):
        self.messages: list = []
        self.arrived = threading.Condition()
        node.create_subscription(msg_type, topic, self._receive, qos)

    def _receive(self, message) -> None:
        with self.arrived:
            self.messages.append(message)
            self.arrived.notify_all()

    def wait(self, count: int = 1, timeout: float = TOPIC_TIMEOUT_S) -> list:
        with self.arrived:
            assert self.arrived.wait_for(lambda: len(self.messages) >= count, timeout), (
                f'{len(self.messages)} of {count} messages in {timeout} s')
            return list(self.messages)


@pytest.mark.parametrize('angles, fragment', [
    ([], 'empty'),
    ([0.1, math.nan], 'angles[1]'),
    ([math.inf], 'finite'),
    ([-math.inf, 0.0], 'finite'),
    ([0.0] * 6, 'output.max_batch = 5'),
])
def test_bad_requests_get_success_false_and_a_reason(start_cam_node, angles, fragment):
    process, client = start_cam_node(DEFAULT, '-p', 'output.max_batch:=5')
    response = evaluate(client, angles)
    assert not response.success
    assert fragment in response.message
    assert len(response.position) == 0
    # The node is unaffected and still answers a good request.
    assert_serves(evaluate(client, SAMPLE_ANGLES[:5]), design_with(), SAMPLE_ANGLES[:5])
    assert process.process.poll() is None


def test_late_subscriber_gets_the_latched_profile_pressure_angle_and_markers(
        start_cam_node, executor):
    start_cam_node(DEFAULT)
    time.sleep(0.5)  # subscribe well after the node published
    listener = executor.node('late_listener')
    profile = Inbox(listener, JointTrajectory, '/cam/profile', LATCHED)
    pressure = Inbox(listener, Float64MultiArray, '/cam/pressure_angle', LATCHED)
    markers = Inbox(listener, MarkerArray, '/cam/markers', LATCHED)

    design = design_with()
    expected = design.profile(design.config.sample_count)
    trajectory = profile.wait()[0]
    assert trajectory.joint_names == ['follower']
    assert len(trajectory.points) == design.config.sample_count == 360
    np.testing.assert_array_equal([p.positions[0] for p in trajectory.points], expected.position)
    np.testing.assert_array_equal([p.accelerations[0] for p in trajectory.points],
                                  expected.acceleration)
    # time_from_start is cam angle / cam speed: 180 deg at 2 pi rad/s is 0.5 s.
    half = trajectory.points[180].time_from_start
    assert (half.sec, half.nanosec) == (0, 500_000_000)

    table = pressure.wait()[0]
    assert [d.size for d in table.layout.dim] == [2, 360]
    data = np.array(table.data).reshape(2, 360)
    np.testing.assert_array_equal(data[0], expected.angle)
    np.testing.assert_array_equal(data[1], expected.pressure_angle)

    drawn = markers.wait()[0]
    namespaces = [marker.ns for marker in drawn.markers]
    assert namespaces == ['cam_surface', 'pitch_curve', 'base_circle']
    base = drawn.markers[2].points
    radii = np.hypot([p.x for p in base], [p.y for p in base])
    np.testing.assert_allclose(radii, 0.04)  # base circle 4 cm


def set_parameters(executor, parameters):
    """Set parameters on /cam atomically through the ROS parameter services."""
    node = executor.node(f'param_client_{time.monotonic_ns()}')
    client = AsyncParameterClient(node, 'cam')
    assert client.wait_for_services(timeout_sec=CALL_TIMEOUT_S)
    future = client.set_parameters_atomically(parameters)
    deadline = time.monotonic() + CALL_TIMEOUT_S
    while not future.done():
        assert time.monotonic() < deadline, 'set_parameters_atomically timed out'
        time.sleep(0.01)
    return future.result().result


def test_accepted_update_rebuilds_and_republishes_rejected_update_keeps_design(
        start_cam_node, executor):
    process, client = start_cam_node(DEFAULT)
    listener = executor.node('profile_listener')
    pressure = Inbox(listener, Float64MultiArray, '/cam/pressure_angle', LATCHED)
    pressure.wait(1)

    result = set_parameters(executor, [Parameter('follower.base_radius', value=5.0),
                                       Parameter('follower.offset', value=0.0)])
    assert result.successful, result.reason
    bigger = design_with(**{'follower.base_radius': 5.0, 'follower.offset': 0.0})
    assert_serves(evaluate(client, SAMPLE_ANGLES), bigger)
    republished = pressure.wait(2)[-1]
    np.testing.assert_array_equal(np.array(republished.data).reshape(2, 360)[1],
                                  bigger.profile(360).pressure_angle)

    # Offset beyond the prime circle: the core rejects it, naming parameter, value and rule.
    result = set_parameters(executor, [Parameter('follower.offset', value=7.0)])
    assert not result.successful
    assert 'follower.offset' in result.reason and '7.0' in result.reason
    # A gap between segments (atomic update of two arrays).
    result = set_parameters(executor, [
        Parameter('motion.start_deg', value=[0.0, 95.0, 180.0, 240.0])])
    assert not result.successful and 'motion.start_deg[1]' in result.reason
    # An int for a double, and an unknown name: refused by the core's check, naming them.
    result = set_parameters(executor, [Parameter('follower.base_radius', value=4)])
    assert not result.successful
    assert result.reason == 'follower.base_radius = 4: must be a double (write 1.0, not 1)'
    result = set_parameters(executor, [Parameter('follower.ofset', value=0.5)])
    assert result.reason == ('follower.ofset = 0.5: is not a cam parameter (did you mean '
                             'follower.offset?)')
    assert_serves(evaluate(client, SAMPLE_ANGLES), bigger)

    reload = listener.create_client(Trigger, '/cam/reload')
    answer = reload.call(Trigger.Request(), timeout_sec=CALL_TIMEOUT_S)
    assert answer.success, answer.message
    assert_serves(evaluate(client, SAMPLE_ANGLES), design_with())
    assert process.stop(signal.SIGINT) == 0


def test_via_point_added_live_then_reload_restores_the_file(start_cam_node, executor):
    process, client = start_cam_node(DEFAULT)
    # The via arrays are empty by default; a polynomial rise through (135 deg, 1.5 cm).
    via = {'motion.laws': ['dwell', 'polynomial', 'dwell', 'simple_harmonic'],
           'motion.via_segment': [1], 'motion.via_deg': [135.0], 'motion.via_position': [1.5]}
    result = set_parameters(executor, [Parameter(name, value=value)
                                       for name, value in via.items()])
    assert result.successful, result.reason
    response = evaluate(client, [math.radians(135.0)])
    assert response.position[0] == pytest.approx(0.015, abs=1e-12)
    assert_serves(evaluate(client, SAMPLE_ANGLES), design_with(**via))

    reload = executor.node('reloader').create_client(Trigger, '/cam/reload')
    answer = reload.call(Trigger.Request(), timeout_sec=CALL_TIMEOUT_S)
    assert answer.success, answer.message
    assert_serves(evaluate(client, SAMPLE_ANGLES), design_with())
    assert process.stop(signal.SIGINT) == 0


def test_live_state_rate_and_values(start_cam_node, executor):
    start_cam_node(DEFAULT, '-p', f'output.state_rate_hz:={STATE_RATE_HZ}')
    listener = executor.node('state_listener')
    joints = Inbox(listener, JointState, '/cam/joint_states', 10)
    joints.wait(2)
    first = len(joints.messages)
    burst = joints.wait(first + STATE_MESSAGES, STATE_TIMEOUT_S)[first:]
    # The rate by the messages' own stamps (node time), not by the arrivals: a late timer
    # callback skips its missed periods, so the typical interval is the period, and no two
    # messages are closer than the timer allows (the clock's jitter aside).
    stamps_ns = np.array([m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in burst])
    intervals = np.diff(stamps_ns) * 1e-9
    period = 1.0 / STATE_RATE_HZ
    assert np.median(intervals) == pytest.approx(period, rel=PERIOD_TOLERANCE), intervals
    assert len(burst) - 1 <= (stamps_ns[-1] - stamps_ns[0]) * 1e-9 / period + 1, intervals
    design = design_with()
    # The default cam turns clockwise: its joint is the rotation about +z, -theta (REP 103).
    angles = -np.array([m.position[0] for m in burst])
    assert all(m.velocity[0] == -design.config.cam_speed for m in burst)
    expected = design.evaluate(angles)
    np.testing.assert_allclose([m.position[1] for m in burst], expected.position, atol=1e-12)
    np.testing.assert_allclose([m.velocity[1] for m in burst], expected.velocity, atol=1e-12)
    assert all(m.name == ['cam', 'follower'] for m in burst)
    # The cam turns at 2 pi rad/s: stamps and angles advance together.
    turned = np.mod(np.diff(angles), 2 * math.pi)
    np.testing.assert_allclose(turned, intervals * 2 * math.pi, atol=1e-9)


@pytest.mark.parametrize('sig', [signal.SIGINT, signal.SIGTERM])
def test_clean_exit_on_signal(start_cam_node, sig):
    process, _ = start_cam_node(DEFAULT)
    assert process.stop(sig) == 0, process.log()
    assert 'Traceback' not in process.log()


def test_invalid_params_file_exits_2_naming_the_parameter(ros_domain, tmp_path):
    bad = tmp_path / 'bad.yaml'
    bad.write_text(DEFAULT.read_text().replace('roller_radius: 1.0', 'roller_radius: -1.0'))
    result = subprocess.run([sys.executable, '-m', 'cam_ros.node', '--ros-args',
                             '--params-file', str(bad)], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 2, result.stderr
    assert 'follower.roller_radius' in result.stderr and '-1.0' in result.stderr


def test_an_internal_error_rejects_the_update_and_keeps_the_design(ros_context, monkeypatch):
    import cam_ros.node.node as node_module

    node = node_module.CamNode(DEFAULT, context=ros_context)
    try:
        served = node.design

        def broken(values):
            raise ZeroDivisionError('a bug in the core')

        monkeypatch.setattr(node_module, 'machine_from_values', broken)
        result = node.set_parameters([Parameter('follower.base_radius', value=5.0)])[0]
        assert not result.successful
        assert result.reason == "internal error: ZeroDivisionError('a bug in the core')"
        assert node.design is served
        assert node.get_parameter('follower.base_radius').value == 4.0
    finally:
        node.destroy_node()
