"""Safe commands on master faults: the axis's limits, one-way and rotary slaves, restarts.

Every check reads the commands themselves: a position difference over a message interval is the
mean velocity over it, a second difference the mean acceleration, so neither can exceed a limit
the commands keep (and both stay below it by at most round-off).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONFIG_DIR

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.follow import ENGAGED, EngageConfig, ENGAGING, Follower
from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.line_shaft import FILTERED, LOCKED
from cam_ros.core.ecam.master_tracker import LOST, MasterTracker
from cam_ros.core.ecam.path_limits import PathLimits
from cam_ros.core.ecam.slave_limits import AxisUnit, CamPeaks, SlaveLimits
from cam_ros.core.ecam.stop import Stop

KNIFE = CONFIG_DIR / 'rotary_knife.yaml'
DEFAULT = CONFIG_DIR / 'default.yaml'
TWO_PI = 2.0 * math.pi
PERIOD = 1_000_000  # ns: a 1 kHz master
SECOND = 1_000_000_000
#: Round-off allowed on the commands' own differences (per s, per s^2).
SLACK = 1e-6


def axis(path, **changes):
    """Return (cam, engage config, limits, nominal master speed) of a params file with changes."""
    values = read_parameters_file(path)
    values.update(changes)
    config = parse_parameters(values)
    design = build_design(config)
    master = MasterConfig.from_config(config)
    return (ElectronicCam(design.program, master.mapping),
            EngageConfig.from_parameters(config.parameters),
            SlaveLimits.from_config(config), master.nominal_speed, AxisUnit.of(config))


def knife(**changes):
    """The rotary knife of config/rotary_knife.yaml, one-way, limited (deg/s, deg/s^2)."""
    return axis(KNIFE, **{'slave.max_velocity': math.degrees(25.0),
                          'slave.max_acceleration': math.degrees(400.0),
                          'slave.direction': 'positive', **changes})


class Run:
    """A follower, its machine of one axis (SlaveAxes: the line shaft), driven by stamped master
    positions through a MasterTracker as cam_node drives them."""

    def __init__(self, cam, config, limits, nominal, unit, present=None):
        self.follower = Follower(cam, config, engage=True, limits=limits, unit=unit)
        self.follower.present = present
        self.axes = SlaveAxes(['axis'], [self.follower], ['position'])
        self.tracker = MasterTracker(SECOND // 2, nominal=nominal)
        self.stamps, self.positions, self.velocities, self.phases = [], [], [], []
        self.stamp = 0

    def feed(self, positions, period=PERIOD):
        """Send master positions one period apart (a master back after a loss is followed)."""
        for q in positions:
            self.stamp += period
            lost = self.tracker.status == LOST
            state = self.tracker.accept(self.stamp, float(q), None, self.stamp)
            if lost:
                self.axes.shaft.follow()
            self.note(self.axes.command(state))

    def note(self, commands):
        """Keep the commands of a step."""
        if commands is not None:
            self.stamps.append(self.stamp)
            self.positions.append(commands.position[0])
            self.velocities.append(commands.velocity[0])
            self.phases.append(self.follower.phase)

    def silence(self, seconds):
        """Let the master be silent: the clock steps the line shaft every period, and stops it
        once the master is lost (after the tracker's timeout)."""
        position = self.tracker.last.position
        for _ in range(round(seconds * 1e9) // PERIOD):
            self.stamp += PERIOD
            if self.tracker.check(self.stamp) == LOST:
                self.axes.shaft.halt('master lost')
            self.note(self.axes.tick(self.stamp, position))

    def differences(self):
        """Return the commands' mean velocities and accelerations between messages."""
        t = np.array(self.stamps) * 1e-9
        p = np.array(self.positions)
        v = np.diff(p) / np.diff(t)
        return v, np.diff(v) / np.diff(t)[1:]


def assert_within(run, limits):
    velocity, acceleration = run.differences()
    assert np.abs(velocity).max() <= limits.max_velocity + SLACK
    assert np.abs(acceleration).max() <= limits.max_acceleration + SLACK
    if limits.direction:
        assert (limits.direction * velocity).min() >= -SLACK


def assert_rejoined(run, cam, q, turn):
    """The last commands are the cam's own, a whole number of turns on (exactly)."""
    want = cam.setpoints(np.asarray(q)).position
    shift = np.round((np.array(run.positions[-len(q):]) - want) / turn) * turn if turn else 0.0
    np.testing.assert_allclose(np.array(run.positions[-len(q):]), want + shift, rtol=0,
                               atol=1e-12)
    assert np.ptp(shift) == 0.0


def test_cam_peaks_are_the_refined_extremes_of_the_cams_slopes():
    cam, _, limits, nominal, _ = knife()
    peaks = CamPeaks.of(cam)
    q = np.linspace(0.0, TWO_PI * cam.mapping.master_scaling, 400_001)
    d = cam.derivatives(q)
    assert peaks.slope[1] == pytest.approx(d.dy.max(), rel=1e-9)
    assert peaks.slope[0] == pytest.approx(d.dy.min(), rel=1e-9)
    assert peaks.curvature >= np.abs(d.d2y).max() * (1 - 1e-9)
    # The knife's figures at 1 m/s of web (config/rotary_knife.yaml's comment): 12.14 rad/s
    at = peaks.at(nominal, 0.0, limits.direction)
    assert at.velocity == pytest.approx(12.14, abs=0.005) and at.backward <= 0.0
    assert peaks.at(-nominal, 0.0, limits.direction).backward == pytest.approx(at.velocity)


def test_a_knife_engaging_312_deg_behind_the_cam_keeps_its_limits_and_never_turns_back():
    # The issue: a knife catching up 312 deg within the 30 deg engage distance ran at 84-98
    # rad/s against the cam's 8.8. Now the line shaft rests while the knife moves forward onto
    # its cam in time within its limits, then catches up with the master.
    cam, config, limits, nominal, unit = knife()
    speed = nominal  # m/s of web
    q0 = 0.3
    present = float(cam.setpoints(q0).position) - math.radians(312.0)
    run = Run(cam, config, limits, nominal, unit, present)
    q = q0 + speed * 1e-3 * np.arange(1, 12_000)
    run.feed(q)
    assert run.phases[0] == ENGAGING and run.phases[-1] == ENGAGED
    assert run.positions[0] == pytest.approx(present, abs=1e-12)
    assert_within(run, limits)
    assert_rejoined(run, cam, q[-1000:], limits.turn)


def test_a_master_restart_after_eleven_turns_is_a_new_origin_the_knife_goes_on_forward():
    cam, config, limits, nominal, unit = knife()
    run = Run(cam, config, limits, nominal, unit)
    step = nominal * 1e-3
    turns = 11 * TWO_PI * cam.mapping.master_scaling  # 11 cuts of web
    run.feed(step * np.arange(1, round(turns / step)))
    made = run.positions[-1]
    assert made > 10 * TWO_PI and run.tracker.multi_turn  # 6.9 m of web: a multi-turn master
    # The stream restarts from 0 (a PLC restart): a jump of -6.9 m of web in 1 ms.
    q = step * np.arange(0, 12_000)
    run.feed(q)
    assert run.tracker.jumps == 1
    assert min(run.positions[-12_000:]) >= made - 1e-12  # never back over the turns made
    assert_within(run, limits)
    assert_rejoined(run, cam, q[-1000:], limits.turn)


def test_a_phase_shift_on_a_running_one_way_knife_is_a_forward_move_at_rest_in_least_time():
    # master.offset_deg of a web master (m): 1.5 deg is 26 mm of web, a quarter of the cut's
    # 100 mm. The line shaft stops the knife on its old cam (a synchronized stop), the knife
    # moves forward onto the new cam in time, then the line shaft catches up with the master.
    cam, config, limits, nominal, unit = knife()
    run = Run(cam, config, limits, nominal, unit)
    step = nominal * 1e-3
    run.feed(step * np.arange(1, 2000))
    assert run.axes.shaft.mode == LOCKED
    shifted_cam, shifted_config, *_ = knife(**{'master.offset_deg': 1.5})
    assert run.follower.change(shifted_cam, shifted_config, limits).startswith('moves onto')
    new = PathLimits.of([shifted_cam], [limits], nominal, shifted_config.distance)
    both = PathLimits.of([cam, shifted_cam], [limits, limits], nominal, shifted_config.distance)
    run.axes.retarget(new, True, both, True)
    assert run.axes.shaft.limits is both  # on its old cam until the move: both meanwhile
    begun = None
    q = step * np.arange(2000, 14_000)
    for position in q:
        run.feed([position])
        if begun is None and run.follower.move is not None:
            begun = run.follower.move, run.axes.virtual, len(run.positions)
    move, virtual, at = begun
    assert virtual.omega == 0.0 and run.axes.shaft.limits is new
    # From the old cam (a whole number of turns on) where theta_v rests: the move's first
    # command
    start = run.positions[at - 1]
    on_old = float(cam.setpoints(virtual.track).position)
    assert move.start.position == start
    assert (start - on_old) / limits.turn == pytest.approx(round((start - on_old) / limits.turn),
                                                           abs=1e-12)
    onto = float(shifted_cam.setpoints(virtual.track).position)  # where theta_v rests
    end = onto + limits.turn * math.ceil((start - onto) / limits.turn)  # the nearest turn ahead
    # Least time of a rest-to-rest move over d within v, a (no jerk limit): a trapezoid or a
    # triangle; the move is planned 1e-6 below each limit.
    d, v, a = end - start, limits.max_velocity, limits.max_acceleration
    least = d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)
    assert least <= move.duration <= least * (1.0 + 1e-5)
    assert_within(run, limits)  # the stop, the move, the catch-up: within, never backward
    assert_rejoined(run, shifted_cam, q[-1000:], limits.turn)
    assert run.axes.shaft.mode == LOCKED


def test_the_master_turning_back_under_a_one_way_knife_is_followed_standing_on_its_cam():
    # The web runs at 1 m/s, brakes at 2 m/s^2 through 0 to -1 m/s, runs back, then speeds up
    # at 2 m/s^2 to 1 m/s again: velocity continuous, positions exact (trapezoids of it).
    cam, config, limits, nominal, unit = knife()
    run = Run(cam, config, limits, nominal, unit)
    dt = 1e-3
    speed = np.concatenate([np.full(3000, 1.0), 1.0 - 2.0 * dt * np.arange(1, 1001),
                            np.full(500, -1.0), -1.0 + 2.0 * dt * np.arange(1, 1001),
                            np.full(9000, 1.0)]) * nominal
    q = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * dt)])
    run.feed(q[:3500])  # braking, still forward
    assert run.phases[-1] == ENGAGED
    run.feed(q[3500:4000])  # through zero into reverse: the line shaft stands on the cam
    assert run.axes.shaft.mode == FILTERED and run.axes.virtual.omega == 0.0
    held = run.positions[-1]
    run.feed(q[4000:5000])  # back, then slowing down
    assert set(run.phases) == {ENGAGED} and set(run.positions[-1000:]) == {held}
    run.feed(q[5000:])
    assert run.axes.shaft.mode == 'locked'
    assert_within(run, limits)
    assert_rejoined(run, cam, q[-1000:], limits.turn)


def test_a_cam_over_the_velocity_limit_at_the_master_speed_runs_slower_within_it():
    # At 1 m/s of web the knife's cam needs 12.14 rad/s, over its 10: it moves onto its cam,
    # then the line shaft lags the master (filtered) so the knife keeps its limits.
    cam, config, limits, nominal, unit = knife(**{'slave.max_velocity': math.degrees(10.0)})
    run = Run(cam, config, limits, nominal, unit, present=0.0)
    run.feed(nominal * 1e-3 * np.arange(1, 3000))
    assert run.follower.phase == ENGAGED and run.axes.shaft.mode == FILTERED
    assert run.axes.shaft.lag > 0.0
    assert_within(run, limits)
    velocity, _ = run.differences()
    assert np.abs(velocity[-500:]).max() >= 0.9 * limits.max_velocity  # as fast as it may


def test_without_limits_a_move_onto_the_cam_is_no_faster_or_harder_than_the_cam_at_cam_speed():
    cam, config, _, nominal, unit = knife()
    run = Run(cam, config, SlaveLimits(turn=TWO_PI), nominal, unit, present=0.0)
    run.feed(nominal * 1e-3 * np.arange(1, 1500))
    assert any('moves onto its cam' in event for event in run.follower.events)
    q = np.linspace(0.0, TWO_PI * cam.mapping.master_scaling, 400_001)
    d = cam.derivatives(q)  # the cam's own peaks at cam_speed, from a dense scan
    fastest, hardest = np.abs(d.dy).max() * nominal, np.abs(d.d2y).max() * nominal ** 2
    phases = np.array(run.phases)
    assert phases[0] == ENGAGING and phases[-1] == ENGAGED
    velocity, acceleration = run.differences()
    moving = phases[1:] == ENGAGING  # the intervals that end during the move
    assert moving.sum() > 10
    assert np.abs(velocity[moving]).max() <= fastest * (1.0 + 1e-6)
    assert np.abs(acceleration[moving[1:]]).max() <= hardest * (1.0 + 1e-6)


def test_a_wrapping_jaw_across_a_dropout_keeps_its_limits_on_re_engaging():
    # The jaw of config/default.yaml on a shaft read by an encoder that wraps at 2 pi: 252 deg
    # turn unseen across 0. Before, the wrapped step read 108 deg backwards (-11.4 rad/s).
    cam, config, limits, nominal, unit = axis(DEFAULT, **{'slave.max_velocity': 500.0,  # cm/s
                                                          'slave.max_acceleration': 40_000.0})
    speed = nominal
    run = Run(cam, config, limits, nominal, unit)
    t = np.arange(1, 1500) * 1e-3
    run.feed(np.mod(1.0 + speed * t, TWO_PI))
    silence = math.radians(252.0) / speed
    run.silence(silence)
    q = 1.0 + speed * (t[-1] + silence + t)
    run.feed(np.mod(q, TWO_PI))
    assert run.tracker.jumps == 0
    assert_within(run, limits)
    assert_rejoined(run, cam, q[-300:], 0.0)


def test_a_stop_decelerates_at_the_limit_and_rests_where_the_kinematics_say():
    stop = Stop(0, 1.0, 3.0, 6.0)
    assert stop.duration == 0.5 and stop.rest == pytest.approx(1.75)
    t = np.linspace(0.0, 1.0, 11)
    position, velocity, acceleration = stop.at(t)
    np.testing.assert_allclose(position, np.where(t < 0.5, 1 + 3 * t - 3 * t * t, 1.75))
    np.testing.assert_allclose(velocity, np.maximum(3 - 6 * t, 0.0), atol=1e-15)
    np.testing.assert_array_equal(acceleration, np.where(t < 0.5, -6.0, 0.0))
    assert tuple(map(float, Stop(0, 2.0, -1.0, 0.0).at(0.3))) == (2.0, 0.0, 0.0)


@pytest.mark.parametrize('limit_deg_s, ok', [(680.0, False), (710.0, True)])
def test_the_report_verdict_checks_the_cam_at_cam_speed_against_the_limits(limit_deg_s, ok):
    # The knife peaks at 12.14 rad/s (695.6 deg/s) at cam_speed (the config file's comment).
    values = read_parameters_file(KNIFE)
    values.update({'slave.max_velocity': limit_deg_s, 'slave.direction': 'positive'})
    design = build_design(parse_parameters(values))
    assert design.ok is ok
    said = [note for note in design.warnings() if 'slave.max_velocity' in note]
    assert bool(said) is not ok
    if said:
        assert 'deg/s' in said[0] and 'rad/s' in said[0]
