"""Electronic cam core: MC_CamIn mapping, chain-rule setpoints, estimator, message rules."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter, build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.master import (BACKWARDS, BadMaster, CamMapping, ElectronicCam,
                                      LENGTHS, LOST, MasterConfig, MasterTracker, NO_JOINT,
                                      NOT_FINITE, OK, read_master, STALE, WAITING)

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
DESIGN = build_design(parse_parameters(read_parameters_file(DEFAULT)))
MAPPING = CamMapping(master_offset=0.3, master_scaling=2.5, slave_offset=0.01,
                     slave_scaling=-1.5)
CAM = ElectronicCam(DESIGN.program, MAPPING)
#: Relative agreement of an exact chain rule with central differences of step H_S.
DIFFERENCE_RTOL = 1e-6
H_S = 1e-4
SECOND = 1_000_000_000


def reference_setpoint(q: float) -> float:
    """Follower position at master q, by the MC_CamIn formula written out here."""
    theta = math.fmod((q - MAPPING.master_offset) / MAPPING.master_scaling, 2 * math.pi)
    theta += 2 * math.pi if theta < 0 else 0.0
    s = float(DESIGN.program.evaluate(theta).s)
    return MAPPING.slave_scaling * s + MAPPING.slave_offset


@pytest.mark.parametrize('q', [0.0, 0.3, 1.7, -2.0, 12.0 * math.pi + 4.0, -101.3, 1e4 + 0.5])
def test_master_positions_map_modulo_one_cam_revolution(q):
    assert float(CAM.setpoints(q).position) == pytest.approx(reference_setpoint(q), abs=1e-12)
    assert 0.0 <= float(MAPPING.cam_angle(q)) < 2 * math.pi


@pytest.mark.parametrize('q0', [2.8, 4.0, 8.5, -3.0])  # rise, dwell end, return, negative
def test_velocity_acceleration_jerk_are_the_chain_rule_of_the_master_motion(q0):
    omega, alpha = 7.0, -3.0  # constant master acceleration: q = q0 + omega t + alpha t^2 / 2

    def position(t):
        return CAM.setpoints(q0 + omega * t + 0.5 * alpha * t ** 2).position

    t = H_S * np.arange(-2, 3)
    y = position(t)
    point = CAM.setpoints(q0, omega, alpha)
    velocity = (y[3] - y[1]) / (2 * H_S)
    acceleration = (y[3] - 2 * y[2] + y[1]) / H_S ** 2
    jerk = (y[4] - 2 * y[3] + 2 * y[1] - y[0]) / (2 * H_S ** 3)
    scale = max(1e-3, abs(float(point.velocity)))
    assert float(point.velocity) == pytest.approx(velocity, rel=DIFFERENCE_RTOL, abs=1e-9 * scale)
    assert float(point.acceleration) == pytest.approx(acceleration, rel=1e-4, abs=1e-5)
    assert float(point.jerk) == pytest.approx(jerk, rel=1e-2, abs=1e-2)


def test_setpoints_broadcast_over_arrays_like_single_samples():
    """One sample in floats (a master message) gives the very numbers of the array path."""
    q = np.linspace(-20.0, 20.0, 101)
    omega = np.linspace(-60.0, 60.0, 101)
    together = CAM.setpoints(q, omega, 2.0)
    for index in range(q.size):
        for alone in (CAM.setpoints(float(q[index]), float(omega[index]), 2.0),
                      CAM.setpoints(q[index], omega[index], 2.0)):  # NumPy scalars
            for field in together._fields:
                assert getattr(together, field)[index] == getattr(alone, field), (index, field)
    assert all(type(value) is float for value in CAM.setpoints(1.0, 3.0, 2.0))


def test_parameters_convert_to_si(tmp_path):
    values = read_parameters_file(DEFAULT)  # length_unit cm
    values.update({'master.offset_deg': 90.0, 'master.scaling': 2.0, 'slave.offset': 1.5,
                   'slave.scaling': -1.0, 'master.source': 'topic', 'master.timeout': 0.2,
                   'command.interface': 'velocity', 'command.trajectory_horizon': 0.05})
    config = MasterConfig.from_config(parse_parameters(values))
    assert config.mapping == CamMapping(math.pi / 2, 2.0, pytest.approx(0.015), -1.0)
    assert (config.source, config.topic, config.joint) == ('topic', '~/master', 'cam')
    assert (config.timeout, config.interface, config.trajectory_horizon) == (0.2, 'velocity',
                                                                             0.05)


def test_oscillating_slave_offset_is_in_degrees():
    values = read_parameters_file(DEFAULT)
    values.update({'follower.type': 'oscillating_roller', 'slave.offset': 10.0})
    config = parse_parameters(values)  # parsing builds no geometry
    assert MasterConfig.from_config(config).mapping.slave_offset == pytest.approx(
        math.radians(10.0))


@pytest.mark.parametrize('max_speed, jump, expected', [
    (0.0, None, (math.inf, 'no limit')),
    (0.0, 30.0, (60.0, 'the jump speed')),  # cam rad/s times master.scaling 2
    (50.0, 30.0, (50.0, 'master.max_speed')),
    (50.0, 20.0, (40.0, 'the jump speed')),
    (50.0, 0.0, (0.0, 'the jump speed')),  # contact lost at rest: any motion warns
])
def test_the_speed_limit_is_the_lower_of_max_speed_and_the_jump_speed(max_speed, jump,
                                                                      expected):
    values = read_parameters_file(DEFAULT)
    values.update({'master.scaling': 2.0, 'master.max_speed': max_speed})
    assert MasterConfig.from_config(parse_parameters(values)).speed_limit(jump) == expected


@pytest.mark.parametrize('name, value, fragment', [
    ('master.scaling', 0.0, '>= 1e-06'),
    ('master.source', 'encoder', 'one of clock, topic'),
    ('command.interface', 'effort', 'one of position, velocity'),
    ('master.timeout', -1.0, '>= 0.001'),
    ('command.trajectory_points', 0, '>= 1'),
    ('slave.offset', 1e6, 'must not exceed'),
])
def test_bad_master_parameters_are_refused_by_name(name, value, fragment):
    values = read_parameters_file(DEFAULT)
    values[name] = value
    with pytest.raises(InvalidParameter, match=fragment) as caught:
        parse_parameters(values)
    assert caught.value.parameter == name


# Master messages ------------------------------------------------------------------------------

@pytest.mark.parametrize('names, position, velocity, effort, reason', [
    (['other'], [1.0], [], [], NO_JOINT),
    ([], [], [], [], NO_JOINT),
    (['cam', 'x'], [1.0], [], [], LENGTHS),
    (['cam'], [1.0], [1.0, 2.0], [], LENGTHS),
    (['cam'], [1.0], [], [0.0, 0.0], LENGTHS),
    (['cam'], [math.nan], [], [], NOT_FINITE),
    (['cam'], [math.inf], [], [], NOT_FINITE),
    (['x', 'cam'], [0.0, 1.0], [0.0, -math.inf], [], NOT_FINITE),
])
def test_bad_master_messages_raise_their_reason(names, position, velocity, effort, reason):
    with pytest.raises(BadMaster) as caught:
        read_master('cam', names, position, velocity, effort)
    assert caught.value.reason == reason


def test_good_master_messages_give_position_and_optional_velocity():
    assert read_master('cam', ['x', 'cam'], [5.0, 1.5], [], []) == (1.5, None)
    assert read_master('cam', ['x', 'cam'], [math.nan, 1.5], [0.0, -2.0], [1.0, 1.0]) == (
        1.5, -2.0)  # only the master's values must be finite


def accelerating(stamps_ns, q0=1.0, omega0=-4.0, alpha=25.0):
    """Return the positions, speeds of a master at constant acceleration at the stamps."""
    t = np.asarray(stamps_ns) * 1e-9
    return q0 + omega0 * t + 0.5 * alpha * t ** 2, omega0 + alpha * t


@pytest.mark.parametrize('wrapped', [False, True])
def test_estimates_are_exact_for_constant_acceleration_at_irregular_stamps(wrapped):
    stamps = np.cumsum([0, 1_000_000, 2_500_000, 700_000, 1_300_000, 4_000_000]) * 50
    positions, speeds = accelerating(stamps)
    if wrapped:  # an encoder reporting [0, 2 pi) must give the same estimates
        positions = np.mod(positions, 2 * math.pi)
    tracker, history = MasterTracker(SECOND), []
    for index, (stamp, q) in enumerate(zip(stamps.tolist(), positions.tolist())):
        state = tracker.accept(stamp, q, None, stamp)
        history.append(state)
        if index >= 2:
            assert state.omega == pytest.approx(speeds[index], rel=1e-9, abs=1e-9)
            assert state.alpha == pytest.approx(25.0, rel=1e-7)
    assert history[0].omega == 0.0 and history[1].alpha == 0.0


def test_a_given_velocity_is_used_and_alpha_follows_from_it():
    stamps = [0, 1_000_000, 3_000_000]
    positions, speeds = accelerating(stamps)
    tracker = MasterTracker(SECOND)
    first = tracker.accept(stamps[0], positions[0], speeds[0], 0)
    second = tracker.accept(stamps[1], positions[1], speeds[1], 0)
    assert (first.omega, first.alpha) == (speeds[0], 0.0)
    assert second.omega == speeds[1]
    assert second.alpha == pytest.approx(25.0, rel=1e-9)


def test_tracker_refuses_stamps_that_do_not_advance():
    tracker = MasterTracker(SECOND // 2)
    tracker.accept(10, 0.0, None, 0)
    for stamp in (10, 9):
        with pytest.raises(BadMaster) as caught:
            tracker.accept(stamp, 0.1, None, 1)
        assert caught.value.reason == BACKWARDS
    assert tracker.accepted == 1


def test_tracker_goes_stale_then_lost_once_and_restarts_its_estimates_on_return():
    timeout = SECOND // 2
    tracker = MasterTracker(timeout)
    assert tracker.check(10 * SECOND) is None and tracker.status == WAITING
    for k in range(3):
        tracker.accept(k * 1_000_000, 2.0 * k * 1e-3, None, k * 1_000_000)
    assert tracker.status == OK
    received = 2_000_000
    assert tracker.check(received + timeout // 2 - 1) is None
    assert tracker.check(received + timeout // 2) == STALE
    assert tracker.check(received + timeout - 1) is None
    assert tracker.check(received + timeout) == LOST
    assert tracker.check(received + 5 * timeout) is None
    back = tracker.accept(5 * SECOND, 7.0, None, 5 * SECOND)
    assert tracker.status == OK and (back.omega, back.alpha, back.step) == (0.0, 0.0, 0.0)
    assert tracker.check(5 * SECOND + 1) is None


def test_tracker_flags_overspeed_while_it_lasts():
    tracker = MasterTracker(SECOND, max_speed=10.0)
    tracker.accept(0, 0.0, 11.0, 0)
    assert tracker.overspeed
    tracker.accept(1, 0.0, -9.0, 0)
    assert not tracker.overspeed
    tracker.accept(2, 0.0, 12.0, 0)
    tracker.check(SECOND // 2)
    assert tracker.overspeed  # stale: still the last known speed
    tracker.check(SECOND)
    assert not tracker.overspeed  # lost: not moving any more
    unlimited = MasterTracker(SECOND)
    unlimited.accept(0, 0.0, 1e9, 0)
    assert not unlimited.overspeed


def master_commands(tracker, cam, stamps, positions):
    """Return the position setpoints a stream of master samples gives through a tracker."""
    return np.array([float(cam.setpoints(tracker.accept(stamp, q, None, stamp).track).position)
                     for stamp, q in zip(stamps, positions)])


@pytest.mark.parametrize('scaling', [0.5, 2.0, 3.0])
@pytest.mark.parametrize('omega', [9.0, -7.0])
def test_a_wrapping_encoder_gives_the_commands_of_a_multi_turn_master(scaling, omega):
    # A master over five turns at 250 Hz, as a multi-turn position and as an encoder in [0, 2 pi)
    # that starts at the same physical position: every command equals the MC_CamIn formula of
    # the multi-turn position (written out above), so the wrapping encoder no longer jumps.
    cam = ElectronicCam(DESIGN.program, CamMapping(master_offset=0.3, master_scaling=scaling))
    stamps = (np.arange(int(5 * 2 * math.pi / abs(omega) * 250)) * 4_000_000).tolist()
    multi = (1.0 + omega * np.asarray(stamps) * 1e-9).tolist()
    wrapped = np.mod(multi, 2 * math.pi).tolist()
    expected = []
    for q in multi:
        theta = math.fmod((q - 0.3) / scaling, 2 * math.pi)
        expected.append(float(DESIGN.program.evaluate(theta + (2 * math.pi if theta < 0 else 0))
                              .s))
    from_multi = master_commands(MasterTracker(SECOND), cam, stamps, multi)
    from_wrapped = master_commands(MasterTracker(SECOND), cam, stamps, wrapped)
    np.testing.assert_allclose(from_multi, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(from_wrapped, expected, rtol=0, atol=1e-9)
    # no step at a wrap: the largest change between samples is the multi-turn master's
    largest = np.abs(np.diff(from_multi)).max()
    assert np.abs(np.diff(from_wrapped)).max() == pytest.approx(largest, abs=1e-9)


def test_the_track_keeps_its_turns_over_a_master_loss():
    tracker = MasterTracker(SECOND // 2)
    for k, q in enumerate([6.2, 0.05, 0.1]):  # wraps once: track 2 pi + 0.05, 2 pi + 0.1
        tracker.accept(k * 1_000_000, q, None, k * 1_000_000)
    assert tracker.last.track == pytest.approx(2 * math.pi + 0.1, abs=1e-15)
    tracker.check(10 * SECOND)
    back = tracker.accept(10 * SECOND, 0.2, None, 10 * SECOND)
    assert back.track == pytest.approx(2 * math.pi + 0.2, abs=1e-15)
    multi_turn = MasterTracker(SECOND // 2)
    for k, q in enumerate([100.0, 100.01, 100.02]):
        assert multi_turn.accept(k, q, None, k).track == q  # exactly its own position
