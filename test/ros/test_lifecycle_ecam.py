"""A managed electronic-cam node under a running master: inactive, activate, deactivate, again.

The master (positions only: the node estimates its speed) runs at constant speed through every
transition. Inactive, nothing is commanded, yet the master is followed: the first command after
activate has the cam's velocity at the master's speed at once (closed form, seed_000_follower).
Deactivate sends one hold (the last command, at rest); activating again ramps from there onto
the cam over master.engage_distance_deg (the quintic blend written out), never with a step.
Shutdown from active holds once more and ends the process.
"""
from __future__ import annotations

import math
import time

import numpy as np
from conftest import CONFIG_DIR, STOP_TIMEOUT_S
from ecam_support import master_message, MasterLink, seed_000_follower, stamp_of
from lifecycle_support import managed_node

DEFAULT = CONFIG_DIR / 'default.yaml'
START_NS = 5_000 * 10 ** 9
DT = 0.002  # 500 Hz
SPEED = 2 * math.pi  # 1 turn/s: 0.72 deg per message
#: The master's start: the activations (after INACTIVE_S and ACTIVE_S + INACTIVE_S) land in
#: the harmonic return (240-360 deg), where the follower moves.
Q0 = math.radians(90.0)
COUNT = 1400  # 2.8 s of master
DISTANCE = math.radians(30.0)  # master.engage_distance_deg's default
HORIZON = 0.05  # command.trajectory_horizon: a trajectory with every command
INACTIVE_S, ACTIVE_S = 0.5, 0.5  # times the test waits in each state
VELOCITY_RTOL = 1e-9


def quintic_ramp(q, q_start, held, cam):
    """The ramp engagement's position: held blended onto the cam over DISTANCE of master."""
    u = np.minimum(np.abs(q - q_start) / DISTANCE, 1.0)
    return held + (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5) * (cam - held)


def test_inactive_sends_nothing_deactivate_holds_once_activate_ramps_from_the_hold(
        executor, tmp_path):
    with managed_node(executor, tmp_path, DEFAULT, '-p', 'master.source:=topic', '-p',
                      'master.timeout:=1.0', '-p', 'master.engage_mode:=ramp', '-p',
                      f'command.trajectory_horizon:={HORIZON}') as managed:
        run_the_master_through_the_states(managed, MasterLink(executor))


def run_the_master_through_the_states(managed, link: MasterLink) -> None:
    """Stream the master while the test configures, activates, deactivates, activates."""
    assert managed.change('configure')
    q = Q0 + SPEED * DT * np.arange(COUNT)
    stream = [master_message(START_NS + round(k * DT * 1e9), position=(position,))
              for k, position in enumerate(q.tolist())]
    sender = link.stream(stream, DT)
    time.sleep(INACTIVE_S)
    for key in ('commands', 'joints', 'trajectories'):
        assert link.messages(key) == [], key  # inactive: the master runs, nothing is sent
    assert managed.change('activate')
    time.sleep(ACTIVE_S)
    assert managed.change('deactivate')
    time.sleep(INACTIVE_S)
    assert managed.change('activate')
    sender.join()
    time.sleep(0.3)  # the last answers
    assert managed.change('shutdown')
    assert managed.process.process.wait(timeout=STOP_TIMEOUT_S) == 0
    assert 'Traceback' not in managed.process.log()

    joints, commands = link.messages('joints'), link.messages('commands')
    trajectories = link.messages('trajectories')
    index = {stamp_of(message): k for k, message in enumerate(stream)}
    answered = [stamp_of(m) in index for m in joints]
    holds = [k for k, is_answer in enumerate(answered) if not is_answer]
    assert len(holds) == 2, holds  # deactivate and shutdown, nothing else
    assert holds[1] == len(joints) - 1  # the shutdown's is the last word
    first, second = joints[:holds[0]], joints[holds[0] + 1:holds[1]]
    assert len(first) > 100 and len(second) > 100, (len(first), len(second))
    assert len(commands) == len(trajectories) == len(joints)  # one each per answer and hold
    assert all(len(command.data) == 1 for command in commands)  # one value per axis

    # The first activation: on the cam at once, with the master's speed already known.
    k = np.array([index[stamp_of(m)] for m in first])
    assert k[0] > INACTIVE_S / DT / 2  # the master ran unanswered while inactive
    position = np.array([m.position[1] for m in first])
    velocity = np.array([m.velocity[1] for m in first])
    cam, cam_velocity = seed_000_follower(q[k], SPEED)
    np.testing.assert_allclose(position, cam, rtol=0, atol=1e-12)
    np.testing.assert_allclose(velocity, cam_velocity, rtol=VELOCITY_RTOL, atol=1e-15)
    assert abs(cam_velocity[0]) > 0.01  # moving: a cold speed estimate would command 0
    np.testing.assert_array_equal([c.data[0] for c in commands[:holds[0]]], position)

    # Deactivate: one hold at the last command, at rest, then nothing while the master runs.
    held = position[-1]
    assert commands[holds[0]].data.tolist() == [held]
    assert joints[holds[0]].position[1] == held and list(joints[holds[0]].velocity) == [0.0, 0.0]
    rest = trajectories[holds[0]].points
    assert [list(point.positions) for point in rest] == [[held]]
    assert [list(point.velocities) for point in rest] == [[0.0]]
    k2 = np.array([index[stamp_of(m)] for m in second])
    assert k2[0] - k[-1] > INACTIVE_S / DT / 2  # unanswered while inactive again

    # Activate again: from the held position (no step) onto the cam over DISTANCE.
    position = np.array([m.position[1] for m in second])
    velocity = np.array([m.velocity[1] for m in second])
    assert position[0] == held and velocity[0] == 0.0
    cam = seed_000_follower(q[k2], SPEED)[0]
    np.testing.assert_allclose(position, quintic_ramp(q[k2], q[k2[0]], held, cam), rtol=0,
                               atol=1e-12)
    assert np.abs(cam[0] - held) > 1e-3  # the cam moved away while inactive: a step averted
    on_cam = np.abs(q[k2] - q[k2[0]]) >= DISTANCE
    assert on_cam.sum() > 100

    # Shutdown from active: one more hold at the last command.
    assert commands[-1].data.tolist() == [position[-1]]
    assert list(joints[-1].velocity) == [0.0, 0.0]
