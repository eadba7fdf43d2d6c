"""A real machine node watches its axes: ~/controller_state, the following-error fault, recovery.

A drive simulated here reports every axis of config/machine.yaml one master message late (a
lag: the last command before the message), stamped with the master message it answers; then the
pusher (feeder) stalls. For every report of a message the node followed, ~/controller_state's
reference is the node's command at that stamp (read from its ~/joint_states) and its error the
reference less the report, to 1e-12. The fault fires at the
first report whose error has stayed over the limit for slave.following_error_time, not before;
it is said once. The line shaft then stops every axis on its cam (no stop in one message);
~/engage true is refused while the pusher's error is over its limit, accepted once the drive has
come back within it (3 mm short of its command): the pusher's command is set to where its drive
is (as a drive's own reset does: no motion), it moves onto its cam in time with the line shaft at
rest, checked against the pairs, and the line shaft catches up with the master, without a step;
the pairs are kept on every command.
"""
from __future__ import annotations

import re

import numpy as np
from cam_ros_interfaces.msg import ControllerState
from conftest import CONFIG_DIR
from ecam_support import constant_speed, DEEP, engage, MasterLink, stamp_of
from sensor_msgs.msg import JointState
from test_node import Inbox

from cam_ros.core import read_parameters_file
from cam_ros.core.machine.machine import load_machine

MACHINE = CONFIG_DIR / 'machine.yaml'
NAMES = ('feeder', 'knife', 'jaw')
AXIS_TOPIC = '/axes/joint_states'
DT = 0.002
START_NS = 6_000 * 10 ** 9
LIMIT_MM, TIME_S = 6.0, 0.02  # the pusher moves at most 4 mm per message: one late is within
STEP = 10  # master messages per round: their commands, then the drive's reports


def test_a_stalled_axis_faults_the_machine_after_its_time_and_engage_recovers(
        start_cam_node, executor):
    wiring = [arg for name in NAMES for arg in ('-p', f'{name}.slave.state_topic:={AXIS_TOPIC}')]
    process, _ = start_cam_node(
        MACHINE, '-p', 'master.joint:=cam', '-p', 'master.timeout:=5.0', *wiring,
        '-p', f'feeder.slave.following_error_limit:={LIMIT_MM}',
        '-p', f'feeder.slave.following_error_time:={TIME_S}', evaluate='feeder/evaluate')
    speed = read_parameters_file(MACHINE)['cam_speed']
    link = MasterLink(executor)
    axis = link.node.create_publisher(JointState, AXIS_TOPIC, DEEP)
    states = Inbox(link.node, ControllerState, '/cam/controller_state', DEEP)
    link.connect(process)
    _, stream = constant_speed(START_NS, 0.0, speed, 400, DT)
    commanded: dict[int, np.ndarray] = {}  # master stamp -> every axis's position command
    reported: dict[int, np.ndarray] = {}
    stall, last_report = 120, None  # the pusher stalls at the 120th message (near mid-stroke)
    for start in range(0, len(stream), STEP):
        chunk = stream[start:start + STEP]
        link.send(chunk)
        for answer in link.answers(chunk):
            commanded[stamp_of(answer)] = np.array(answer.position[1:])
        for index, message in enumerate(chunk, start):
            stamp = stamp_of(message)
            # The drive reports the last command it had (the node may skip a late message).
            before = max(at for at in commanded if at < stamp) if index else stamp
            late = commanded.get(before, commanded[min(commanded)]).copy()
            if index >= stall:
                late[0] = last_report[0]
            last_report = reported[stamp] = late
            report = JointState(name=list(NAMES), position=late.tolist())
            report.header = message.header
            axis.publish(report)
        states.wait(len(reported) - 1)  # the very first report predates every command kept

    # Every report: reference = the command at its stamp, error = reference - feedback.
    checked = 0
    for state in states.messages:
        stamp = stamp_of(state)
        assert list(state.joint_names) == list(NAMES)
        if stamp not in commanded:  # a master message the node skipped: no command to read
            continue
        checked += 1
        np.testing.assert_allclose(state.reference.positions, commanded[stamp], rtol=0,
                                   atol=1e-12)
        np.testing.assert_array_equal(state.feedback.positions, reported[stamp])
        np.testing.assert_allclose(state.error.positions,
                                   np.array(state.reference.positions) - reported[stamp],
                                   rtol=0, atol=1e-12)

    assert checked >= len(states.messages) // 4
    # The fault: at the first report over the limit for TIME_S, not before.
    stamps = sorted(stamp for stamp in reported if stamp in commanded)
    errors = np.array([commanded[stamp][0] - reported[stamp][0] for stamp in stamps])
    over = np.abs(errors) > LIMIT_MM * 1e-3
    # (a master message the node skipped can put one late report over the limit before the
    # stall: the fault needs TIME_S of it)
    span = round(TIME_S / DT) + 1
    first = next(k for k in range(len(over)) if over[k:k + span].all())
    due = stamps[first] + round(TIME_S * 1e9)
    lines = [line for line in process.log().splitlines() if 'following error of' in line]
    assert len(lines) == 1 and lines[0].startswith('[ERROR]')  # said once
    assert 'following error of feeder' in lines[0]
    assert int(re.search(r'at stamp (\d+) ns', lines[0]).group(1)) == due
    state = link.diagnostics('cam: engagement', lambda v: 'following error' in v['message'])
    assert state['message'].endswith(': following error of feeder')
    assert state['level'] == b'\x02'

    # The line shaft stops: every axis decelerates on its cam to rest, together.
    joints = [m for m in link.messages('joints') if stamp_of(m) in commanded]
    after = [m for m in joints if stamp_of(m) > due]
    assert any(after[0].velocity[1:])  # not stopped in one message
    rest = next(k for k, m in enumerate(after) if not any(m.velocity[1:]))
    assert rest > 5
    machine = load_machine(MACHINE)
    knife = np.array([m.position[2] for m in after[:rest + 1]])  # rad: rises with the angle
    theta = np.linspace(0.0, 2 * np.pi * 4, 400_001)
    turns = machine.positions(theta)[:, 1]
    on = np.interp(knife, turns, theta)  # the line shaft's angle, from the knife
    np.testing.assert_allclose([m.position[1:] for m in after[:rest + 1]],
                               machine.positions(on), rtol=0, atol=1e-6)  # on the cams
    for message in after[rest:]:
        np.testing.assert_array_equal(message.position[1:], after[rest].position[1:])
    held = np.array(after[rest].position[1:])

    # ~/engage true while the pusher is still stalled is refused, naming it and its error.
    answer = engage(executor, True)
    assert not answer.success and 'following error of feeder' in answer.message
    assert 'over slave.following_error_limit' in answer.message

    # The drive comes back within the limit, 3 mm short of its command; cleared.
    back_at = held - np.array([0.003, 0.0, 0.0])
    report = JointState(name=list(NAMES), position=back_at.tolist())
    report.header = after[-1].header
    count = len(states.messages)
    axis.publish(report)
    states.wait(count + 1)
    answer = engage(executor, True)
    assert answer.success, answer.message
    assert 'following error of feeder cleared' in process.log()

    # The pusher moves onto its cam from where its drive is; then the line shaft catches up
    # with the master from rest, without a step, and is exact. (Stamped on the master's
    # clock, which ran on while the machine stood: 20 s on.)
    _, back = constant_speed(START_NS + 20 * 10 ** 9, speed * DT * 400, speed, 400, DT)
    link.send(back)
    sent, answers = link.answered(back)
    moved = np.array([a.position[1:] for a in answers])
    assert moved[0, 0] == back_at[0]  # from where the drive is
    onto = int(np.argmax(np.abs(moved[:, 0] - held[0]) <= 1e-12))  # on its cam again
    assert onto > 1 and np.all(np.diff(moved[:onto + 1, 0]) >= 0.0)  # straight there
    # The others wait on their cams (the exact path's rounding, not the table's: ulps).
    np.testing.assert_allclose(moved[:onto + 1, 1:], np.tile(held[1:], (onto + 1, 1)), rtol=0,
                               atol=1e-12)
    assert 'feeder: moves onto its cam: 0.003 m (3 mm)' in process.log()
    gap = 0.31 - moved[:, 0] - moved[:, 2]  # the pairs on every command
    assert gap.min() >= 0.015
    assert not ((moved[:, 2] > 0.06) & (np.degrees(moved[:, 1]) % 360.0 > 320.0)).any()
    exact = machine.positions(np.array([m.position[0] for m in sent[-100:]]))
    actual = np.array([a.position[1:] for a in answers[-100:]])
    turns = np.round((actual[:, 1] - exact[:, 1]) / (2 * np.pi))  # the knife, on whole turns
    assert np.ptp(turns) == 0.0
    exact[:, 1] += turns * 2 * np.pi
    np.testing.assert_allclose(actual, exact, rtol=0, atol=1e-9)
