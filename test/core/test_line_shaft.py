"""The line shaft's virtual master on a limited machine: locked while the master is admissible,
filtered (never past a limit) where it is not, synchronized stops, resynchronization."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core.ecam.line_shaft import (AT_REST, FILTERED, LineShaft, LOCKED, LOST,
                                          STOPPING)
from cam_ros.core.ecam.master_tracker import MasterState

from line_shaft_support import DT, line, NOMINAL, peaks, run, within

MACHINE = line()
CYCLE = 2 * math.pi


def ramp(rate: float, speed: float, after: float = 0.0, back: float = 0.0):
    """Return a master acceleration: rate up to speed, at `after` s rate down to back."""
    up, down = speed / rate, (speed - back) / rate

    def acceleration(t: float) -> float:
        if t < up:
            return rate
        if after and after <= t < after + down:
            return -rate
        return 0.0
    return acceleration


def steady(t: float) -> float:
    """Cam speed from the first sample on."""
    return NOMINAL / DT if t == 0.0 else 0.0


def test_locked_at_cam_speed_the_virtual_master_is_the_master_exactly():
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, tracks = run(shaft, steady, 2.0)
    assert set(modes) == {LOCKED} and shaft.filtered == 0
    assert [state.theta for state in states] == tracks
    assert peaks(MACHINE, states)[1][1] > 20.0  # the knife uses most of its 30 rad/s^2


@pytest.mark.parametrize('name, acceleration', [
    ('300 rad/s^2 to cam speed and to rest', ramp(300.0, NOMINAL, after=2.0)),
    ('overspeed 1.5 x', ramp(300.0, 1.5 * NOMINAL, after=2.0, back=NOMINAL)),
    ('a master turning back', ramp(300.0, NOMINAL, after=1.0, back=-NOMINAL)),
])
def test_a_master_beyond_the_limits_is_filtered_within_every_limit(name, acceleration):
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, _ = run(shaft, acceleration, 3.0)
    assert FILTERED in modes
    within(MACHINE, states)
    theta = np.array([state.theta for state in states])
    assert np.diff(theta).min() >= 0.0  # the knife is one-way: theta_v never turns back


def test_after_an_overspeed_the_virtual_master_locks_again_on_the_masters_phase():
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, tracks = run(shaft, ramp(300.0, 1.5 * NOMINAL, after=2.5, back=NOMINAL), 6.0)
    assert modes[-1] == LOCKED and modes.count(FILTERED) > 100
    lagged = (tracks[-1] - states[-1].theta) / CYCLE  # whole cycles behind, never unwound
    assert lagged == pytest.approx(round(lagged), abs=1e-9) and round(lagged) >= 1
    within(MACHINE, states)


def test_a_halt_is_a_synchronized_stop_to_rest_within_every_limit():
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, _ = run(shaft, steady, 2.0, events={250: lambda s: s.halt(LOST)})
    assert modes[249] == LOCKED and STOPPING in modes and modes[-1] == AT_REST
    within(MACHINE, states)
    assert states[-1].omega == 0.0 and shaft.why == LOST


def test_silence_is_coasted_at_the_masters_speed_then_a_loss_stops_on_the_clock():
    shaft = LineShaft(MACHINE.path, one_way=True)
    states, modes, _ = run(shaft, steady, 2.0, events={300: lambda s: s.halt(LOST)},
                           silent=range(250, 500))
    coasted = [state.theta for state in states[249:300]]
    np.testing.assert_allclose(np.diff(coasted), NOMINAL * DT, rtol=1e-12)
    assert modes[299] == LOCKED and modes[499] == AT_REST
    within(MACHINE, states[:500])


@pytest.mark.parametrize('one_way', [True, False])
def test_a_master_back_after_a_loss_is_caught_up_modulo_a_cycle(one_way):
    """The master ran on unseen for 1.3 s; theta_v stopped, then catches up with the master's
    phase: forward for a one-way machine, the nearer way otherwise; no turn unwound."""
    shaft = LineShaft(MACHINE.path, one_way=one_way)
    shifts: list[float] = []
    events = {250: lambda s: s.halt(LOST), 575: lambda s: s.follow(),
              576: lambda s: shifts.append(s.shift)}
    states, modes, tracks = run(shaft, steady, 4.0, events, silent=range(250, 575))
    rest = states[574].theta
    assert modes[574] == AT_REST and modes[-1] == LOCKED
    within(MACHINE, states)
    behind = (tracks[-1] - states[-1].theta) / CYCLE
    assert behind == pytest.approx(round(behind), abs=1e-9)
    moved = np.diff([state.theta for state in states[574:]])
    if one_way:
        assert moved.min() >= 0.0
    gap = tracks[575] + shifts[0] - rest  # the master's phase theta_v went after
    assert 0.0 <= gap < CYCLE if one_way else abs(gap) <= CYCLE / 2


def test_a_new_master_origin_is_taken_modulo_a_cycle_from_where_the_axes_are():
    shaft = LineShaft(MACHINE.path, one_way=True)
    states = []
    for k in range(600):  # a restart from 0 at sample 300 (a re-homing)
        track = NOMINAL * DT * (k if k < 300 else k - 300 + 0.37 / (NOMINAL * DT))
        if k == 300:
            shaft.origin()
        states.append(shaft.master(MasterState(round(k * DT * 1e9), track, NOMINAL, 0.0, 0.0,
                                               track)))
    theta = np.array([state.theta for state in states])
    assert np.diff(theta).min() >= 0.0 and shaft.mode == LOCKED
    assert (theta[-1] - track) / CYCLE == pytest.approx(round((theta[-1] - track) / CYCLE))
    within(MACHINE, states)


def test_the_first_sample_starts_the_virtual_master_on_the_master():
    shaft = LineShaft(MACHINE.path, one_way=False)
    assert shaft.tick(5) is None
    state = shaft.master(MasterState(10, 1.0, 2.0, 0.0, 0.0, 7.5))
    assert (state.theta, state.omega) == (7.5, 2.0) and shaft.mode == LOCKED
