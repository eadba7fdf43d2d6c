"""~/switch_state on a real node: each switch word with the stamp and position it was found at.

Two tracks, glue (40-100 deg) and a 3 deg short one (200-203 deg), on a 60 rpm master sent
at 250 Hz in three stretches. The words are checked against the switch table written out here:
the word just past every edge the master crosses between two messages, in order, each with the
later message's stamp and position. A jump over the short track between two messages gives its
on and off; the master lost (silent past master.timeout) while it passes the short track gives
neither: the word after the return is the state at the first message, said only if it changed.
"""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import master_message, MasterLink, stamp_of, WAIT_S
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
    link.connect(process)  # at position 0: the word 0, said once
    assert [(m.bits, m.master_position) for m in states.messages] == [(0, 0.0)]
    assert [m.data for m in words.messages] == [0]
    # 0.06 deg to 195 deg, a jump to 205 deg (over the short track), on to 550 deg; lost; from
    # 570 deg (the short track of the second turn passed while lost) to 640 deg; lost; from
    # 770 deg (glue on) to 800 deg.
    first = list(np.arange(0.06, 195.0, STEP_DEG)) + list(np.arange(205.0, 550.0, STEP_DEG))
    stretches = [first, list(np.arange(570.0, 640.0, STEP_DEG)),
                 list(np.arange(770.0, 800.0, STEP_DEG))]
    expected, stamp_ns, previous, now = [], START_NS, 0.0, 0
    for number, degrees in enumerate(stretches):
        stream = []
        for index, angle in enumerate(degrees):
            stamp_ns += round(DT * 1e9)
            stream.append(master_message(stamp_ns, position=(math.radians(angle),),
                                         velocity=(2 * math.pi,)))
            returned = number > 0 and index == 0  # the first message after a loss
            for bits in [word(angle)] if returned else crossed(previous, angle):
                if bits != now:  # said when it changes
                    expected.append((stamp_ns, math.radians(angle), bits))
                    now = bits
            previous = angle
        link.stream(stream, DT).join()
        link.answers(stream)
        if number < len(stretches) - 1:
            time.sleep(0.1)
            said = len(states.messages)
            time.sleep(2 * TIMEOUT_S)  # lost: the tracks forget the master, nothing is said
            assert len(states.messages) == said
    deadline = time.monotonic() + WAIT_S
    while len(states.messages) < 1 + len(expected) and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.2)
    heard = [(stamp_of(m), m.master_position, m.bits) for m in states.messages[1:]]
    assert heard == expected
    # What the table says, spelled out: glue on/off in each turn of the first stretch; the short
    # track's on and off at the jump, both with the stamp of 205 deg; nothing of the short track
    # passed while lost; glue on at the first message after the second return (770 deg).
    jump = next(m for m in heard if m[2] == 2)
    assert [m for m in heard if m[0] == jump[0]] == [jump, (jump[0], math.radians(205.0), 0)]
    assert [bits for _, _, bits in heard] == [1, 0, 2, 0, 1, 0, 1]
    assert heard[-1][1:] == (math.radians(770.0), 1)
    assert [m.data for m in words.messages[1:]] == [bits for _, _, bits in expected]
