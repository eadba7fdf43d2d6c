"""A real cam_node: ~/engage false stops its line shaft on the cam, ~/engage true catches up with
a 600 rpm master without a step, and the cam switches switch at their angles."""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import ecam_design, engage, master_message, MasterLink, RPM, stamp_of, WAIT_S
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


def test_disengaged_it_rests_and_engaged_it_catches_up_with_600_rpm_without_a_step(
        start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                'master.timeout:=30.0', *SWITCHES)
    design = ecam_design(DEFAULT)
    link = MasterLink(executor)
    switches = Inbox(link.node, UInt32, '/cam/switches',
                     QoSProfile(depth=1000, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    link.connect(process)
    answer = engage(executor, False)
    assert answer.success and answer.message.startswith('disengaged')
    held = link.messages('commands')[-1].data[0]
    t = DT * np.arange(1000)  # four seconds at 600 rpm: 40 turns
    q = 2.0 + SPEED * t
    stream = [master_message(START_NS + round(ti * 1e9), position=(qi,))
              for ti, qi in zip(t.tolist(), q.tolist())]
    link.send(stream[:50])
    _, resting = link.answered(stream[:50])
    assert {answer.position[1] for answer in resting} == {held}  # at rest on the cam
    assert engage(executor, True).success
    link.send(stream[50:])
    sent, answers = link.answered(stream[50:])
    positions = np.array([answer.position[1] for answer in answers])
    # No step: the line shaft starts from rest, within the stop over 30 deg of master travel
    # from cam speed (the design has no slave limits): its first move is a tiny one.
    assert abs(positions[0] - held) < 1e-6
    # Caught up: the commands are the cam at the master's positions again, exactly.
    at = np.array([stamp_of(message) for message in sent])
    locked = at >= START_NS + round(2.5e9)
    exact, cam_velocity = reference(design, np.array([m.position[0] for m in sent]), SPEED)
    np.testing.assert_allclose(positions[locked], exact[locked], rtol=0, atol=1e-12)
    velocity = np.array([answer.velocity[1] for answer in answers])
    np.testing.assert_allclose(velocity[locked], cam_velocity[locked], rtol=1e-6, atol=1e-9)
    master = link.diagnostics('cam: master', lambda v: v['line_shaft'] == 'locked')
    assert float(master['lag_deg']) == 0.0 and int(master['filtered_steps']) > 0
    # Switches: the glue track is on where the cam angle + lead * speed is in [40, 100) deg;
    # the last edges are those of the locked stretch.
    phase = np.degrees(q[-375:] + 0.002 * SPEED) % 360.0
    expected = ((phase >= 40.0) & (phase < 100.0)).astype(int)
    changes = expected[np.flatnonzero(np.diff(expected)) + 1].tolist()
    assert len(changes) >= 2 * 14
    deadline = time.monotonic() + WAIT_S  # until the last edge has arrived (or the deadline)
    while ([m.data for m in switches.messages][-len(changes):] != changes
           and time.monotonic() < deadline):
        time.sleep(0.05)
    assert [m.data for m in switches.messages][-len(changes):] == changes
    state = link.diagnostics('cam: engagement', lambda v: v['message'] == 'engaged')
    assert state['switches'] in ('0', '1') and state['engage_mode'] == 'ramp'
    assert process.process.poll() is None
