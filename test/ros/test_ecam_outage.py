"""A real cam_node loses its master: the line shaft coasts, stops on the cam when the master is
lost, and catches up with the master's phase when it returns; never a step, never a freeze.

config/default.yaml has no slave limits: the line shaft's stop is the master's own, over
master.engage_distance_deg of travel from the speed it had (path_limits.master_limit). Commands
are checked against the closed form of config/default.yaml (seed_000_follower).
"""
from __future__ import annotations

import math

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import (constant_speed, MasterLink, seed_000_follower, stamp_of,
                          StateWatch)

DEFAULT = CONFIG_DIR / 'default.yaml'
OFFSET_CM = 0.5
TIMEOUT_S = 0.3
START_NS = 3_000 * 10 ** 9
DT = 0.002  # 500 Hz
TURN = 2 * math.pi
SPEED = 3 * TURN  # 180 rpm before the outage
DISTANCE = math.radians(30.0)  # master.engage_distance_deg's default


def test_a_lost_master_is_a_stop_on_the_cam_and_its_return_a_catch_up(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                f'master.timeout:={TIMEOUT_S}', '-p', f'slave.offset:={OFFSET_CM}')
    offset = OFFSET_CM * 0.01
    link = MasterLink(executor)
    states = StateWatch(link)
    link.connect(process)

    # 1.5 s at constant speed from rest at the probes' position: a master that starts moving.
    q, running = constant_speed(START_NS, 0.0, SPEED, 750, DT)
    running_said = states.count()
    link.send(running)
    sent, answers = link.answered(running)
    q_sent = np.array([m.position[0] for m in sent])
    late = np.array([stamp_of(m) for m in sent]) >= START_NS + 10 ** 9
    position = np.array([m.position[1] for m in answers])
    np.testing.assert_allclose(position[late], seed_000_follower(
        q_sent[late], SPEED, slave_offset=offset)[0], rtol=0, atol=1e-12)  # locked: exact
    # (said while the master ran: on a loaded machine the silence after may be over already)
    states.wait('engaged', since=running_said)

    # Silence: the commands go on (coasting, then a stop on the cam), stamped on, from the
    # answer to the last master message answered (on a loaded machine the stop may be over
    # before the test reads it).
    states.wait('at rest: master lost', timeout=5.0)
    stop = link.after('joints', answers[-1])
    assert len(stop) > 20  # the clock stepped the line shaft: no freeze
    follower = np.array([m.position[1] for m in stop])
    speed = np.array([m.velocity[1] for m in stop])
    assert speed[-1] == 0.0
    stamps = [stamp_of(m) for m in link.messages('joints')]
    assert all(b > a for a, b in zip(stamps, stamps[1:]))  # never backwards
    steepest = np.abs(seed_000_follower(np.linspace(0, TURN, 10_001), 1.0)[1]).max()
    gaps = np.diff([stamp_of(m) for m in stop]) * 1e-9
    assert (np.abs(np.diff(follower)) <= steepest * SPEED * gaps * 1.01).all()  # never faster
    said = [m.message for m in states.inbox.messages]
    assert said[-2:] == ['stopping: master lost', 'at rest: master lost']
    master = link.diagnostics('cam: master', lambda values: values['message'] == 'lost' and
                              values['line_shaft'] != 'stopping: master lost')  # (~1 Hz)
    assert master['level'] == b'\x02' and master['line_shaft'] == 'at rest: master lost'
    rest = follower[-1]

    # The master returns two turns on, elsewhere, at another speed: the line shaft catches up.
    speed_back = -2 * TURN
    q_back, back = constant_speed(START_NS + 2 * 10 ** 9, q[-1] + 2 * TURN + 1.1, speed_back,
                                  1250, DT)
    said = states.count()
    link.send(back)
    sent, answers = link.answered(back)
    position = np.array([m.position[1] for m in answers])
    assert abs(position[0] - rest) <= steepest * abs(speed_back) * DT  # from where it rests
    at = np.array([stamp_of(m) for m in sent])
    locked = at >= START_NS + round(3.5e9)
    closed, closed_velocity = seed_000_follower(np.array([m.position[0] for m in sent]),
                                                speed_back, slave_offset=offset)
    np.testing.assert_allclose(position[locked], closed[locked], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array([m.velocity[1] for m in answers])[locked],
                               closed_velocity[locked], rtol=1e-9, atol=1e-12)
    states.wait('engaged', since=said)  # (silent again since, it may be stopping already)
    assert 'master lost -> ok' in process.log() and 'master back: the line shaft' in process.log()
    assert process.process.poll() is None
