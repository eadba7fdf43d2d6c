"""A real cam_node runs a one-shot cam (master.periodic false): one cycle, hold, ~/engage again.

The slave follows the cam for one master cycle from where it engaged, then holds the position it
reached with velocity 0 (`end of profile` in ~/state and the diagnostics); ~/engage true runs the
cam again from the next master message. Checked against the core's ElectronicCam built here from
the same parameters and the closed form of config/default.yaml.
"""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import (constant_speed, ecam_design, engage, MasterLink, seed_000_follower,
                          stamp_of, StateWatch)

from cam_ros.core.ecam.master import ElectronicCam, MasterConfig

DEFAULT = CONFIG_DIR / 'default.yaml'
START_NS = 4_000 * 10 ** 9
DT = 0.002  # 500 Hz
TURN = 2 * math.pi
SPEED = 2 * TURN  # 120 rpm: 1.44 deg per message
COUNT = 375  # 1.5 turns of master per run


def run_once(link, cam, messages, q, start: float):
    """Send one run; check the cam up to one cycle from start, then the hold; return the end."""
    link.send(messages)
    sent, answers = link.answered(messages)  # by stamp: a backlog is skipped
    q = q[np.isin([stamp_of(m) for m in messages], [stamp_of(m) for m in sent])]
    position = np.array([m.position[1] for m in answers])
    velocity = np.array([m.velocity[1] for m in answers])
    ended = np.abs(q - start) >= TURN  # as the node tests it (master.scaling 1)
    assert 10 < ended.sum() < q.size - 10  # both parts heard (a backlog may be skipped)
    on_cam = cam.setpoints(q, SPEED)
    closed_form, closed_velocity = seed_000_follower(q, SPEED)
    running = ~ended
    np.testing.assert_allclose(position[running], on_cam.position[running], rtol=1e-12, atol=0)
    np.testing.assert_allclose(position[running], closed_form[running], rtol=0, atol=1e-12)
    np.testing.assert_allclose(velocity[running], closed_velocity[running], rtol=1e-9,
                               atol=1e-12)
    end = float(cam.setpoints(start + TURN).position)  # where the cycle ends
    np.testing.assert_allclose(end, seed_000_follower(start, SPEED)[0], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(position[ended], end)
    np.testing.assert_array_equal(velocity[ended], 0.0)
    assert np.abs(on_cam.position[ended] - end).max() > 0.01  # a periodic cam would show
    return end


def test_one_shot_cam_holds_its_end_and_engage_runs_it_again(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                'master.periodic:=false', '-p', 'master.engage_mode:=immediate',
                                '-p', 'master.timeout:=300.0')  # no clock steps in the pause
    design = ecam_design(DEFAULT)
    cam = ElectronicCam(design.program, MasterConfig.from_config(design.config).mapping)
    link = MasterLink(executor)
    states = StateWatch(link)
    link.connect(process)  # the first probe (master at 0) engages: the cycle starts at 0
    q, first = constant_speed(START_NS, 0.0, SPEED, COUNT, DT)
    assert run_once(link, cam, first, q, 0.0) == 0.0  # the cam's start and end
    paused = time.monotonic()
    states.wait('end of profile')
    engagement = link.diagnostics('cam: engagement',
                                  lambda values: values['message'] == 'end of profile')
    assert engagement['periodic'] == 'False' and engagement['level'] == b'\x00'

    answer = engage(executor, True)
    assert answer.success and answer.message == 'engaging (immediate) at the next master message'
    # The master goes on from 180 deg; the slave engages at its next message (in the dwell at
    # 2 cm, a step from 0) and holds at 2 cm one cycle later, where the cam returns to 0.
    q_again = q[-1] + SPEED * DT
    # The master stood meanwhile: its stamps go on after the pause (the node's clock ran on).
    pause_ns = round((time.monotonic() - paused) * 1e9)
    q, second = constant_speed(START_NS + round(COUNT * DT * 1e9) + pause_ns, q_again, SPEED,
                               COUNT, DT)
    end = run_once(link, cam, second, q, q_again)
    assert abs(end - 0.02) < 1e-12
    states.wait('end of profile')
    said = [m.message for m in states.inbox.messages]
    assert said[-3:] == ['holding', 'engaged', 'end of profile']
    assert process.process.poll() is None
