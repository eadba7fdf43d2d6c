"""`cam_ros replay --apply-parameters` gives a recorded e-cam run's commands back, a change too.

A real node records its run while the test changes slave.offset, with the master paused or
streaming at 250 Hz (the line shaft then stops, the axis moves onto the new cam in time, and the
line shaft catches up). rclpy logs /parameter_events 10-20 ms before the node's e-cam takes the
design; the replay finds the master message it was taken at in the recorded ~/state. The
recorded master stream is replayed by the CLI into a fresh node: with --apply-parameters its
commands are the recorded ones bit for bit up to the change, and to round-off once both command
the new cam at the master again (in between, each node's move began at the step after its
planner thread finished, and its catch-up integrated the steps it took); without, they are the
old cam's after the change. Each node may skip a backlog: the runs are compared by stamp.
"""
from __future__ import annotations

import math
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import constant_speed, ecam_design, MasterLink, stamp_of, WAIT_S
from rclpy.parameter import Parameter
from test_node import set_parameters

from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.recording import open_recording, parameter_changes

DEFAULT = CONFIG_DIR / 'default.yaml'
#: master.timeout 300 s: the node's clock steps the line shaft (the master moving on) only after
#: 30 s of silence, not while the paused master waits for the change on a loaded machine.
ECAM = ('-p', 'master.source:=topic', '-p', 'master.timeout:=300.0')
START_NS = 5_000 * 10 ** 9
DT = 0.004  # 250 Hz
SPEED = 2 * math.pi  # 60 rpm: 1.44 deg per message
COUNT = 750  # 3 s of master: a change made late on a loaded machine still lands in it
CHANGE_AFTER = 0.5  # s into the stream
OFFSET_CM = 0.3


def replay_into_fresh_node(start_cam_node, executor, path, *options: str) -> dict[int, float]:
    """Start a fresh node, replay the recorded master stream into it with the CLI.

    Return its position commands by master stamp (its ~/joint_states carry the master's stamp)
    once they stop coming (its last message too may be lost).
    """
    node, _ = start_cam_node(DEFAULT, *ECAM)
    link = MasterLink(executor)
    result = subprocess.run([sys.executable, '-m', 'cam_ros.cli', 'replay', str(path), '--topics',
                             '/cam/master', '--wait', str(WAIT_S), *options],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    recorded = open_recording(path).topics['/cam/master'].count
    assert result.stdout.startswith(f'published {recorded} messages')
    deadline, count = time.monotonic() + WAIT_S, -1
    while count != len(link.messages('joints')):  # 0.5 s without an answer
        assert time.monotonic() < deadline, node.log()
        count = len(link.messages('joints'))
        time.sleep(0.5)
    assert node.stop(signal.SIGINT) == 0, node.log()
    return {stamp_of(m): m.position[1] for m in link.messages('joints')}


@pytest.mark.parametrize('master', [
    'paused',  # the change is made between two master messages (the master waits for it)
    'streaming'])  # the node takes it at a master message its ~/state names
def test_replay_with_apply_parameters_reproduces_a_recorded_run_with_a_change(
        master, start_cam_node, executor, tmp_path):
    folder = tmp_path / 'runs'
    first, _ = start_cam_node(DEFAULT, *ECAM, '-p', 'recording.enabled:=true',
                              '-p', f'recording.directory:={folder}')
    link = MasterLink(executor)
    link.connect(first)
    q, stream = constant_speed(START_NS, 0.5, SPEED, COUNT, DT)
    half, resume = round(CHANGE_AFTER / DT), threading.Event()
    if master == 'paused':
        thread = link.stream(stream, DT, half, resume)
        link.answers(stream[:half])  # the master waits for the change: so do its stamps

    else:
        thread = link.stream(stream, DT)
        time.sleep(CHANGE_AFTER)
    result = set_parameters(executor, [Parameter('slave.offset', value=OFFSET_CM)])
    assert result.successful, result.reason
    resume.set()
    thread.join()
    taken, answers = link.answered(stream)  # by stamp: a backlog is skipped
    q = q[np.isin([stamp_of(m) for m in stream], [stamp_of(m) for m in taken])]
    assert first.stop(signal.SIGINT) == 0, first.log()
    path = next(folder.glob('*.mcap'))
    recording = open_recording(path)
    commands = [m.message.data[0] for m in recording.messages(['/cam/commands'])]
    assert commands == [m.data[0] for m in link.messages('commands')]
    assert recording.topics['/cam/master'].count >= COUNT  # every message, skipped ones too
    changes = [(c.name, c.old, c.new) for c in parameter_changes(recording)
               if not c.name.startswith('recording.')]
    assert changes == [('slave.offset', 0.0, OFFSET_CM)]

    # Before the change the old cam, at the end the new one: the run has both.
    design = ecam_design(DEFAULT)
    cam = ElectronicCam(design.program, MasterConfig.from_config(design.config).mapping)
    old = cam.setpoints(q).position
    position = np.array([m.position[1] for m in answers])
    changed = np.flatnonzero(position != old)
    assert 0 < changed[0] and changed[-1] == q.size - 1
    np.testing.assert_array_equal(position[:changed[0]], old[:changed[0]])
    np.testing.assert_allclose(position[-1] - old[-1], OFFSET_CM * 0.01, rtol=1e-12)

    # The fresh node may miss master messages (its best-effort subscription still matching the
    # replaying publisher at first, or a backlog skipped on a loaded machine); every one both
    # nodes answered must match.
    recorded = {stamp_of(m): m.position[1] for m in answers}
    replayed = replay_into_fresh_node(start_cam_node, executor, path, '--apply-parameters')
    assert len(replayed.keys() & recorded.keys()) >= 100  # each node may skip some
    common = np.array(sorted(replayed.keys() & recorded.keys()))
    mine, theirs = (np.array([run[stamp] for stamp in common]) for run in (replayed, recorded))
    on_old = np.array([dict(zip(recorded, old))[stamp] for stamp in common])
    on_new = on_old + OFFSET_CM * 0.01
    changed = common[theirs != on_old].min()  # where the recorded node left its old cam
    # from where both stay on the new cam (in a dwell a catching-up axis can touch it before)
    off = (np.abs(mine - on_new) > 1e-12) | (np.abs(theirs - on_new) > 1e-12)
    locked = common[off].max()
    before, after = common < changed, common > locked
    np.testing.assert_array_equal(mine[before], theirs[before])
    # (to round-off after: each node's line shaft may be a machine cycle apart in theta_v)
    np.testing.assert_allclose(mine[after], theirs[after], rtol=0, atol=1e-12)
    assert (before | after).mean() >= 0.5

    unchanged = replay_into_fresh_node(start_cam_node, executor, path)
    assert len(unchanged.keys() & recorded.keys()) >= 100
    expected = dict(zip(recorded, old))  # the old cam all through, the change not made
    assert {stamp: value for stamp, value in unchanged.items() if stamp in recorded} == {
        stamp: expected[stamp] for stamp in unchanged if stamp in recorded}
