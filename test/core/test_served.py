"""What a node serves and says of a machine (core.machine.served) against independent references.

The figures of a pair's line (a gap in the machine's unit and in m, a zones margin or overlap,
where) against dense scans of config/machine.yaml's axes (the pusher's cycloids written out),
the one-line collisions a node refuses to start with, an update refused for a mix of old and new
cams with the gap of that mix, and a single cam served as a machine of one axis.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.parameters import PARAMETERS
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design_from_config import build_design
from cam_ros.core.machine import check_interference, InterferencePair
from cam_ros.core.machine.interference import PairCheck
from cam_ros.core.machine.served import (collisions, machine_from_values, pair_line,
                                         served_specs, update_refusal)

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
VALUES = read_parameters_file(CONFIG_DIR / 'machine.yaml')
TWO_PI = 2.0 * math.pi
#: A dense scan of the machine cycle: 2^21 angles, 1.7e-4 deg apart.
THETA = np.linspace(0.0, TWO_PI, 2 ** 21, endpoint=False)
STEP_DEG = 360.0 / THETA.size


def changed(**changes) -> dict:
    """Return machine.yaml's values with some replaced (keys with '__' for '.')."""
    values = dict(VALUES)
    values.update({key.replace('__', '.'): value for key, value in changes.items()})
    return values


def pusher(theta: np.ndarray, stroke: float) -> np.ndarray:
    """Return the pusher's position (m): cycloids out over 0-140 deg and back over 200-320."""
    def cycloid(u):
        u = np.clip(u, 0.0, 1.0)
        return u - np.sin(TWO_PI * u) / TWO_PI
    d = np.degrees(theta)
    return stroke * (cycloid(d / 140.0) - cycloid((d - 200.0) / 120.0))


def jaw(values: dict) -> np.ndarray:
    """Return the jaw's positions (m) on THETA, as the machine of values commands it."""
    machine = machine_from_values(values)
    return machine.positions(THETA)[:, machine.config.names.index('jaw')]


def figures(line: str) -> list[float]:
    """Return the numbers of a pair's line, in order."""
    return [float(text) for text in re.findall(r'-?\d+(?:\.\d+)?', line.split(':', 1)[1])]


def below(printed: float, true: float, digits: int = 6) -> bool:
    """Say whether printed is true rounded down to 6 significant digits (at most a unit less)."""
    unit = 10.0 ** (math.floor(math.log10(abs(true))) - digits + 1)
    return true - unit * (1 + 1e-9) <= printed <= true + 1e-12 * abs(true)


def test_the_clearance_line_says_the_smallest_gap_in_mm_and_m_where_it_is():
    machine = machine_from_values(VALUES)
    check = check_interference(machine)[0]
    gap = 0.31 - pusher(THETA, 0.2) - jaw(VALUES)  # 310 mm - feeder - jaw
    smallest, where = gap.min(), math.degrees(THETA[gap.argmin()])
    line = pair_line(check, 'mm')
    assert line.startswith('clearance feeder-jaw: smallest gap ') and line.endswith(': ok')
    mm, metre, at, limit = figures(line)
    assert below(mm, smallest * 1e3) and below(metre, smallest)  # the machine's unit and SI
    assert smallest * 1e3 == pytest.approx(32.49, abs=0.005)     # machine.yaml's 32.48 mm
    assert at == pytest.approx(where, abs=0.01) and limit == 15.0


def zone_margin(in_a: np.ndarray, in_b: np.ndarray) -> tuple[float, float]:
    """Return the smallest margin (deg) from one leaving its zone to the other entering (both
    orders, cyclic) and where it leaves (deg), or minus the longest overlap and where it starts,
    from the scan written out."""
    both = in_a & in_b
    if both.any():
        starts = np.flatnonzero(both & ~np.roll(both, 1))
        runs = [np.argmin(np.roll(both, -start)) for start in starts]  # first False after
        longest = int(np.argmax(runs))
        return -runs[longest] * STEP_DEG, starts[longest] * STEP_DEG
    best = (math.inf, math.nan)
    for one, other in ((in_a, in_b), (in_b, in_a)):
        leaves = np.flatnonzero(~one & np.roll(one, 1))
        enters = np.flatnonzero(other & ~np.roll(other, 1))
        after = enters[np.searchsorted(enters, leaves) % enters.size]
        gaps = (after - leaves) % one.size
        best = min(best, (gaps.min() * STEP_DEG, leaves[gaps.argmin()] * STEP_DEG))
    return best


def knife_in_zone(values: dict, level_deg: float) -> np.ndarray:
    """Return where the knife (a turn per cycle, taken modulo a turn) is above level_deg."""
    machine = machine_from_values(values)
    knife = machine.positions(THETA)[:, machine.config.names.index('knife')]
    return np.degrees(np.mod(knife, TWO_PI)) > level_deg


@pytest.mark.parametrize('level_deg, kind', [(320.0, 'margin'), (100.0, 'overlap')])
def test_the_zones_line_says_the_margin_or_the_overlap_of_a_dense_scan(level_deg, kind):
    values = changed(interference__zone_b=[0.0, level_deg])
    check = check_interference(machine_from_values(values))[1]
    margin, where = zone_margin(jaw(values) > 0.06, knife_in_zone(values, level_deg))
    line = pair_line(check, 'mm')
    numbers = figures(line)
    if kind == 'margin':  # machine.yaml's: 70.5 deg from the knife leaving to the jaw entering
        assert line.startswith('zones jaw-knife: smallest margin ') and line.endswith(': ok')
        printed, at, limit = numbers
        assert margin == pytest.approx(70.54, abs=0.005)
        assert below(printed, math.degrees(check.value))
    else:
        assert line.startswith('zones jaw-knife: both in the zone for ')
        assert line.endswith(': COLLIDES')
        overlap, at, printed, limit = numbers
        assert margin < 0 and overlap == pytest.approx(-margin, abs=3 * STEP_DEG)
        assert below(-overlap, math.degrees(check.value))  # the overlap rounded up
        assert below(printed, math.degrees(check.value))
    assert printed == pytest.approx(margin, abs=3 * STEP_DEG)
    assert at == pytest.approx(where, abs=0.01) and limit == 20.0


@pytest.mark.parametrize('zone_a, line', [
    (-10.0, 'zones jaw-knife: an axis never leaves its zone, the other enters it at '),
    (100.0, 'zones jaw-knife: an axis never enters its zone: limit >= 20 deg: ok'),
])
def test_a_zone_never_left_or_never_entered_is_said_so(zone_a, line):
    values = changed(interference__zone_a=[0.0, zone_a])
    check = check_interference(machine_from_values(values))[1]
    said = pair_line(check, 'mm')
    assert said.startswith(line)
    if zone_a < 0:  # where the knife enters above 320 deg: the scan's first angle in it
        enters = knife_in_zone(values, 320.0)
        first = np.flatnonzero(enters & ~np.roll(enters, 1))
        assert len(first) == 1 and said.endswith(': limit >= 20 deg: COLLIDES')
        assert figures(said)[0] == pytest.approx(first[0] * STEP_DEG, abs=0.01)


def test_a_margin_of_exactly_zero_is_a_margin_not_an_overlap():
    pair = InterferencePair('jaw', 'knife', 'zones', 0.0, 0.0, 0.0, 0.0, 0.06, 1.0, 0.1)
    line = pair_line(PairCheck(pair, 0.0, 1.0, False), 'mm')
    assert line.startswith('zones jaw-knife: smallest margin 0.0 deg of machine angle')


def test_collisions_says_every_colliding_pair_and_only_those():
    assert collisions(machine_from_values(VALUES)) == ''
    values = changed(interference__min_clearance=[40.0, 0.0])
    machine = machine_from_values(values)
    said = collisions(machine)
    assert said == pair_line(check_interference(machine)[0], 'mm')
    assert said.endswith('limit >= 40 mm: COLLIDES') and ';' not in said


def longer_pusher_shorter_jaw() -> dict:
    """Return machine.yaml with a 230 mm pusher and a 50 mm jaw: apart, but the new pusher
    meets the jaw as it is now (310 - 230 - 80 mm at the closest)."""
    return changed(feeder__motion__start_position=[0.0, 230.0, 230.0, 0.0],
                   feeder__motion__end_position=[230.0, 230.0, 0.0, 0.0],
                   jaw__motion__start_position=[0.0, 0.0, 50.0, 50.0, 0.0],
                   jaw__motion__end_position=[0.0, 50.0, 50.0, 0.0, 0.0])


def test_an_update_is_refused_for_the_mix_of_new_and_old_cams_that_collides():
    old, values = machine_from_values(VALUES), longer_pusher_shorter_jaw()
    new = machine_from_values(values)
    assert collisions(new) == ''  # the new machine alone is clear
    refusal = update_refusal(old, new)
    assert refusal.startswith('clearance feeder-jaw: smallest gap ')
    assert refusal.endswith(': COLLIDES (feeder new, jaw as now)')
    gap = 0.31 - pusher(THETA, 0.23) - jaw(VALUES)
    mm, metre, at, _ = figures(refusal.split(' (feeder')[0])
    assert below(mm, gap.min() * 1e3) and below(metre, gap.min())
    assert 0.0 < mm < 15.0
    assert at == pytest.approx(math.degrees(THETA[gap.argmin()]), abs=0.01)


def test_an_update_that_changes_nothing_or_stays_clear_is_taken():
    old = machine_from_values(VALUES)
    assert update_refusal(old, machine_from_values(dict(VALUES))) == ''
    shorter = changed(feeder__motion__start_position=[0.0, 190.0, 190.0, 0.0],
                      feeder__motion__end_position=[190.0, 190.0, 0.0, 0.0])
    assert update_refusal(old, machine_from_values(shorter)) == ''
    # Undone: the update back is the old pusher with the jaw as it runs: clear.
    assert update_refusal(machine_from_values(shorter), old) == ''


def test_a_single_cam_is_served_as_a_machine_of_one_axis_without_pairs():
    values = read_parameters_file(CONFIG_DIR / 'default.yaml')
    machine = machine_from_values(values)
    config = parse_parameters(values)
    assert machine.config.names == ('follower',) and machine.config.interference == ()
    assert machine.config.length_unit == config.length_unit
    assert [axis.name for axis in machine.axes] == ['follower']
    design = build_design(config)
    theta = np.linspace(0.0, TWO_PI, 3601)
    np.testing.assert_array_equal(machine.positions(theta)[:, 0],
                                  design.electronic_cam.derivatives(theta).y)
    assert repr(machine.config.axes) == repr((config,)) and collisions(machine) == ''
    assert list(served_specs(values)) == [spec.name for spec in PARAMETERS]
