"""A real machine node watches its axes: ~/controller_state, the following-error fault, recovery.

A drive simulated here reports every axis of config/machine.yaml one master message late (a
lag), stamped with the master message it answers; then the pusher (feeder) stalls. For every
report, ~/controller_state's reference is the node's command at that stamp (read from its
~/joint_states) and its error the reference less the report, to 1e-12. The fault fires at the
first report whose error has stayed over the limit for slave.following_error_time, not before;
every axis then holds its last command, and ~/engage true re-engages each from where it is
reported, without a step.
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
            late = commanded[stamp_of(stream[max(index - 1, 0)])].copy()
            if index >= stall:
                late[0] = last_report[0]
            last_report = reported[stamp] = late
            report = JointState(name=list(NAMES), position=late.tolist())
            report.header = message.header
            axis.publish(report)
        states.wait(len(reported) - 1)  # the very first report predates every command kept

    # Every report: reference = the command at its stamp, error = reference - feedback.
    for state in states.messages:
        stamp = stamp_of(state)
        assert list(state.joint_names) == list(NAMES)
        np.testing.assert_allclose(state.reference.positions, commanded[stamp], rtol=0,
                                   atol=1e-12)
        np.testing.assert_array_equal(state.feedback.positions, reported[stamp])
        np.testing.assert_allclose(state.error.positions,
                                   np.array(state.reference.positions) - reported[stamp],
                                   rtol=0, atol=1e-12)

    # The fault: at the first report over the limit for TIME_S, not before.
    stamps = sorted(reported)
    errors = np.array([commanded[stamp][0] - reported[stamp][0] for stamp in stamps])
    over = np.abs(errors) > LIMIT_MM * 1e-3
    first = int(np.argmax(over))
    assert over[first:first + round(TIME_S / DT) + 1].all()
    due = stamps[first] + round(TIME_S * 1e9)
    line = next(line for line in process.log().splitlines() if 'following error of' in line)
    assert line.startswith('[ERROR]') and 'following error of feeder' in line
    assert int(re.search(r'at stamp (\d+) ns', line).group(1)) == due
    state = link.diagnostics('cam: engagement', lambda v: v['message'].startswith('fault'))
    assert state['message'] == 'fault: following error' and state['level'] == b'\x02'

    # Every axis holds its last command from the next round of master messages on (the node
    # took the report at `due` after the commands of its own round), at rest.
    joints = [m for m in link.messages('joints') if stamp_of(m) in commanded]
    hold = next(k for k, m in enumerate(joints) if not any(m.velocity[1:]))
    assert stamp_of(joints[hold]) <= due + 2 * STEP * round(DT * 1e9)
    assert any(joints[hold - 1].velocity[1:])  # moving up to the fault
    for message in joints[hold:]:
        np.testing.assert_array_equal(message.position[1:], joints[hold - 1].position[1:])
        assert list(message.velocity[1:]) == [0.0] * 3

    # ~/engage true: each axis leaves from where it was last reported, without a step.
    assert engage(executor, True).success
    _, back = constant_speed(START_NS + 10 ** 9, speed * DT * 500, speed, 60, DT)
    link.send(back)
    answers = link.answers(back)
    np.testing.assert_array_equal(answers[0].position[1:], last_report)
    # A ramp, no step: over the 30 deg blend a step is at most the smoothstep's steepest
    # (1.875 x the distance to the cam / 30 deg) plus the cam's own slope, times one stride.
    stride = speed * DT
    steps = np.abs(np.diff([a.position[1:] for a in answers], axis=0))
    for column, (stroke, slope) in ((0, (0.2, 0.19)), (2, (0.08, 0.14))):  # m, m per rad
        assert steps[:, column].max() <= (1.875 * stroke / np.radians(30.0) + slope) * stride
