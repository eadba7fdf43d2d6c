"""A real cam_node loses its master and engages again in each master.engage_mode when it returns.

The master runs at constant speed and stops sending for longer than master.timeout (the node
holds: its last position, velocity 0, `lost`), then returns at another position and speed. Each
command after the return is checked against the core's ElectronicCam and Blend built here from the
same parameters, and against the closed form of config/default.yaml (seed_000_follower).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import (constant_speed, ecam_design, MasterLink, seed_000_follower,
                          StateWatch)

from cam_ros.core.ecam.engage import Blend, Held
from cam_ros.core.ecam.master import chain_rule, ElectronicCam, MasterConfig

DEFAULT = CONFIG_DIR / 'default.yaml'
OFFSET_CM = 0.5  # slave.offset: the cam's dwell at 0-90 deg is at 0.5 cm
TIMEOUT_S = 0.3
START_NS = 3_000 * 10 ** 9
DT = 0.002  # 500 Hz
TURN = 2 * math.pi
SPEED = 3 * TURN  # 180 rpm before the outage: 2.16 deg per message
DISTANCE = math.radians(30.0)  # master.engage_distance_deg's default
#: mode: (cam angle where the master goes silent, where it returns (deg), its speed on return).
#: next_cycle can only start from a held position that the cam commands at rest at angle 0:
#: the master stops in the dwell there. The others stop in the rise (1.1 cm).
CASES = {'immediate': (135.0, 330.0, 2 * TURN),
         'ramp': (135.0, 330.0, -2 * TURN),
         'next_cycle': (45.0, 200.0, 2 * TURN)}
#: ~/state from the outage on.
STATES = {'immediate': ['holding: master lost', 'engaged'],
          'ramp': ['holding: master lost', 'engaging', 'engaged'],
          'next_cycle': ['holding: master lost', 'waiting for the cycle start', 'engaged']}


@pytest.mark.parametrize('mode', CASES)
def test_master_outage_holds_then_the_return_engages_in_the_mode(
        mode, start_cam_node, executor):
    stop_deg, return_deg, return_speed = CASES[mode]
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                f'master.timeout:={TIMEOUT_S}', '-p',
                                f'master.engage_mode:={mode}', '-p', f'slave.offset:={OFFSET_CM}')
    design = ecam_design(DEFAULT, **{'slave.offset': OFFSET_CM})
    cam = ElectronicCam(design.program, MasterConfig.from_config(design.config).mapping)
    offset = OFFSET_CM * 0.01
    link = MasterLink(executor)
    states = StateWatch(link)
    link.connect(process)

    # 1.5 turns at constant speed up to the stop (engaged on the cam whatever the mode).
    count = 250
    q_stop = TURN + math.radians(stop_deg)
    _, running = constant_speed(START_NS, q_stop - SPEED * DT * (count - 1), SPEED, count, DT)
    link.send(running)
    last = link.answers(running)[-1]
    held = last.position[1]
    np.testing.assert_allclose(held, seed_000_follower(q_stop, SPEED, slave_offset=offset)[0],
                               rtol=0, atol=1e-12)
    assert held == float(cam.setpoints(q_stop).position)

    # Silence: one hold command (the last position), zero speeds, `lost`.
    commands, joints = len(link.messages('commands')), len(link.messages('joints'))
    assert link.inbox['commands'].wait(commands + 1)[commands].data[0] == held
    hold = link.inbox['joints'].wait(joints + 1)[joints]
    assert list(hold.velocity) == [0.0, 0.0] and hold.position[1] == held
    master = link.diagnostics('cam: master', lambda values: values['message'] == 'lost')
    assert master['level'] == b'\x02'
    engagement = link.diagnostics('cam: engagement', lambda values: True)
    assert engagement['message'] == 'holding: master lost'
    assert engagement['engage_mode'] == mode
    assert len(link.messages('commands')) == commands + 1  # said once
    states.wait('holding: master lost')  # ~/state may arrive after the diagnostics
    seen = len(states.inbox.messages) - 1  # the states from the hold on

    # The master returns two turns on, at another angle and speed.
    q_back = 3 * TURN + math.radians(return_deg)
    q, back = constant_speed(START_NS + 2 * 10 ** 9, q_back, return_speed, 260, DT)
    link.send(back)
    answers = link.answers(back)
    position = np.array([m.position[1] for m in answers])
    velocity = np.array([m.velocity[1] for m in answers])
    on_cam = cam.setpoints(q, return_speed)
    closed_form, closed_velocity = seed_000_follower(q, return_speed, slave_offset=offset)
    if mode == 'immediate':  # on the cam at once: a step from the held position
        following = np.ones(q.size, dtype=bool)
        assert abs(position[0] - held) > 0.005
    elif mode == 'ramp':  # from the held position onto the cam over DISTANCE: no step
        blend = Blend(Held(held), cam, q_back, DISTANCE)
        path = chain_rule(cam.mapping.cam_angle(q), blend.derivatives(q), return_speed, 0.0)
        following = np.abs(q - q_back) >= DISTANCE
        assert position[0] == held and velocity[0] == 0.0
        np.testing.assert_allclose(position, path.position, rtol=0, atol=1e-15)
        np.testing.assert_allclose(velocity, path.velocity, rtol=1e-12, atol=1e-15)
        u = np.minimum(np.abs(q - q_back) / DISTANCE, 1.0)
        b = 10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5
        np.testing.assert_allclose(position, held + b * (closed_form - held), rtol=0,
                                   atol=1e-12)
        # A step of the blend is no larger than the quintic's steepest over one message.
        stride = abs(return_speed) * DT
        steepest = 1.875 * np.abs(closed_form - held).max() / DISTANCE + np.abs(
            closed_velocity).max() / abs(return_speed)
        assert np.abs(np.diff(position)).max() <= steepest * stride
        assert following.sum() > 200
    else:  # holds until the cam angle passes 0, then the cam
        crossing = np.flatnonzero(np.diff(np.floor(q / TURN)))[0] + 1
        following = np.arange(q.size) >= crossing
        assert held == offset  # the cam's value at rest at angle 0
        np.testing.assert_array_equal(position[:crossing], held)
        np.testing.assert_array_equal(velocity[:crossing], 0.0)
        assert np.abs(on_cam.position[:crossing] - held).max() > 0.015  # following would show
        assert np.ptp(position[crossing:]) > 0.019  # the next rise is followed
    np.testing.assert_allclose(position[following], on_cam.position[following], rtol=1e-12,
                               atol=0)
    np.testing.assert_allclose(position[following], closed_form[following], rtol=0, atol=1e-12)
    np.testing.assert_allclose(velocity[following], on_cam.velocity[following], rtol=1e-12,
                               atol=1e-15)
    np.testing.assert_allclose(velocity[following], closed_velocity[following], rtol=1e-9,
                               atol=1e-12)
    states.wait('engaged')
    assert [m.message for m in states.inbox.messages[seen:]] == STATES[mode]
    assert 'master lost -> ok' in process.log()
