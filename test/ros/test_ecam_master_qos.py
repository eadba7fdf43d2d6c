"""cam_node hears any master QoS, warns about incompatible peers and follows wrapping encoders."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import ecam_design, master_message, MasterLink, stamp_of, WAIT_S
from rclpy.qos import (DurabilityPolicy, qos_profile_sensor_data, QoSProfile,
                       ReliabilityPolicy)
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from test_ecam import outputs, stepped

DEFAULT = CONFIG_DIR / 'default.yaml'
TOPIC_MODE = ('-p', 'master.source:=topic', '-p', 'master.timeout:=30.0')
PUBLISHERS = {'reliable': QoSProfile(depth=1000),
              'sensor data': qos_profile_sensor_data}  # best effort, depth 5


@pytest.mark.parametrize('kind', list(PUBLISHERS))
def test_a_master_is_heard_whether_it_publishes_reliable_or_best_effort(start_cam_node, executor,
                                                                        kind):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE)
    link = MasterLink(executor)
    link.publisher = link.node.create_publisher(JointState, '/cam/master', PUBLISHERS[kind])
    link.connect(process)  # fails with the node's log if no command ever comes back
    assert 'master waiting -> ok' in process.log()


def test_an_incompatible_subscriber_gets_a_warning_naming_the_topic(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE)
    link = MasterLink(executor)
    link.connect(process)
    # ~/commands is volatile: a subscriber asking for transient local can never match it.
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                         reliability=ReliabilityPolicy.RELIABLE)
    link.node.create_subscription(Float64MultiArray, '/cam/commands', lambda _: None, latched)
    deadline = time.monotonic() + WAIT_S
    while 'incompatible QoS on /cam/commands' not in process.log():
        assert time.monotonic() < deadline, process.log()
        time.sleep(0.2)
    line = next(line for line in process.log().splitlines()
                if 'incompatible QoS on /cam/commands' in line)
    assert line.startswith('[WARN]') and 'a subscription whose DURABILITY policy' in line


@pytest.mark.parametrize('scaling', [0.5, 2.0, 3.0])
def test_a_wrapping_encoder_commands_what_a_multi_turn_master_does(
        start_cam_node, executor, scaling):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE, '-p', f'master.scaling:={scaling}')
    design = ecam_design(DEFAULT, **{'master.scaling': scaling})
    link = MasterLink(executor)
    link.connect(process)
    stamps = 10 ** 12 + np.arange(1, 800) * 4_000_000  # 250 Hz, 3.2 s
    multi = 0.25 + 12.0 * (stamps - stamps[0]) * 1e-9  # about six master turns
    messages = [master_message(stamp, position=(q,)) for stamp, q in
                zip(stamps.tolist(), np.mod(multi, 2 * math.pi).tolist())]
    before = outputs(link)
    link.send(messages)
    sent, _, commands = stepped(link, before, messages)  # by stamp: a backlog is skipped
    commands = np.array([m.data[0] for m in commands])
    multi = multi[np.isin(stamps, [stamp_of(m) for m in sent])]
    theta = np.mod(multi / scaling, 2 * math.pi)  # MC_CamIn on the multi-turn position
    expected = design.program.evaluate(theta).s
    np.testing.assert_allclose(commands, expected, rtol=0, atol=1e-9)
