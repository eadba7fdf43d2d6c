"""Cam switch tracks: edges at the expected master angle with lead time, both ways, standstill."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core.ecam.switches import switch_table, SwitchTable, SwitchTracks

DEG = math.pi / 180
#: glue: on 40-100 deg, lead 20 ms; mark: through 0 (350-10 deg); pulse: one degree wide.
TABLE = SwitchTable(('glue', 'mark', 'pulse'), np.radians([40.0, 350.0, 200.0]),
                    np.radians([100.0, 10.0, 201.0]), np.array([0.02, 0.0, 0.005]), 0.1 * DEG)


def reference_on(track, angle_deg):
    """Whether a track is on at a cam angle, written out here."""
    on, off = math.degrees(TABLE.on[track]), math.degrees(TABLE.off[track])
    angle = angle_deg % 360.0
    return on <= angle < off if on < off else angle >= on or angle < off


def edges_seen(turns, speeds):
    """Feed cam turns (rad); return [(sample, words)] of every change."""
    tracks = SwitchTracks(TABLE)
    return [(k, tracks.update(t, w)) for k, (t, w) in enumerate(zip(turns, speeds))]


@pytest.mark.parametrize('rpm', [60.0, 300.0, 600.0])
@pytest.mark.parametrize('direction', [1.0, -1.0])
def test_every_edge_comes_at_its_angle_less_the_lead_at_that_speed(rpm, direction):
    speed = direction * rpm * 2 * math.pi / 60  # cam rad/s (master.scaling 1)
    dt = 0.004
    t = np.arange(int(1.2 * 60 / rpm / dt) + 2) * dt  # 1.2 turns at 250 Hz
    turns = 0.3 + speed * t
    changes = edges_seen(turns, np.full(t.size, speed))
    lag = 0.0 if direction > 0 else 0.1  # the play: h behind in the negative direction
    state = changes[0][1][-1]  # the first sample says its state
    for k, words in changes[1:]:
        state = words[-1] if words else state
        for track in range(3):  # where the track reads: z + lead * speed, in deg
            read = math.degrees(turns[k] + speed * TABLE.lead_time[track]) + lag
            assert bool(state >> track & 1) == reference_on(track, read), (k, track)
    # The one-degree pulse is seen on and off once per turn, even when between two samples.
    pulses = sum(1 for _, words in changes for w in words if w & 4)
    assert pulses == 1


def test_without_tracks_the_word_is_0_said_once():
    tracks = SwitchTracks(SwitchTable((), np.array([]), np.array([]), np.array([]), 0.1 * DEG))
    said = [tracks.update(turn, 10.0) for turn in (0.0, 1.0, 7.0, -3.0)]
    assert said == [[0], [], [], []] and tracks.word == 0


# Edges in the travel: 7 places a turn (b off and d on share 35 deg), 350 deg not reached again
# forward (2.9 .. 828 deg: 20), reached from 828 down to -22.9 deg (21).
@pytest.mark.parametrize('start, end, places', [(0.05, 2.3 * 2 * math.pi, 20),
                                                (2.3 * 2 * math.pi, -0.4, 21)],
                         ids=['forward', 'backward'])
def test_one_long_step_gives_the_words_of_many_short_ones(start, end, places):
    """Edges crossed between two samples (over turns, two at once) come in order, each once."""
    table = SwitchTable(('a', 'b', 'c', 'd'), np.radians([10.0, 30.0, 350.0, 35.0]),
                        np.radians([50.0, 35.0, 20.0, 60.0]), np.zeros(4), 0.0)
    one_step = SwitchTracks(table)
    one_step.update(start, 0.0)
    fine = SwitchTracks(table)
    fine.update(start, 0.0)
    steps = np.linspace(start, end, 20_001)[1:]  # 0.04 deg apart: one edge a step at most,
    expected = [w for turn in steps for w in fine.update(turn, 0.0)]  # b off with d on at 35
    assert one_step.update(end, 0.0) == expected
    assert len(expected) == places


@pytest.mark.parametrize('lead', [[0.01, 0.0, 0.25], []], ids=['leads', 'no leads'])
def test_the_switches_parameters_become_a_table_in_si(lead):
    table = switch_table({'switches.names': ['glue', 'mark', 'pulse'],
                          'switches.on_deg': [40.0, 350.0, 200.0],
                          'switches.off_deg': [90.0, 10.0, 200.5],
                          'switches.lead_time': lead, 'switches.hysteresis_deg': 0.5})
    assert table.names == ('glue', 'mark', 'pulse')
    np.testing.assert_allclose(table.on, np.radians([40.0, 350.0, 200.0]), rtol=1e-15)
    np.testing.assert_allclose(table.off, np.radians([90.0, 10.0, 200.5]), rtol=1e-15)
    np.testing.assert_array_equal(table.lead_time, lead or [0.0, 0.0, 0.0])
    assert table.hysteresis == pytest.approx(0.5 * math.pi / 180, rel=1e-15)


@pytest.mark.parametrize('start, end', [(0.05, 2.3 * 2 * math.pi), (2.3 * 2 * math.pi, -0.4)],
                         ids=['forward', 'backward'])
def test_one_long_step_with_leads_gives_the_words_of_many_short_ones(start, end):
    """With lead times each track reads its own phase (z + lead x speed): edges of tracks at
    different phases crossed in one step still come in the order of many short steps."""
    table = SwitchTable(('a', 'b', 'c', 'd'), np.radians([10.0, 30.0, 350.0, 35.0]),
                        np.radians([50.0, 35.0, 20.0, 60.0]), np.array([0.0, 0.03, 0.01, 0.02]),
                        0.0)
    speed = 10.0  # rad/s: leads of 0 to 17 deg
    one_step, fine = SwitchTracks(table), SwitchTracks(table)
    one_step.update(start, speed)
    fine.update(start, speed)
    steps = np.linspace(start, end, 20_001)[1:]  # 0.04 deg apart: one edge a step at most
    expected = [w for turn in steps for w in fine.update(turn, speed)]
    assert one_step.update(end, speed) == expected
    assert len(expected) > 16
