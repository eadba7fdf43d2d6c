"""slave.state_topic on a real node: the first engagement starts where the driven axis reports.

The node starts disengaged with nothing commanded yet; an axis (as ros2_control's
joint_state_broadcaster does) reports joint `follower` at 1.23 cm. The node holds there, and a
ramp engagement onto a 600 rpm master leaves from it: the first command is the reported
position, then a move onto the cam. A report without joint `follower` is dropped and
counted in the engagement diagnostics, and changes nothing.

The engagement is a move in time with the line shaft at rest where the probes left it (master
angle 0): the design has no slave limits, so the move is no faster and no harder than the cam
itself at cam_speed (V = max |y'| w, A = max |y''| w^2 from a dense scan here), a triangle or
trapezoid of least time; then the line shaft catches up with the master and the commands are the
cam's own.
"""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import ecam_design, engage, master_message, MasterLink, RPM, WAIT_S
from sensor_msgs.msg import JointState
from test_ecam import outputs, reference, stepped

DEFAULT = CONFIG_DIR / 'default.yaml'
AXIS_TOPIC = '/axis/joint_states'
REPORTED = 0.0123  # m: where the axis says the follower is
START_NS = 3_000 * 10 ** 9
DT = 0.004  # 250 Hz
SPEED = 600 * RPM


def axis_state(names, positions) -> JointState:
    return JointState(name=list(names), position=[float(p) for p in positions])


def test_the_first_engagement_leaves_from_the_reported_slave_position(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                'master.timeout:=30.0', '-p', 'master.engage_on_start:=false',
                                '-p', f'slave.state_topic:={AXIS_TOPIC}')
    link = MasterLink(executor)
    axis = link.node.create_publisher(JointState, AXIS_TOPIC, 10)
    deadline = time.monotonic() + WAIT_S
    while axis.get_subscription_count() == 0:
        assert time.monotonic() < deadline, process.log()
        time.sleep(0.05)
    for _ in range(5):  # a broadcaster reports on and on; the bad one in between is dropped
        axis.publish(axis_state(['other_joint'], [0.5]))
        axis.publish(axis_state(['cam', 'follower'], [1.0, REPORTED]))
        time.sleep(0.05)
    link.connect(process)  # probes: the node holds, at rest, where the axis is
    held = [m.data[0] for m in link.messages('commands')]
    assert held and set(held) == {REPORTED}
    assert {m.velocity[1] for m in link.messages('joints')} == {0.0}

    assert engage(executor, True).success
    t = DT * np.arange(500)
    q = 2.0 + SPEED * t
    stream = [master_message(START_NS + round(ti * 1e9), position=(qi,))
              for ti, qi in zip(t.tolist(), q.tolist())]
    before = outputs(link)
    link.send(stream)
    sent, _, commands = stepped(link, before, stream)  # by stamp: a backlog is skipped
    commands = np.array([m.data[0] for m in commands])
    stamps = np.array([m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in sent])
    q = np.array([m.position[0] for m in sent])
    design = ecam_design(DEFAULT)
    exact, _ = reference(design, q, SPEED)
    assert commands[0] == REPORTED  # no step from where the axis is
    rest, _ = reference(design, [0.0], 0.0)  # the cam where the line shaft rests
    arrived = int(np.argmax(commands == rest[0]))
    assert arrived > 0 and np.all(np.diff(commands[:arrived + 1]) <= 0.0)  # straight there
    w, k = (design.config.parameters[name] for name in ('cam_speed', 'slave.scaling'))
    dense = design.program.evaluate(np.linspace(0.0, 2 * math.pi, 400_001))
    fastest, hardest = k * np.abs(dense.ds).max() * w, k * np.abs(dense.d2s).max() * w * w
    velocity = np.diff(commands[:arrived + 1]) / np.diff(stamps[:arrived + 1])
    assert np.abs(velocity).max() <= fastest * (1.0 + 1e-6)
    distance = REPORTED - rest[0]
    least = distance / fastest + fastest / hardest if distance >= fastest ** 2 / hardest \
        else 2.0 * math.sqrt(distance / hardest)
    assert stamps[arrived] - stamps[0] >= least * (1.0 - 1e-6)  # no faster than it can
    assert np.array_equal(commands[-10:], exact[-10:])  # caught up: the cam's own

    engagement = link.diagnostics('cam: engagement',
                                  lambda values: values['message'] == 'engaged')
    assert engagement['slave_state_topic'] == AXIS_TOPIC
    assert 1 <= int(engagement['slave_states_dropped']) <= 5  # best effort: most arrive
    master = link.diagnostics('cam: master', lambda values: True)
    assert master['dropped'] == '0'  # the axis's reports are not the master's
    assert process.process.poll() is None
