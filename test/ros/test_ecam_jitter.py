"""A real cam_node takes the speed of a 250 Hz master whose stamps jitter by ±0.2 ms to 1 %."""
from __future__ import annotations

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import ecam_design, master_message, MasterLink, RPM, stamp_of
from test_ecam import outputs, reference, stepped

from cam_ros.core.ecam.cycle_clock import SETTLED
from cam_ros.core.ecam.master_tracker import MasterTracker

DEFAULT = CONFIG_DIR / 'default.yaml'
START_NS = 3_000 * 10 ** 9
PERIOD_NS = 4_000_000  # 250 Hz
JITTER_NS = 200_000
SPEED = 600 * RPM
WINDOW_NS = 50_000_000
LIMIT = 0.01  # the issue asks 2 %
SECOND = 10 ** 9


def test_speed_from_jittered_stamps_in_setpoints_joint_states_and_diagnostics(
        start_cam_node, executor, report):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic', '-p',
                                'master.timeout:=30.0', '-p',
                                f'master.velocity_window:={WINDOW_NS * 1e-9}',
                                '-p', 'command.interface:=velocity')
    design = ecam_design(DEFAULT)
    link = MasterLink(executor)
    link.connect(process)
    count = 2 * SETTLED + 100
    nominal = PERIOD_NS * np.arange(count)  # sampled on the cycle, stamped late or early
    jitter = np.random.default_rng(11).integers(-JITTER_NS, JITTER_NS + 1, count)
    stamps = START_NS + nominal + jitter
    q = 1.0 + SPEED * nominal * 1e-9
    messages = [master_message(stamp, position=(qi,))
                for stamp, qi in zip(stamps.tolist(), q.tolist())]
    before = outputs(link)
    link.send(messages)
    sent, joints, commands = stepped(link, before, messages)  # by stamp: a backlog is skipped
    taken = np.isin(stamps, [stamp_of(m) for m in sent])
    commands = np.array([m.data[0] for m in commands])
    master_speed = np.array([m.velocity[0] for m in joints])
    follower_velocity = np.array([m.velocity[1] for m in joints])
    _, exact = reference(design, q[taken], SPEED)
    # From the first full window on, where the node took every message of the window: the cycle
    # clock follows a master it hears in full (a skipped backlog leaves the jittered stamps).
    skipped = np.concatenate([[0], np.cumsum(~taken)])
    oldest = np.searchsorted(nominal, nominal - WINDOW_NS)
    heard = skipped[np.arange(count) + 1] == skipped[oldest]
    full = ((nominal >= WINDOW_NS) & heard)[taken]
    assert full.sum() >= 100
    speed_error = np.abs(master_speed / SPEED - 1.0)[full]
    # A setpoint's error is its cam slope times the speed error: relative to the largest setpoint.
    setpoint_error = np.abs(commands - exact)[full] / np.abs(exact).max()
    report('jittered master, speed error max (joint states)', f'{speed_error.max():.3%}')
    report('jittered master, velocity setpoint error max / peak', f'{setpoint_error.max():.3%}')
    np.testing.assert_array_equal(follower_velocity, commands)
    assert speed_error.max() <= LIMIT and setpoint_error.max() <= LIMIT
    three_point = MasterTracker(SECOND)  # the stamps as they are: far off, the test can fail
    omega = [three_point.accept(t, qi, None, t).omega
             for t, qi in zip(stamps.tolist(), q.tolist())]
    assert np.abs(np.array(omega[SETTLED:]) / SPEED - 1.0).max() > 5 * LIMIT
    master = link.diagnostics('cam: master',
                              lambda v: int(v['accepted']) + int(v['skipped']) >= count)
    assert float(master['speed']) == pytest.approx(master_speed[-1], rel=1e-5)  # the last one
