"""cam_node as an electronic cam: a real node process follows a master axis fed by the test."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest
from conftest import CONFIG_DIR
from ecam_support import (ecam_design, master_message, MasterLink, phases_profile, RPM, stamp_of,
                          StateWatch)
from rclpy.parameter import Parameter
from test_lifecycle import until
from test_node import set_parameters


DEFAULT = CONFIG_DIR / 'default.yaml'
TOPIC_MODE = ('-p', 'master.source:=topic')
#: MC_CamIn mapping of the main run, in the file's units (cm, deg).
MAPPING = {'master.offset_deg': 30.0, 'master.scaling': 2.0, 'slave.offset': 0.5,
           'slave.scaling': -1.0}
START_NS = 1_000 * 10 ** 9  # stamps of the master's run start here (any origin works)
DT = 0.004  # s between master messages (250 Hz: a loaded machine's node keeps up)


def ros_args(values: dict) -> list[str]:
    """Turn parameter values into -p arguments."""
    return [arg for name, value in values.items() for arg in ('-p', f'{name}:={value}')]


def reference(design, q, omega):
    """Follower position and velocity at master q, speed omega: MC_CamIn and chain rule here."""
    config = design.config.parameters
    scaling, slave_scaling = config['master.scaling'], config['slave.scaling']
    theta = np.mod((np.asarray(q) - math.radians(config['master.offset_deg'])) / scaling,
                   2 * math.pi)
    values = design.program.evaluate(theta)
    offset = config['slave.offset'] * 0.01  # cm
    return (slave_scaling * values.s + offset,
            slave_scaling * values.ds * np.asarray(omega) / scaling)


def outputs(link) -> dict:
    """Return how many commands and joint states arrived so far (before a run)."""
    return {key: len(link.messages(key)) for key in ('commands', 'joints')}


def stepped(link, before: dict, messages) -> tuple[list, list, list]:
    """Return the messages the node answered, their joint states and their commands, by stamp.

    Every line shaft step sends one ~/commands and one ~/joint_states, in order; only the joint
    states carry a stamp, so each command is paired with the next joint state (since before)
    whose axis positions or velocities it carries. A test process held up can lose one of
    either (the node's publishers keep the last 10): those steps are left out. At least a
    quarter of the messages must be paired.
    """
    sent, answers = link.answered(messages)
    joints, commands = (link.messages(key)[before[key]:] for key in ('joints', 'commands'))
    paired, k = {}, 0
    for command in commands:
        values = list(command.data)
        while k < len(joints) and values not in (list(joints[k].position[1:]),
                                                 list(joints[k].velocity[1:])):
            k += 1
        if k == len(joints):
            break
        paired[stamp_of(joints[k])] = command
        k += 1
    kept = [(message, answer) for message, answer in zip(sent, answers)
            if stamp_of(answer) in paired]
    assert 4 * len(kept) >= len(messages), f'{len(kept)} of {len(messages)} paired'
    return ([message for message, _ in kept], [answer for _, answer in kept],
            [paired[stamp_of(answer)] for _, answer in kept])


def at_rest(link) -> bool:
    """Say whether the last command, joint state and trajectory hold the follower at rest."""
    return (list(link.messages('commands')[-1].data) == [0.0]
            and list(link.messages('joints')[-1].velocity) == [0.0, 0.0]
            and all(list(point.velocities) == [0.0]
                    for point in link.messages('trajectories')[-1].points))


def test_commands_follow_a_ramp_stop_reversal_and_multi_turn_master(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE, *ros_args(MAPPING), '-p',
                                'master.timeout:=10.0')
    design = ecam_design(DEFAULT, **MAPPING)
    link = MasterLink(executor)
    link.connect(process)
    accelerate = 600 * RPM / 0.5
    times, q, omega, phase = phases_profile(
        [(0.5, accelerate), (0.2, 0.0), (0.5, -accelerate), (0.1, 0.0), (0.3, -accelerate / 2),
         (0.2, 0.0)], DT, q0=-3.0)
    assert q.max() - q.min() > 4 * 2 * math.pi  # several master (and cam) turns
    with_velocity = times < 0.9  # the first half says its speed, the second leaves it out
    stamps = START_NS + np.round(times * 1e9).astype(np.int64)
    messages = [master_message(stamp, ('other', 'cam'), (5.0, position),
                               (1.0, speed) if given else ())
                for stamp, position, speed, given in zip(stamps.tolist(), q.tolist(),
                                                         omega.tolist(), with_velocity.tolist())]
    before = outputs(link)
    link.send(messages)
    sent, joints, commands = stepped(link, before, messages)
    taken = np.isin(stamps, [stamp_of(m) for m in sent])  # the node skips a backlog
    # Estimated speeds are exact once the window's samples (master.velocity_window 0.02 s: this
    # one and those up to 18 ms before) lie in one constant-acceleration phase.
    back = round(0.018 / DT)
    same_phase = np.zeros_like(with_velocity)
    same_phase[back:] = phase[back:] == phase[:-back]
    q, omega, with_velocity, same_phase, stamps = (
        array[taken] for array in (q, omega, with_velocity, same_phase, stamps))
    position, velocity = reference(design, q, omega)
    np.testing.assert_allclose([m.data[0] for m in commands], position, rtol=0, atol=1e-12)

    later = [stamp_of(m) for m in link.messages('joints') if stamp_of(m) >= START_NS]
    assert later == stamps.tolist()  # same stamp as the master, and no step of its own
    assert all(m.name == ['cam', 'follower'] for m in joints)
    np.testing.assert_array_equal([m.position[0] for m in joints], q)  # the master as given
    np.testing.assert_array_equal([m.velocity[0] for m in joints][:10], omega[:10])
    np.testing.assert_allclose([m.position[1] for m in joints], position, rtol=0, atol=1e-12)
    follower_velocity = np.array([m.velocity[1] for m in joints])
    np.testing.assert_allclose(follower_velocity[with_velocity], velocity[with_velocity],
                               rtol=1e-12, atol=1e-15)
    estimated = ~with_velocity & same_phase
    estimated[np.flatnonzero(~with_velocity)[:2]] = False
    assert estimated.sum() > 100
    np.testing.assert_allclose(follower_velocity[estimated], velocity[estimated], rtol=1e-6,
                               atol=1e-9)
    assert process.process.poll() is None


def test_bad_master_messages_are_dropped_counted_and_never_commanded(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE, '-p', 'command.interface:=velocity',
                                '-p', 'command.trajectory_horizon:=0.05',
                                '-p', 'command.trajectory_points:=5', '-p', 'master.timeout:=1.0',
                                '-p', 'master.max_speed:=25.0', '-p',
                                'master.engage_mode:=immediate')  # back on the cam at once
    design = ecam_design(DEFAULT)
    link = MasterLink(executor)
    states = StateWatch(link)
    link.connect(process)
    good = [master_message(START_NS + k * 10 ** 7, position=(1.9 + 0.2 * k,), velocity=(20.0,))
            for k in range(5)]
    origin = time.monotonic()

    def now_ns() -> int:
        """The master's clock now: stamps sent later are after the node's own steps'."""
        return START_NS + round((time.monotonic() - origin) * 1e9)

    before = outputs(link)
    link.send(good)
    sent, _, commands = stepped(link, before, good)
    np.testing.assert_allclose([m.data[0] for m in commands],
                               reference(design, [m.position[0] for m in sent], 20.0)[1],
                               rtol=1e-12)
    link.inbox['trajectories'].wait(len(link.messages('commands')))
    last = link.messages('trajectories')[-1]
    times = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec
                      for p in last.points])
    np.testing.assert_allclose(times, 0.01 * np.arange(1, 6), atol=1e-9)
    ahead_position, ahead_velocity = reference(design, 2.7 + 20.0 * times, 20.0)
    np.testing.assert_allclose([p.positions[0] for p in last.points], ahead_position, atol=1e-12)
    np.testing.assert_allclose([p.velocities[0] for p in last.points], ahead_velocity,
                               rtol=1e-12)
    assert last.joint_names == ['follower'] and all(len(p.accelerations) == 1
                                                    for p in last.points)

    stamp = now_ns() + 10 ** 7
    bad = [master_message(stamp, names=('other',), position=(1.0,)),
           master_message(stamp + 1, position=(math.nan,)),
           master_message(stamp + 2, position=(math.inf,)),
           master_message(stamp + 3, position=(1.0,), velocity=(-math.inf,)),
           master_message(stamp + 4, names=('cam', 'x'), position=(1.0,)),
           master_message(stamp + 5, position=(1.0,), velocity=(1.0, 2.0)),
           master_message(stamp + 6, position=(1.0,), effort=(1.0, 2.0)),
           master_message(START_NS, position=(1.0,)),  # backwards
           master_message(START_NS + 4 * 10 ** 7, position=(1.0,))]  # equal to the last
    link.send(bad, answered=False)
    fast = [master_message(stamp + 7, position=(3.0,), velocity=(30.0,))]  # too fast
    before = outputs(link)
    link.send(fast)
    answered = stepped(link, before, fast)[2][0]
    assert answered.data[0] == reference(design, 3.0, 30.0)[1]
    # The probes' stamps count up from 1 ns; the node's own steps while they are silent come
    # 0.1 s (master.timeout / 10) of silence later.
    probes = len([m for m in link.messages('joints') if stamp_of(m) < 10 ** 8])
    master = link.diagnostics('cam: master', lambda v: v['dropped'] == '9' and  # a backlog:
                              int(v['accepted']) + int(v['skipped']) == 6 + probes)  # skipped
    assert master['message'].endswith(', over master.max_speed')  # ok or already stale
    assert master['level'] == b'\x01'
    assert master['dropped: no master joint'] == '1'
    assert master['dropped: not finite'] == '3'
    assert master['dropped: mismatched array lengths'] == '3'
    assert master['dropped: stamp not after the previous'] == '2'
    assert process.process.poll() is None

    # Master loss: the line shaft stops on the cam (no limits: over master.engage_distance_deg
    # from its speed), never in one message; at rest nothing more is sent. The commands since
    # the one answering the last master message (the stop may be over before the test looks).
    lost = link.diagnostics('cam: master', lambda v: v['message'] == 'lost')
    assert lost['level'] == b'\x02'
    states.wait('at rest: master lost')
    until(lambda: at_rest(link), 'at rest said, not sent', timeout=5.0)  # (on other topics)
    assert len(link.after('commands', answered)) > 2
    assert 'stopping: master lost' in [m.message for m in states.inbox.messages]
    rested = len(link.messages('commands'))
    time.sleep(1.0)
    assert len(link.messages('commands')) == rested  # at rest: said once
    # The master comes back at 10 rad/s: the line shaft catches up with it, then follows it
    # exactly again.
    back = [master_message(now_ns() + 10 ** 7 + k * 10 ** 7, position=(2.5 + 0.1 * k,),
                           velocity=(10.0,)) for k in range(160)]
    before = outputs(link)
    link.send(back)
    sent, _, commands = stepped(link, before, back)
    assert len(sent) >= 50
    np.testing.assert_allclose([m.data[0] for m in commands[-50:]],
                               reference(design, [m.position[0] for m in sent[-50:]], 10.0)[1],
                               rtol=0, atol=1e-12)  # m/s: the cam's turns added back
    link.diagnostics('cam: master', lambda v: v['message'] == 'ok')
    log = process.log()
    assert 'master silent for 1 s' in log and 'master lost -> ok' in log
    assert 'dropped a master message' in log
    assert log.count('over master.max_speed (25 rad/s)') == 1


def test_a_master_over_the_jump_speed_is_warned_about(start_cam_node, executor):
    machine = CONFIG_DIR / 'machine_dynamics.yaml'
    process, _ = start_cam_node(machine, *TOPIC_MODE, '-p', 'master.scaling:=2.0',
                                '-p', 'master.timeout:=30.0')
    jump = ecam_design(machine).dynamics_check.jump_speed  # cam rad/s
    link = MasterLink(executor)
    link.connect(process)
    design = link.diagnostics('cam: design', lambda v: True)
    assert float(design['jump_speed_rad_s']) == pytest.approx(jump, rel=1e-5)
    link.send([master_message(START_NS, position=(1.0,), velocity=(1.9 * jump,)),
               master_message(START_NS + 10 ** 7, position=(1.2,), velocity=(2.1 * jump,))])
    master = link.diagnostics('cam: master', lambda v: v['message'].endswith('jump speed'))
    assert master['speed_limit'] == f'{2 * jump:.6g} (the jump speed)'
    log = process.log()
    assert log.count('over the jump speed') == 1 and f'{2.1 * jump:.6g} rad/s' in log


def test_design_change_on_a_running_master_waits_for_a_common_place(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, *TOPIC_MODE, '-p', 'master.timeout:=30.0')
    rise = {'motion.start_position': [0.0, 0.0, 3.0, 3.0],
            'motion.end_position': [0.0, 3.0, 3.0, 0.0]}
    old, new = ecam_design(DEFAULT), ecam_design(DEFAULT, **rise)
    link = MasterLink(executor)
    link.connect(process)
    speed = math.pi  # 30 rpm, 250 Hz: two turns from 57 deg, the change asked for at 100 deg
    q = 1.0 + speed * DT * np.arange(1000)
    stamps = START_NS + np.round(DT * 1e9 * np.arange(q.size)).astype(np.int64)
    messages = [master_message(stamp, position=(angle,), velocity=(speed,))
                for stamp, angle in zip(stamps.tolist(), q.tolist())]
    first = outputs(link)
    origin = time.monotonic()
    running = link.stream(messages, DT)  # the master runs on while the parameters are set
    time.sleep((math.radians(100.0) - q[0]) / speed)
    result = set_parameters(executor, [Parameter(name, value=value)
                                       for name, value in rise.items()])
    asked = START_NS + round((time.monotonic() - origin) * 1e9)  # messages after: asked before
    assert result.successful, result.reason
    running.join()
    answered, _, commands = stepped(link, first, messages)
    taken = np.isin(stamps, [stamp_of(m) for m in answered])
    q, stamps = q[taken], stamps[taken]
    commands = np.array([m.data[0] for m in commands])
    by_old, by_new = reference(old, q, speed)[0], reference(new, q, speed)[0]
    from_old = np.abs(commands - by_old) <= 1e-12
    from_new = np.abs(commands - by_new) <= 1e-12
    assert (from_old | from_new).all()
    # Asked for in the rise (the cams differ from 90 deg to 360 deg), the change waits: the old
    # cam rules on through the rise, the dwell and the return; the new one from the common dwell
    # at 0-90 deg on (applied at the cycle start, the cams' first difference at 90-100 deg).
    degrees = np.degrees(q)
    assert 90.0 < degrees[np.searchsorted(stamps, asked)] < 340.0, 'asked too late to show it'
    waiting = (stamps > asked) & (degrees < 360.0)
    assert np.sum(waiting & ~from_new) > 50 and from_old[waiting].all()
    new_only = np.flatnonzero(from_new & ~from_old)
    assert 450.0 < degrees[new_only[0]] < 460.0
    assert from_new[new_only[0]:].all() and from_old[:new_only[0]].all()
    # No step: every increment is one the old or the new cam makes over the same master step.
    increments = np.maximum(np.abs(np.diff(by_old)), np.abs(np.diff(by_new)))
    assert (np.abs(np.diff(commands)) <= increments + 1e-9).all()
    log = process.log()
    assert 'design change pending' in log and 'design change applied at cam angle' in log
    refused = set_parameters(executor, [Parameter('master.topic', value='/other')])
    assert not refused.successful and refused.reason.startswith("master.topic = '/other'")
    assert 'restart the node' in refused.reason
