"""Replay a recorded master stream into a fresh electronic cam node: the same commands back.

For a single cam and for config/machine.yaml (every axis's command in each ~/commands).
"""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import master_message, MasterLink, stamp_of, WAIT_S
from std_msgs.msg import Float64MultiArray
from test_ecam import outputs, stepped

from cam_ros.recording import open_recording, Player

DEFAULT = CONFIG_DIR / 'default.yaml'
ECAM = ('-p', 'master.source:=topic', '-p', 'master.timeout:=30.0', '-p', 'slave.scaling:=2.0',
        '-p', 'command.trajectory_horizon:=0.02')
MACHINE = CONFIG_DIR / 'machine.yaml'
MACHINE_ARGS = ('-p', 'master.joint:=cam', '-p', 'master.timeout:=30.0', '-p',
                'command.trajectory_horizon:=0.02')
RECORDED = {'/cam/master', '/cam/commands', '/cam/joint_trajectory', '/cam/joint_states',
            '/diagnostics'}


def settled(link, before: dict) -> tuple[list, list]:
    """Wait until the node's outputs stop coming (0.5 s without one); return its joint states
    and commands since before, one of each per step."""
    deadline, count = time.monotonic() + WAIT_S, -1
    while count != len(link.messages('joints')):
        assert time.monotonic() < deadline
        count = len(link.messages('joints'))
        time.sleep(0.5)
    joints, commands = (link.messages(key)[before[key]:] for key in ('joints', 'commands'))
    assert len(joints) == len(commands)
    return joints, commands


@pytest.mark.parametrize('params, args, evaluate', [(DEFAULT, ECAM, 'evaluate'),
                                                    (MACHINE, MACHINE_ARGS, 'knife/evaluate')])
def test_a_recorded_master_stream_replayed_into_a_fresh_node_gives_the_same_commands(
        start_cam_node, executor, tmp_path, params, args, evaluate):
    folder = tmp_path / 'runs'
    first, _ = start_cam_node(params, *args, '-p', 'recording.enabled:=true',
                              '-p', f'recording.directory:={folder}', evaluate=evaluate)
    link = MasterLink(executor)
    link.connect(first)
    t = 0.01 * np.arange(150)
    q = 2.0 + 30.0 * t - 10.0 * t ** 2  # slows down, stops at 1.5 s
    # Every other message gives its speed, the first too: the fresh node's own probe (stamp 0)
    # then cannot change an estimate.
    stream = [master_message(10 ** 9 + round(ti * 1e9), position=(qi,),
                             velocity=() if k % 2 else (30.0 - 20.0 * ti,))
              for k, (ti, qi) in enumerate(zip(t.tolist(), q.tolist()))]
    before = outputs(link)
    link.stream(stream, 0.01).join()
    taken, answers, commands = stepped(link, before, stream)  # by stamp: a backlog is skipped
    # /diagnostics comes about once a second: wait for one that the recording holds too.
    link.diagnostics('cam: recording', lambda values: values['message'].startswith('recording'))
    assert first.stop(signal.SIGINT) == 0, first.log()
    recording = open_recording(next(folder.glob('*.mcap')))
    assert recording.complete and RECORDED <= set(recording.topics)
    recorded = {topic: [m.message for m in recording.messages([topic])]
                for topic in ('/cam/master', '/cam/commands', '/cam/joint_states')}
    assert len(recorded['/cam/master']) >= len(stream)  # every message, the skipped ones too
    statuses = {status.name: status.message for array in recording.messages(['/diagnostics'])
                for status in array.message.status}
    assert statuses['cam: recording'].startswith(f'recording to {folder}/cam_')
    assert [list(m.data) for m in recorded['/cam/commands']] == [
        list(m.data) for m in link.messages('commands')]
    assert [stamp_of(m) for m in recorded['/cam/joint_states']] == [
        stamp_of(m) for m in link.messages('joints')]

    second, _ = start_cam_node(params, *args, name='cam', evaluate=evaluate)
    fresh = MasterLink(executor)
    with Player(recording, executor.node('player'), topics=['/cam/master']) as player:
        # One probe, older than every recording, through the replaying publisher: once the node
        # answers it, its best-effort subscription has matched that publisher and loses nothing.
        fresh.connect(second, stamp_ns=0, advance=False,
                      publisher=player.publishers['/cam/master'])
        again = outputs(fresh)
        count = player.play(rate=1.0)
    assert count == len(recorded['/cam/master'])
    reanswers, recommands = settled(fresh, again)  # the last message too may be lost
    assert all(isinstance(m, Float64MultiArray) for m in recommands)
    # The messages both nodes took (each may skip a backlog or lose a message) give the same
    # outputs where both took every message of the speed window (master.velocity_window 0.02 s)
    # before them too: the same inputs.
    first_by_stamp = {stamp_of(m): (joint, command)
                      for m, joint, command in zip(taken, answers, commands)}
    stamps = [stamp_of(m) for m in stream]
    common = set(first_by_stamp) & {stamp_of(m) for m in reanswers}
    same_window = {stamp for k, stamp in enumerate(stamps)
                   if all(earlier in common for earlier in stamps[max(k - 3, 0):k + 1])}
    both = [(first_by_stamp[stamp_of(joint)], (joint, command))
            for joint, command in zip(reanswers, recommands) if stamp_of(joint) in same_window]
    assert len(both) >= 20  # of 150: a loaded machine's nodes skip some, each its own
    for (joint, command), (rejoint, recommand) in both:
        assert rejoint.name == joint.name and len(recommand.data) == len(command.data)
    np.testing.assert_allclose([list(j.position) + list(j.velocity) + list(c.data)
                                for (j, c), _ in both],
                               [list(j.position) + list(j.velocity) + list(c.data)
                                for _, (j, c) in both], rtol=0, atol=1e-12)
    assert second.stop(signal.SIGINT) == 0
