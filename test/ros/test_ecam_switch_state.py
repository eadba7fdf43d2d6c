"""~/switch_state on a real node: each switch word with the stamp and position it was found at.

Two tracks, glue (40-100 deg) and a 3 deg short one (200-203 deg), on a 60 rpm master sent
at 250 Hz. The tracks run on the line shaft, as the axes. While it follows the master, the words
are checked against the switch table written out here: the word just past every edge the master
crosses between two messages the node took, in order, each with the later message's stamp and
position; a jump over the short track between two messages gives its on and off. While the
master is silent the line shaft coasts on at its speed, then stops on the cam (master.timeout):
the short track it passes is said, with the master as last heard. When the master comes back,
the line shaft catches up with its phase the nearer way (forward here, over glue on), then
follows it exactly again, a cycle ahead of where it was.
"""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import (master_message, MasterLink, seed_000_follower, stamp_of, StateWatch,
                          WAIT_S)
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import UInt32
from test_node import Inbox

from cam_ros_interfaces.msg import SwitchState

DEFAULT = CONFIG_DIR / 'default.yaml'
TRACKS = {'glue': (40.0, 100.0), 'short': (200.0, 203.0)}  # on, off (deg)
SWITCHES = ('-p', 'switches.names:=[glue, short]', '-p', 'switches.on_deg:=[40.0, 200.0]',
            '-p', 'switches.off_deg:=[100.0, 203.0]')
TIMEOUT_S = 0.5
ECAM = ('-p', 'master.source:=topic', '-p', f'master.timeout:={TIMEOUT_S}', *SWITCHES)
START_NS = 3_000 * 10 ** 9
DT = 0.004  # 250 Hz
STEP_DEG = 1.44  # 60 rpm
DEEP = QoSProfile(depth=1000, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def word(angle_deg: float) -> int:
    """Return the switch word at a master angle (deg; scaling 1, no offset, no lead time)."""
    angle = angle_deg % 360.0
    return sum(1 << bit for bit, (on, off) in enumerate(TRACKS.values()) if on <= angle < off)


def crossed(a: float, b: float) -> list[int]:
    """Return the words just past each edge in (a, b] (deg, rising), then the word at b."""
    edges = sorted(edge + 360.0 * turn for on_off in TRACKS.values() for edge in on_off
                   for turn in range(math.floor(a / 360.0), math.floor(b / 360.0) + 1)
                   if a < edge + 360.0 * turn <= b)
    return [word(edge + 1e-9) for edge in edges] + [word(b)]


def test_switch_state_carries_the_word_the_stamp_and_the_master_position(
        start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, *ECAM)
    link = MasterLink(executor)
    states = Inbox(link.node, SwitchState, '/cam/switch_state', DEEP)
    words = Inbox(link.node, UInt32, '/cam/switches', DEEP)
    states_said = StateWatch(link)
    link.connect(process)  # at position 0: the word 0, said once
    assert [(m.bits, m.master_position) for m in states.messages] == [(0, 0.0)]
    assert [m.data for m in words.messages] == [0]
    # 0.06 deg to 195 deg, a jump to 205 deg (over the short track), on to 470 deg: lost.
    first = list(np.arange(0.06, 195.0, STEP_DEG)) + list(np.arange(205.0, 470.0, STEP_DEG))
    stream = [master_message(START_NS + k * round(DT * 1e9), position=(math.radians(angle),),
                             velocity=(2 * math.pi,)) for k, angle in enumerate(first)]
    # connect's last probe is 0.5 s (master.timeout) old on return: the node may have just
    # stopped the line shaft for a lost master, and would catch up with the stream instead of
    # locking on it. A tenth of a second of master at rest where it was brings it back first.
    at_rest = [master_message(START_NS - k * round(DT * 1e9), velocity=(0.0,))
               for k in range(round(0.1 / DT), 0, -1)]
    link.stream(at_rest + stream, DT).join()
    sent, _ = link.answered(stream)  # by stamp: a backlog is skipped
    paused = time.monotonic()
    expected, previous, now = [], 0.0, 0
    for message in sent:
        angle = math.degrees(message.position[0])
        for bits in crossed(previous, angle):
            if bits != now:  # said when it changes
                expected.append((stamp_of(message), message.position[0], bits))
                now = bits
        previous = angle
    heard = wait_for(states, 1 + len(expected))
    assert heard == expected
    assert [bits for _, _, bits in heard] == [1, 0, 2, 0, 1, 0]
    jump = next(m for m in heard if m[2] == 2)  # on and off, both with the stamp of 205 deg
    assert [m for m in heard if m[0] == jump[0]] == [jump, (jump[0], math.radians(205.0), 0)]

    # Silent: the line shaft coasts on from 469.7 deg at 360 deg/s for master.timeout (to about
    # 650 deg), then stops within 30 deg: over the short track at 560 deg, short of glue at 760
    # (unless the loss is noticed 0.2 s late).
    states_said.wait('at rest: master lost')
    coasted = wait_for(states, 1 + len(expected) + 2)[len(expected):]
    last = sent[-1]
    assert [(position, bits) for _, position, bits in coasted] == [(last.position[0], 2),
                                                                   (last.position[0], 0)]
    assert stamp_of(last) < coasted[0][0] <= coasted[1][0]  # the node's clock, not a master's

    # Back at 420 deg (phase 60 deg): the line shaft, at rest near 680 deg, catches up forward
    # with 780 deg, over glue on at 760 deg, glue off (820) and the short track (920); locked
    # again by 740 deg of master, it follows the master exactly, a cycle ahead: glue at 760 and
    # 820 deg (1120 and 1180) and the short track at 920 deg (1280) at the master's messages.
    start = stamp_of(last) + round((time.monotonic() - paused + 0.01) * 1e9)
    second = [master_message(start + k * round(DT * 1e9), position=(math.radians(angle),),
                             velocity=(2 * math.pi,))
              for k, angle in enumerate(np.arange(420.0, 1000.0, STEP_DEG))]
    link.stream(second, DT).join()
    sent, answers = link.answered(second)
    q = np.array([m.position[0] for m in sent])
    locked = q >= math.radians(740.0)
    position, velocity = seed_000_follower(q[locked], 2 * math.pi)
    np.testing.assert_allclose([m.position[1] for m, on in zip(answers, locked) if on], position,
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose([m.velocity[1] for m, on in zip(answers, locked) if on], velocity,
                               rtol=0, atol=1e-12)
    returned = wait_for(states, 1 + len(expected) + 2 + 8)[len(expected) + 2:]
    assert [bits for _, _, bits in returned] == [1, 0, 2, 0, 1, 0, 2, 0]
    past = [next(m for m in sent if math.degrees(m.position[0]) >= edge)
            for edge in (760.0, 820.0, 920.0, 923.0)]
    assert returned[4:] == [(stamp_of(m), m.position[0], bits)
                            for m, bits in zip(past, (1, 0, 2, 0))]
    time.sleep(0.2)
    assert len(states.messages) == 1 + len(expected) + 2 + 8
    assert [m.data for m in words.messages[1:]] == [m.bits for m in states.messages[1:]]


def wait_for(states: Inbox, count: int) -> list:
    """Wait for count ~/switch_state messages; return all but the first as (stamp, position,
    bits)."""
    deadline = time.monotonic() + WAIT_S
    while len(states.messages) < count:
        assert time.monotonic() < deadline, f'{len(states.messages)} of {count} switch states'
        time.sleep(0.05)
    return [(stamp_of(m), m.master_position, m.bits) for m in states.messages[1:]]
