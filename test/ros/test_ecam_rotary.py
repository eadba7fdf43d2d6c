"""A rotary knife (motion only, slave in deg) served and driven by its web as master."""
from __future__ import annotations

import math

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import ecam_design, master_message, MasterLink
from test_ecam import outputs, stepped
from test_node import evaluate

KNIFE = CONFIG_DIR / 'rotary_knife.yaml'
TWO_PI = 2.0 * math.pi
# The probes of MasterLink.connect name their joint 'cam'; timeout long for a loaded machine.
ARGS = ('-p', 'master.joint:=cam', '-p', 'master.timeout:=30.0')


def test_the_knife_serves_its_advance_and_follows_the_web_through_several_cuts(
        start_cam_node, executor):
    process, client = start_cam_node(KNIFE, *ARGS)
    design = ecam_design(KNIFE)
    angles = np.array([0.1, 0.1 + TWO_PI, 0.1 - 2 * TWO_PI, 5.0 + 3 * TWO_PI])
    answer = evaluate(client, angles)
    assert answer.success, answer.message
    once = design.program.evaluate(np.mod(angles, TWO_PI))
    np.testing.assert_allclose(answer.position, once.s + TWO_PI * np.floor(angles / TWO_PI),
                               atol=1e-12)  # rad: each cut adds a turn of the knife
    assert np.isnan(answer.pressure_angle).all()

    link = MasterLink(executor)
    link.connect(process)
    before = outputs(link)
    speed, dt = 1.0, 0.002  # m/s of web, s between master messages
    web = 0.05 + speed * dt * np.arange(800)  # 1.6 m: two and a half cut lengths of 0.628 m
    messages = [master_message(10 ** 9 + round(k * dt * 1e9), position=(q,), velocity=(speed,))
                for k, q in enumerate(web.tolist())]
    link.send(messages)
    sent, _, commands = stepped(link, before, messages)  # by stamp: a backlog is skipped
    commands = np.array([m.data[0] for m in commands])
    web = np.array([m.position[0] for m in sent])
    turns = web / 0.1  # cam angle (rad): master.scaling 0.1 m of web per rad
    np.testing.assert_allclose(commands, design.program.evaluate(turns).s, atol=1e-12)
    assert commands[-1] - commands[0] > 2 * TWO_PI  # the knife turned on, cut after cut
    steps = np.diff(commands)  # never back, never a jump: at most the recovery's peak speed
    assert steps.min() > 0.0 and (steps / np.diff(web / speed)).max() <= 12.15
