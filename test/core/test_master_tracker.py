"""Master samples: message rules, speed estimates, the track over wraps, dropouts and restarts."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.ecam.master_tracker import (BACKWARDS, BadMaster, LENGTHS, LOST, MasterTracker,
                                              NO_JOINT, NOT_FINITE, OK, read_master, STALE,
                                              WAITING)

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
DESIGN = build_design(parse_parameters(read_parameters_file(DEFAULT)))
SECOND = 1_000_000_000


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


def test_a_multi_turn_master_keeps_its_own_position_as_the_track():
    multi_turn = MasterTracker(SECOND // 2)
    for k, q in enumerate([100.0, 100.01, 100.02]):
        assert multi_turn.accept(k, q, None, k).track == q  # exactly its own position


def run(tracker, stamps_ns, positions):
    """Feed samples (received at their stamps); return the states."""
    return [tracker.accept(stamp, q, None, stamp) for stamp, q in zip(stamps_ns, positions)]


@pytest.mark.parametrize('omega', [7.0, -7.0])
def test_a_wrapping_encoder_that_crossed_zero_during_a_dropout_goes_on_forward(omega):
    # The case: the shaft turns 252 deg unseen and crosses 0. Nearest the last position
    # that is 108 deg backwards; nearest the travel predicted from the last speed it is the
    # 252 deg the shaft really made (prediction exact at constant speed).
    period = 1_000_000
    stamps = [k * period for k in range(40)]
    true = [3.0 + omega * stamp * 1e-9 for stamp in stamps]
    tracker = MasterTracker(SECOND // 10, nominal=abs(omega))
    states = run(tracker, stamps, np.mod(true, 2 * math.pi).tolist())
    silence = math.radians(252.0) / abs(omega)
    tracker.check(stamps[-1] + SECOND // 10)
    assert tracker.status == LOST
    stamp = stamps[-1] + round(silence * 1e9)
    position = true[-1] + omega * silence
    back = tracker.accept(stamp, position % (2 * math.pi), None, stamp)
    assert back.track - states[-1].track == pytest.approx(math.copysign(math.radians(252.0),
                                                                        omega), abs=1e-9)
    assert not back.origin and tracker.jumps == 0 and back.step == 0.0  # starts afresh


def test_a_multi_turn_master_restarting_from_zero_is_a_new_origin_not_eleven_turns_back():
    # A knife's line shaft after 11 turns restarts its stream from 0 (a PLC restart): no motion
    # at the master's speed explains 11 turns back in one message, so it is a new origin.
    omega, period = 10.0, 1_000_000
    stamps = [k * period for k in range(30)]
    tracker = MasterTracker(SECOND // 2, nominal=omega)
    run(tracker, stamps, [22 * math.pi + omega * t * 1e-9 for t in stamps])
    assert tracker.multi_turn
    restart = tracker.accept(stamps[-1] + period, 0.0, None, stamps[-1] + period)
    assert restart.origin and tracker.jumps == 1 and restart.track == 0.0
    assert (restart.omega, restart.alpha, restart.step) == (0.0, 0.0, 0.0)
    after = tracker.accept(stamps[-1] + 2 * period, omega * 1e-3, None, stamps[-1] + 2 * period)
    assert not after.origin and after.omega == pytest.approx(omega)


@pytest.mark.parametrize('bound, nominal, jump, is_origin', [
    (0.0, 1.0, 0.019, False),  # under 2 x 10 x 1 rad/s x 1 ms
    (0.0, 1.0, 0.021, True),
    (5.0, 10.0, 0.009, False),  # master.max_speed sets it when given: 2 x 5 rad/s x 1 ms
    (5.0, 10.0, 0.011, True),
])
def test_a_jump_is_a_new_origin_beyond_twice_the_plausible_speed(bound, nominal, jump,
                                                                 is_origin):
    tracker = MasterTracker(SECOND, bound=bound, nominal=nominal)
    run(tracker, [0, 1_000_000, 2_000_000], [20.0] * 3)  # multi-turn, at rest: speed known
    state = tracker.accept(3_000_000, 20.0 + jump, None, 3_000_000)
    assert state.origin is is_origin and tracker.jumps == int(is_origin)


def test_a_master_far_faster_than_cam_speed_is_not_taken_for_jumps_after_a_loss():
    # 30 rad/s, over 2 x 10 x the 1 rad/s at cam_speed: the first samples after a loss are not
    # judged (the speed is not known yet), the later ones by the speed they give.
    tracker = MasterTracker(SECOND // 2, nominal=1.0)
    stamps = [k * 1_000_000 for k in range(1, 200)]
    run(tracker, stamps, [100.0 + 30.0 * t * 1e-9 for t in stamps])
    tracker.check(10 * SECOND)
    later = [10 * SECOND + stamp for stamp in stamps]
    states = run(tracker, later, [100.0 + 30.0 * t * 1e-9 for t in later])
    assert tracker.jumps == 0 and not any(state.origin for state in states)
    assert states[-1].omega == pytest.approx(30.0)


def test_an_encoder_of_minus_pi_to_pi_sending_exactly_minus_pi_still_wraps():
    """At pi rad/s every 10 ms, sample 100 is at pi: such an encoder sends -pi. The track stays
    the unwrapped pi k / 100 (the position -pi is in the wrapping range, not multi-turn)."""
    stamps = [k * 10_000_000 for k in range(151)]
    positions = [(math.pi * k / 100 + math.pi) % (2 * math.pi) - math.pi for k in range(151)]
    positions[100] = -math.pi
    tracker = MasterTracker(SECOND)
    states = run(tracker, stamps, positions)
    assert not tracker.multi_turn and tracker.jumps == 0
    track = np.array([state.track for state in states]) - states[0].track
    np.testing.assert_allclose(track, math.pi * np.arange(151) / 100, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize('off, is_origin', [(0.05, False), (0.07, True)])
def test_the_plausible_speed_is_the_last_speed_when_over_ten_times_nominal(off, is_origin):
    """30 rad/s with 1 rad/s at cam_speed: a travel off the prediction by more than
    2 x max(30, 10 x 1) rad/s x 1 ms = 0.06 rad is a new origin, by less it is not."""
    tracker = MasterTracker(SECOND, nominal=1.0)
    stamps = [k * 1_000_000 for k in range(10)]
    run(tracker, stamps, [100.0 + 30.0 * t * 1e-9 for t in stamps])
    state = tracker.accept(10_000_000, 100.0 + 0.3 + off, None, 10_000_000)
    assert state.origin is is_origin and tracker.jumps == int(is_origin)


@pytest.mark.parametrize('positions, origins', [
    ([20.0, 20.0, 21.0], [False, False, False]),  # the third: not judged
    ([20.0, 20.0, 20.0, 21.0], [False, False, False, True])])  # the fourth: judged
def test_after_a_loss_the_first_three_samples_are_taken_as_they_come_as_at_the_start(
        positions, origins):
    """The speed is known again after KNOWN_SPEED (3) samples: the fourth is the first judged,
    from scratch and after a loss alike (a jump of 1 rad in 1 ms, 1 rad/s nominal)."""
    stamps = [k * 1_000_000 for k in range(len(positions))]
    fresh = MasterTracker(SECOND // 2, nominal=1.0)
    first = run(fresh, stamps, positions)
    back = MasterTracker(SECOND // 2, nominal=1.0)
    run(back, [k * 1_000_000 for k in range(5)], [20.0] * 5)
    assert back.check(5 * SECOND) == LOST
    later = run(back, [6 * SECOND + stamp for stamp in stamps], positions)
    assert [state.origin for state in first] == [state.origin for state in later] == origins
