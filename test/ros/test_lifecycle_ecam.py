"""A managed electronic-cam node under a running master: inactive, activate, deactivate, again.

The master (positions only: the node estimates its speed) runs at constant speed through every
transition. Inactive, nothing is commanded, yet the master is followed: the first command after
activate has the cam's velocity at the master's speed at once (closed form, seed_000_follower).
Deactivate stops the line shaft on the cam (no hold in one message) and then sends nothing;
activating again catches up with the master from where it rests, never with a step, and is on
the cam again after. Shutdown from active stops once more and ends the process.
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
HORIZON = 0.05  # command.trajectory_horizon: a trajectory with every command
INACTIVE_S, ACTIVE_S = 0.5, 0.5  # times the test waits in each state
VELOCITY_RTOL = 1e-9


def test_inactive_sends_nothing_deactivate_stops_on_the_cam_activate_catches_up(
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
    assert len(commands) == len(trajectories) == len(joints)  # one each per step
    assert all(len(command.data) == 1 for command in commands)  # one value per axis
    stamps = [stamp_of(m) for m in joints]
    assert all(b > a for a, b in zip(stamps, stamps[1:]))
    index = {stamp_of(message): k for k, message in enumerate(stream)}
    k = np.array([index.get(stamp, -1) for stamp in stamps])
    gap = int(np.argmax(np.diff(np.maximum.accumulate(k)))) + 1  # the inactive stretch
    assert k[gap] - k[gap - 1] > INACTIVE_S / DT / 2
    first, second = joints[:gap], joints[gap:]
    assert len(first) > 20 and len(second) > 20, (len(first), len(second))

    # The first activation: on the cam at once, with the master's speed already known.
    assert k[0] > INACTIVE_S / DT / 2  # the master ran unanswered while inactive
    position = np.array([m.position[1] for m in first])
    velocity = np.array([m.velocity[1] for m in first])
    running = (k[:gap] >= 0) & (k[:gap] < k[0] + ACTIVE_S / DT / 2)  # not the clock's stop
    cam, cam_velocity = seed_000_follower(q[k[:gap][running]], SPEED)
    np.testing.assert_allclose(position[running], cam, rtol=0, atol=1e-12)
    np.testing.assert_allclose(velocity[running], cam_velocity, rtol=VELOCITY_RTOL, atol=1e-15)
    assert abs(cam_velocity[0]) > 0.01  # moving: a cold speed estimate would command 0
    np.testing.assert_array_equal([c.data[0] for c in commands[:gap]], position)

    # Deactivate: the line shaft stops on the cam, then nothing while the master runs.
    assert velocity[-1] == 0.0  # at rest, where it stays while inactive
    held = position[-1]
    rest = trajectories[gap - 1].points
    assert all(list(point.positions) == [held] for point in rest)

    # Activate again: from where it rests (no step), catching up, then on the cam again.
    position = np.array([m.position[1] for m in second])
    assert position[0] == held
    steepest = np.abs(seed_000_follower(np.linspace(0, 2 * np.pi, 10_001), 1.0)[1]).max()
    gaps = np.diff(stamps[gap:]) * 1e-9
    assert (np.abs(np.diff(position)) <= steepest * 3 * SPEED * gaps).all()  # no step
    answered = np.flatnonzero(k[gap:] >= 0)[-100:]  # the master's last 0.2 s or more
    cam = seed_000_follower(q[k[gap:][answered]], SPEED)[0]
    np.testing.assert_allclose(position[answered], cam, rtol=0, atol=1e-12)

    # Shutdown from active: a stop on the cam once more, at rest last.
    assert joints[-1].velocity[1] == 0.0
