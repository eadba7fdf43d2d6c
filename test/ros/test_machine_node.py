"""A real cam_node serving config/machine.yaml: three axes on one master, one message for all.

Every command is checked against the MC_CamIn coupling written out here (cam angle
((q - q0) / m) mod 2 pi, slave k s + y0, s from the axis's own program), a phase shift of the
knife moves from its old coupling to its new one, one of the jaw that would make the jaw meet the
knife's zone is refused by name and changes nothing, and after a master loss the line shaft
stops every axis on its cam and catches up with the master when it returns.
"""
from __future__ import annotations

import math

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import constant_speed, MasterLink, stamp_of
from rclpy.parameter import Parameter
from test_node import set_parameters
from test_node_evaluate import call

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.core.config.parameters import UNITS

MACHINE = CONFIG_DIR / 'machine.yaml'
NAMES = ('feeder', 'knife', 'jaw')
DT = 0.002  # 500 Hz
START_NS = 4_000 * 10 ** 9
TIMEOUT_S = 1.0  # longer than the probes take: the stream starts on the cam


def axis_values(values, name, **changes):
    """Return one axis's single-cam values from the machine file (written out, not the core's)."""
    flat = {key.partition('.')[2]: value for key, value in values.items()
            if key.startswith(f'{name}.')}
    flat.update({key: values[key] for key in ('cam_speed', 'master.source')})
    flat.update(changes)
    return flat


def coupled(values, name, q, **changes):
    """Return the axis's commanded position (SI) at master positions q: MC_CamIn by hand."""
    flat = axis_values(values, name, **changes)
    program = build_design(parse_parameters(flat)).program
    q0 = math.radians(flat.get('master.offset_deg', 0.0))
    m = flat.get('master.scaling', 1.0)
    unit = UNITS[flat['length_unit']]
    y0, k = flat.get('slave.offset', 0.0) * unit, flat.get('slave.scaling', 1.0)
    turns = (np.asarray(q) - q0) / m  # an advancing program adds its advance per whole turn
    return k * program.evaluate(turns).s + y0


def commands(link, messages):
    """Return the master positions of the messages the node followed and, by stamp, every
    axis's position command for them (rows: messages; columns: axes)."""
    sent, answers = link.answered(messages)
    return (np.array([m.position[0] for m in sent]),
            np.array([list(answer.position[1:]) for answer in answers]))


def test_a_machine_node_commands_every_axis_from_one_master(start_cam_node, executor):
    process, knife_client = start_cam_node(MACHINE, '-p', 'master.joint:=cam', '-p',
                                           f'master.timeout:={TIMEOUT_S}',
                                           evaluate='knife/evaluate')
    values = read_parameters_file(MACHINE)
    speed = values['cam_speed']  # rad/s of machine angle
    link = MasterLink(executor)
    link.connect(process)
    joints = link.messages('joints')[-1]
    assert list(joints.name) == ['cam', *NAMES]

    # A cycle and a half at 100 products/min: every axis on its coupling, exactly.
    _, stream = constant_speed(START_NS, 0.0, speed, 900, DT)
    link.send(stream)
    q, got = commands(link, stream)
    for column, name in enumerate(NAMES):
        np.testing.assert_allclose(got[:, column], coupled(values, name, q), rtol=0, atol=1e-12)

    # Each axis's ~/<axis>/evaluate serves its own design.
    knife = build_design(parse_parameters(axis_values(values, 'knife')))
    answer = call(knife_client, [0.5, 2.0])
    np.testing.assert_array_equal(answer.position, knife.evaluate(np.array([0.5, 2.0])).position)

    # A knife phase shift of -5 deg: the line shaft stops every axis on its cam, the knife moves
    # onto its new cam, the line shaft catches up; then the new coupling, every axis exact.
    result = set_parameters(executor, [Parameter('knife.master.offset_deg', value=95.0)])
    assert result.successful, result.reason
    start = stream[-1].position[0] + speed * DT
    _, stream = constant_speed(START_NS + 2 * 10 ** 9, start, speed, 1000, DT)
    link.send(stream)
    q, got = commands(link, stream)
    assert_coupled(values, q, got, {'knife': {'master.offset_deg': 95.0}})
    # No step: no axis moves more in a message than the line shaft's fastest catch-up (3x the
    # master's speed, line_shaft.CATCH_UP) takes its coupling.
    for column, name in enumerate(NAMES):
        fastest = np.abs(np.diff(coupled(values, name, q)) / np.diff(q)).max() * speed
        assert np.abs(np.diff(got[:, column]) / np.diff(q) * speed).max() <= 3.0 * fastest, name
    log = process.log()
    assert 'design change knife: moves onto the new cam in time' in log  # only that axis
    assert 'feeder: ' not in log.split('design change knife')[1].splitlines()[0]
    assert 'knife: moves onto its new cam' in log

    # A jaw shift that brings it into the knife's zone 15.5 deg after the knife leaves it (the
    # file's 70.5 deg, less the knife's 5 and the jaw's 60 deg of shift): refused.
    result = set_parameters(executor, [Parameter('jaw.master.offset_deg', value=-60.0)])
    assert not result.successful
    assert 'zones jaw-knife: smallest margin 15.53' in result.reason
    _, stream = constant_speed(START_NS + 4 * 10 ** 9, stream[-1].position[0] + speed * DT,
                               speed, 300, DT)
    link.send(stream)
    q, got = commands(link, stream)
    np.testing.assert_allclose(got[:, 2], coupled(values, 'jaw', q), rtol=0, atol=1e-12)

    # Master lost: the line shaft stops every axis on its cam (the clock steps it, stamping on
    # after the last master message), then rests.
    link.diagnostics('cam: master', lambda v: v['line_shaft'] == 'at rest: master lost')
    stop = np.array([list(m.position[1:]) for m in link.messages('joints')
                     if stamp_of(m) > stamp_of(stream[-1])])
    assert len(stop) > 5 and (stop[0] != got[-1]).any()  # moving on, not held at once
    held = stop[-1]
    # Back elsewhere: every axis leaves from where it rests and is on its cam again after.
    _, stream = constant_speed(START_NS + 8 * 10 ** 9, 1.0, speed, 900, DT)
    link.send(stream)
    q, got = commands(link, stream)
    assert np.abs(got[0] - held).max() < 1e-3  # no step (m; the knife: rad)
    assert_coupled(values, q, got, {'knife': {'master.offset_deg': 95.0}})


def assert_coupled(values, q, got, changes):
    """The last 100 commands are every axis's coupling at the master (with changes by axis)."""
    after = np.arange(len(q)) >= len(q) - 100
    for column, name in enumerate(NAMES):
        want = coupled(values, name, q[after], **changes.get(name, {}))
        if name == 'knife':  # a rotary slave goes on by whole turns, never unwinding them
            want += np.round((got[after, 1] - want) / (2 * math.pi)) * 2 * math.pi
        np.testing.assert_allclose(got[after, column], want, rtol=0, atol=1e-12)
