"""slave.state_topic on a real node: the first engagement starts where the driven axis reports.

The node starts disengaged with nothing commanded yet; an axis (as ros2_control's
joint_state_broadcaster does) reports joint `follower` at 1.23 cm. The node holds there, and a
ramp engagement onto a 600 rpm master leaves from it: the first command is the reported
position, then the quintic blend onto the cam. A report without joint `follower` is dropped and
counted in the engagement diagnostics, and changes nothing.
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
DISTANCE = math.radians(30.0)


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
    t = DT * np.arange(100)
    q = 2.0 + SPEED * t
    stream = [master_message(START_NS + round(ti * 1e9), position=(qi,))
              for ti, qi in zip(t.tolist(), q.tolist())]
    before = outputs(link)
    link.send(stream)
    sent, _, commands = stepped(link, before, stream)  # by stamp: a backlog is skipped
    commands = np.array([m.data[0] for m in commands])
    q = np.array([m.position[0] for m in sent])
    exact, _ = reference(ecam_design(DEFAULT), q, SPEED)
    assert commands[0] == REPORTED  # no step from where the axis is
    u = np.minimum((q - q[0]) / DISTANCE, 1.0)  # from the first master message taken
    blend = 10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5
    np.testing.assert_allclose(commands, REPORTED + blend * (exact - REPORTED), rtol=0,
                               atol=1e-12)
    assert np.all(u[-10:] == 1.0) and np.array_equal(commands[-10:], exact[-10:])

    engagement = link.diagnostics('cam: engagement',
                                  lambda values: values['message'] == 'engaged')
    assert engagement['slave_state_topic'] == AXIS_TOPIC
    assert 1 <= int(engagement['slave_states_dropped']) <= 5  # best effort: most arrive
    master = link.diagnostics('cam: master', lambda values: True)
    assert master['dropped'] == '0'  # the axis's reports are not the master's
    assert process.process.poll() is None
