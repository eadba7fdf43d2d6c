"""A real cam_node on the faults every machine meets: its commands stay within the slave's limits.

A rotary knife (config/rotary_knife.yaml, one-way, velocity and acceleration limited) whose web
master restarts from 0 after 11 cuts, is disengaged and engaged again far behind its cam, and is
phase-shifted while it runs; a sealing jaw (config/default.yaml) whose wrapping shaft encoder
turns 252 deg unseen across 0 during a dropout. Every check reads the commands themselves: the
difference of two positions over their stamps is the mean velocity between them, a second
difference the mean acceleration, so neither exceeds a limit the commands keep. After each fault
the commands are the cam's again, exactly (a whole number of knife turns on).
"""
from __future__ import annotations

import math

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import ecam_design, engage, master_message, MasterLink, stamp_of
from rclpy.parameter import Parameter
from test_node import set_parameters

from cam_ros.core.ecam.master import ElectronicCam, MasterConfig

KNIFE, DEFAULT = CONFIG_DIR / 'rotary_knife.yaml', CONFIG_DIR / 'default.yaml'
TURN = 2 * math.pi
DT = 0.002  # 500 Hz
START_NS = 5_000 * 10 ** 9
MAX_VELOCITY, MAX_ACCELERATION = 30.0, 400.0  # rad/s, rad/s^2 of knife
SLACK = 1e-6  # round-off on the commands' differences
LIMITS = ('-p', f'slave.max_velocity:={math.degrees(MAX_VELOCITY)}', '-p',
          f'slave.max_acceleration:={math.degrees(MAX_ACCELERATION)}', '-p',
          'slave.direction:=positive')


class Master:
    """A stamped master stream and the node's answers (~/joint_states) to it."""

    def __init__(self, link):
        self.link, self.stamp = link, START_NS
        self.q, self.answers = [], []

    def send(self, positions, speed=None):
        """Send positions DT apart (with a velocity when given); keep the positions of the
        messages the node followed and its answers; return how many."""
        messages = []
        for q in positions:
            self.stamp += round(DT * 1e9)
            messages.append(master_message(self.stamp, position=(q,),
                                           velocity=() if speed is None else (speed,)))
        self.link.send(messages)
        sent, answers = self.link.answered(messages)
        self.q += [message.position[0] for message in sent]
        self.answers += answers
        self.last = positions[-1]
        return len(sent)

    def commands(self):
        """Return the stamps (s from the first, exact in ns) and commanded positions so far."""
        ns = np.array([stamp_of(answer) for answer in self.answers])
        return (ns - ns[0]) * 1e-9, np.array([answer.position[1] for answer in self.answers])


def differences(t, p):
    """Return the mean velocities between commands and the mean accelerations of even steps."""
    h = np.diff(t)
    v = np.diff(p) / h
    even = np.isclose(h[1:], h[:-1], rtol=1e-6)  # a second difference over a gap is no mean
    return v, (np.diff(v) / h[1:])[even]


def assert_within(t, p, direction, max_velocity=MAX_VELOCITY,
                  max_acceleration=MAX_ACCELERATION):
    v, a = differences(t, p)
    assert np.abs(v).max() <= max_velocity + SLACK
    assert np.abs(a).max() <= max_acceleration + SLACK
    if direction:
        assert (direction * v).min() >= -SLACK


def assert_on_cam(cam, q, p, turn):
    want = cam.setpoints(np.asarray(q)).position
    shift = np.round((p - want) / turn) * turn if turn else 0.0
    np.testing.assert_allclose(p, want + shift, rtol=0, atol=1e-12)
    assert np.ptp(shift) == 0.0


def test_a_knife_keeps_its_limits_on_a_restart_a_far_engage_and_a_phase_shift(
        start_cam_node, executor):
    process, _ = start_cam_node(KNIFE, '-p', 'master.joint:=cam', '-p', 'master.timeout:=5.0',
                                *LIMITS)
    design = ecam_design(KNIFE)
    cam = ElectronicCam(design.program, MasterConfig.from_config(design.config).mapping)
    link = MasterLink(executor)
    link.connect(process)
    master = Master(link)
    speed = 1.0  # m/s of web
    cut = TURN * 0.1  # m of web per cut

    # 11 cuts, then the stream restarts from 0 (a PLC restart): a new origin, not 11 turns back.
    master.send((speed * DT * np.arange(1, round(11 * cut / (speed * DT)))).tolist(), speed)
    made = master.commands()[1][-1]
    assert made > 10 * TURN
    count = master.send((speed * DT * np.arange(0, 2500)).tolist(), speed)
    t, p = master.commands()
    assert p[-count:].min() >= made - 1e-12
    assert_within(t, p, 1)
    assert_on_cam(cam, master.q[-300:], p[-300:], TURN)
    values = link.diagnostics('cam: master', lambda v: v.get('new_origins') == '1')
    assert values['new_origins'] == '1'
    assert 'new master origin' in process.log()

    # Disengaged (it stops within its acceleration), then engaged again far behind the cam.
    assert engage(executor, False).success
    base = master.last
    master.send((base + speed * DT * np.arange(1, 400)).tolist(), speed)
    stopped = master.commands()[1][-1]
    assert np.ptp(master.commands()[1][-100:]) == 0.0
    assert engage(executor, True).success
    base = master.last
    count = master.send((base + speed * DT * np.arange(1, 3000)).tolist(), speed)
    t, p = master.commands()
    assert p[-count:].min() >= stopped - 1e-12
    assert_within(t, p, 1)
    assert_on_cam(cam, master.q[-300:], p[-300:], TURN)

    # A phase shift on the running knife: a stop, a move onto the new cam and a catch-up,
    # within the limits, never backwards.
    result = set_parameters(executor, [Parameter('master.offset_deg', value=1.5)])
    assert result.successful, result.reason
    shifted = ElectronicCam(design.program, MasterConfig.from_config(
        ecam_design(KNIFE, **{'master.offset_deg': 1.5}).config).mapping)
    base = master.last
    master.send((base + speed * DT * np.arange(1, 2500)).tolist(), speed)
    t, p = master.commands()
    assert_within(t, p, 1)
    assert_on_cam(shifted, master.q[-300:], p[-300:], TURN)


def test_a_jaw_whose_wrapping_encoder_crossed_zero_in_a_dropout_goes_on_forward(
        start_cam_node, executor):
    # 300 rpm: the 252 deg take 0.14 s, under master.timeout (0.5 s): the master is stale, not
    # lost, and the step read 108 deg backwards went into the speed estimate (-11 rad/s).
    timeout = 0.5
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                f'master.timeout:={timeout}', '-p',
                                'slave.max_velocity:=100.0', '-p',  # cm/s
                                'slave.max_acceleration:=8000.0')
    design = ecam_design(DEFAULT)
    cam = ElectronicCam(design.program, MasterConfig.from_config(design.config).mapping)
    link = MasterLink(executor)
    link.connect(process)
    master = Master(link)
    speed = 5 * TURN  # rad/s of shaft
    q = 0.5 + speed * DT * np.arange(1, 700)
    master.send(np.mod(q, TURN).tolist())
    # 252 deg turned unseen, across 0: the next message comes that much later.
    silence = math.radians(252.0) / speed
    master.stamp += round((silence - DT) * 1e9)
    resumed = q[-1] + silence + speed * DT * np.arange(0, 700)
    count = master.send(np.mod(resumed, TURN).tolist())
    t, p = master.commands()
    assert_within(t, p, 0, 1.0, 80.0)  # m/s, m/s^2
    q = np.array(master.q[-count:])
    assert_on_cam(cam, q, p[-count:], 0.0)
    velocity = np.array([a.velocity[1] for a in master.answers[-count:]])
    estimated = np.arange(count) >= 20  # the speed estimate's window after the dropout
    np.testing.assert_allclose(velocity[estimated], cam.setpoints(q, speed).velocity[estimated],
                               rtol=0, atol=1e-6)
    assert link.diagnostics('cam: master', lambda v: v['new_origins'] == '0')['message'] == 'ok'
