"""A real cam_node engages onto a 600 rpm master without a step and drives cam switches."""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import ecam_design, engage, master_message, MasterLink, RPM, WAIT_S
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import UInt32
from test_ecam import reference
from test_node import Inbox

DEFAULT = CONFIG_DIR / 'default.yaml'
START_NS = 2_000 * 10 ** 9
DT = 0.004  # 250 Hz
SPEED = 600 * RPM
DISTANCE = math.radians(30.0)
SWITCHES = ('-p', 'switches.names:=[glue]', '-p', 'switches.on_deg:=[40.0]', '-p',
            'switches.off_deg:=[100.0]', '-p', 'switches.lead_time:=[0.002]')


def test_ramp_engage_onto_600_rpm_and_switch_edges_at_their_angles(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                'master.timeout:=30.0', *SWITCHES)
    design = ecam_design(DEFAULT)
    link = MasterLink(executor)
    switches = Inbox(link.node, UInt32, '/cam/switches',
                     QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    link.connect(process)
    answer = engage(executor, False)
    assert answer.success and answer.message.startswith('disengaged')
    held = link.messages('commands')[-1].data[0]
    t = DT * np.arange(250)  # one second at 600 rpm: ten turns
    q = 2.0 + SPEED * t
    stream = [master_message(START_NS + round(ti * 1e9), position=(qi,))
              for ti, qi in zip(t.tolist(), q.tolist())]
    before = len(link.messages('commands'))
    link.send(stream[:50])
    assert [m.data[0] for m in link.messages('commands')[before:]] == [held] * 50
    assert engage(executor, True).success
    link.send(stream[50:])
    commands = np.array([m.data[0] for m in link.messages('commands')[before + 50:]])
    joints = link.messages('joints')[-200:]
    q_run = q[50:]
    exact, cam_velocity = reference(design, q_run, SPEED)
    assert commands[0] == held  # the blend starts where the slave holds: no step
    # The quintic blend written out: held + b(u) (cam - held), u the master travel / distance.
    u = np.minimum((q_run - q_run[0]) / DISTANCE, 1.0)
    b, db = 10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5, 30 * u ** 2 * (1 - u) ** 2
    np.testing.assert_allclose(commands, held + b * (exact - held), rtol=0, atol=1e-12)
    follower_velocity = np.array([m.velocity[1] for m in joints])
    np.testing.assert_allclose(follower_velocity, b * cam_velocity + db / DISTANCE * (
        exact - held) * SPEED, rtol=1e-6, atol=1e-9)
    assert follower_velocity[0] == 0.0
    speeds = np.array([m.velocity[0] for m in joints])
    steady = np.arange(speeds.size) >= 3
    np.testing.assert_allclose(speeds[steady], SPEED, rtol=1e-9)  # exact at constant speed
    # Switches: the glue track is on where the cam angle + lead * speed is in [40, 100) deg.
    phase = np.degrees(q + 0.002 * SPEED) % 360.0
    expected = ((phase >= 40.0) & (phase < 100.0)).astype(int)
    changes = expected[np.flatnonzero(np.diff(expected)) + 1].tolist()
    assert len(changes) == 2 * 10
    deadline = time.monotonic() + WAIT_S  # until the last edge has arrived (or the deadline)
    while ([m.data for m in switches.messages][-len(changes):] != changes
           and time.monotonic() < deadline):
        time.sleep(0.05)
    words = [m.data for m in switches.messages]
    assert words[-len(changes):] == changes
    state = link.diagnostics('cam: engagement', lambda v: v['message'] == 'engaged')
    assert state['switches'] in ('0', '1') and state['engage_mode'] == 'ramp'
    assert process.process.poll() is None
