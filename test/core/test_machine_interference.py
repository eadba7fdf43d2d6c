"""Interference of a machine's axes, against dense scans refined by SciPy written here."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.machine import (build_machine, check_interference, load_machine,
                                  machine_report, parse_machine)
from cam_ros.core.machine.interference import zone_margin

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
MACHINE = read_parameters_file(CONFIG_DIR / 'machine.yaml')
TWO_PI = 2.0 * math.pi
SCAN = np.linspace(0.0, TWO_PI, 2_000_000, endpoint=False)
STEP = TWO_PI / SCAN.size
MM, DEG = 1e-3, math.pi / 180.0


def machine_with(**edits):
    return build_machine(parse_machine({**MACHINE, **{key.replace('__', '.'): value
                                                      for key, value in edits.items()}}))


def file_y(machine, name):
    """Return an axis's y(theta) in its file unit (mm, or deg modulo a turn for the knife)."""
    index = machine.config.names.index(name)

    def y(theta):
        value = machine.positions(np.atleast_1d(np.asarray(theta, dtype=float)))[:, index]
        return np.mod(np.degrees(value), 360.0) if name == 'knife' else value / MM
    return y


def smallest_gap(gap):
    """Return (value, angle) of a gap's minimum: dense scan, then bounded minimisation."""
    values = gap(SCAN)
    index = int(np.argmin(values))
    found = minimize_scalar(lambda t: float(gap(t)[0]), method='bounded',
                            bounds=(SCAN[index] - STEP, SCAN[index] + STEP),
                            options={'xatol': 1e-13})
    return min(float(found.fun), float(values[index])), float(found.x) % TWO_PI


def crossings(level):
    """Return the refined angles where level (sampled on SCAN) changes sign, and the sign after."""
    def crossing(func):
        values = func(SCAN)
        change = np.flatnonzero(np.sign(values) != np.sign(np.roll(values, -1)))
        roots = [brentq(lambda t: float(func(t)[0]), SCAN[i], SCAN[i] + STEP, xtol=1e-14)
                 for i in change]
        return np.array(roots) % TWO_PI, np.roll(values, -1)[change] > 0.0
    return crossing(level)


def margin(zone_a, zone_b):
    """Return the smallest machine angle from an exit of one zone to the next entry of the other.

    Each zone function is positive inside; exits and entries come from the refined crossings.
    """
    events = []
    for axis, zone in enumerate((zone_a, zone_b)):
        roots, entering = crossings(zone)
        events += [(root, axis, bool(enter)) for root, enter in zip(roots, entering)]
    smallest = math.inf
    for root, axis, enter in events:
        if enter:
            continue
        ahead = [((other - root) % TWO_PI, other) for other, who, entry in events
                 if who != axis and entry]
        smallest = min(smallest, min(ahead)[0])
    return smallest


def test_the_shipped_machine_clears_with_the_stated_margins():
    machine = load_machine(CONFIG_DIR / 'machine.yaml')
    clearance, zones = check_interference(machine)
    feeder, jaw, knife = (file_y(machine, name) for name in ('feeder', 'jaw', 'knife'))
    value, at = smallest_gap(lambda t: 310.0 - feeder(t) - jaw(t))
    assert clearance.value / MM == pytest.approx(value, abs=1e-9)
    assert clearance.value / MM <= value + 1e-12  # never the lenient side
    assert clearance.at == pytest.approx(at, abs=1e-6)
    assert clearance.ok and clearance.value / MM > 32.4  # config/machine.yaml: 32.48 mm
    expected = margin(lambda t: jaw(t) - 60.0, lambda t: knife(t) - 320.0)
    assert zones.value == pytest.approx(expected, abs=1e-9)
    assert zones.ok and math.degrees(zones.value) > 70.5  # config/machine.yaml: 70.5 deg
    assert math.degrees(zones.at) == pytest.approx(124.9088, abs=1e-3)  # the knife leaves
    report = machine_report(machine)
    assert report.ok and len(report.axes) == 3 and report.interference == (clearance, zones)


def test_a_collision_is_found_and_fails_the_machine():
    machine = machine_with(interference__offset=[270.0, 0.0],
                           jaw__master__scaling=0.5)  # the jaw closes twice per cycle
    clearance = check_interference(machine)[0]
    feeder, jaw = file_y(machine, 'feeder'), file_y(machine, 'jaw')
    value, at = smallest_gap(lambda t: 270.0 - feeder(t) - jaw(t))
    assert value < 15.0 and not clearance.ok and not machine_report(machine).ok
    assert clearance.value / MM == pytest.approx(value, abs=1e-9)
    assert clearance.at == pytest.approx(at, abs=1e-6)


def test_a_rotary_axis_counts_modulo_a_turn_and_its_wrap_as_a_one_sided_limit():
    # gap = 400 mm - 1 mm per knife deg (modulo a turn) - pusher: lowest just before the wrap.
    machine = machine_with(interference__axis_a=['knife', 'jaw'],
                           interference__axis_b=['feeder', 'knife'],
                           interference__offset=[400.0, 0.0],
                           interference__gain_a=[-1.0, 0.0])
    clearance = check_interference(machine)[0]
    knife, feeder = file_y(machine, 'knife'), file_y(machine, 'feeder')
    turns = machine.positions(SCAN)[:, 1] / TWO_PI  # the knife's unwrapped turns
    index = int(np.flatnonzero(np.floor(turns) != np.floor(np.roll(turns, -1)))[0])
    wrap = brentq(lambda t: float(machine.positions(np.array([t]))[0, 1] / TWO_PI
                                  - math.floor(turns[index + 1])),
                  SCAN[index], SCAN[index + 1], xtol=1e-15)
    limit = 400.0 - 360.0 - float(feeder(wrap)[0])  # the knife's limit 360 deg from below
    scanned = float(np.min(400.0 - knife(SCAN) - feeder(SCAN)))
    assert clearance.value / MM == pytest.approx(limit, abs=1e-8)
    assert clearance.value / MM <= scanned  # the infimum, below every sample
    assert clearance.at == pytest.approx(wrap, abs=1e-9)


def test_overlapping_zones_report_minus_the_overlap():
    machine = machine_with(knife__master__offset_deg=240.0)  # the cut while the jaw seals
    zones = check_interference(machine)[1]
    jaw, knife = file_y(machine, 'jaw'), file_y(machine, 'knife')
    both = (jaw(SCAN) > 60.0) & (knife(SCAN) > 320.0)
    roots, _ = crossings(lambda t: knife(t) - 320.0)  # one knife arc, inside the jaw's
    assert not zones.ok
    assert zones.value == pytest.approx(-np.count_nonzero(both) * STEP, abs=2 * STEP)
    assert zones.value == pytest.approx(-((roots[1] - roots[0]) % TWO_PI), abs=1e-9)
    assert zones.at == pytest.approx(roots[0], abs=1e-9)


@pytest.mark.parametrize('zone_a, value, ok', [(100.0, math.inf, True),
                                               (-1.0, -math.inf, False)],
                         ids=['jaw never in its zone', 'jaw always in its zone'])
def test_zones_never_entered_or_never_left(zone_a, value, ok):
    zones = check_interference(machine_with(interference__zone_a=[0.0, zone_a]))[1]
    assert zones.value == value and zones.ok is ok


def longest_common_run(arcs_a, arcs_b):
    """Return (length, start) of the longest stretch inside an arc of both, on SCAN."""
    def inside(arcs):
        mask = np.zeros(SCAN.size, dtype=bool)
        for start, length in zip(*arcs):
            mask |= np.mod(SCAN - start, TWO_PI) < length
        return mask
    both = inside(arcs_a) & inside(arcs_b)
    first_out = int(np.argmin(both))  # unroll the turn from an angle outside the overlap
    rolled = np.roll(both, -first_out).astype(int)
    edges = np.diff(np.concatenate(([0], rolled, [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    longest = int(np.argmax(ends - starts))
    return (ends - starts)[longest] * STEP, SCAN[(starts[longest] + first_out) % SCAN.size]


@pytest.mark.parametrize('arcs_a, arcs_b', [
    (((10.0, 200.0), (50.0, 60.0)), ((40.0, 230.0), (30.0, 100.0))),  # the longer one second
    (((350.0,), (40.0,)), ((0.0, 300.0), (20.0, 10.0))),  # across the cycle start
    (((100.0, 5.0), (50.0, 10.0)), ((80.0,), (40.0,))),  # b entered before a
], ids=['two overlaps', 'across 0', 'b first'])
def test_the_zone_margin_of_overlapping_arcs_is_minus_the_longest_overlap(arcs_a, arcs_b):
    arcs_a, arcs_b = (tuple(np.radians(np.array(part)) for part in arcs)
                      for arcs in (arcs_a, arcs_b))
    length, start = longest_common_run(arcs_a, arcs_b)
    margin, at = zone_margin(arcs_a, arcs_b)
    assert margin == pytest.approx(-length, abs=2 * STEP)
    assert at == pytest.approx(start, abs=2 * STEP)


def test_an_axis_always_in_its_zone_collides_where_the_other_enters():
    always, once = (np.zeros(1), np.full(1, TWO_PI)), (np.radians([40.0]), np.radians([30.0]))
    assert zone_margin(always, once) == (-math.inf, pytest.approx(math.radians(40.0)))
    assert zone_margin(once, always) == (-math.inf, pytest.approx(math.radians(40.0)))


def test_each_check_names_its_pair_in_the_files_order():
    machine = load_machine(CONFIG_DIR / 'machine.yaml')
    checks = check_interference(machine)
    assert [check.pair for check in checks] == list(machine.config.interference)
    assert [check.pair.type for check in checks] == ['clearance', 'zones']


@pytest.mark.parametrize('level, value', [(0.0, -math.inf), (80.0, math.inf)],
                         ids=['touched from above', 'touched from below'])
def test_a_zone_level_touched_but_never_crossed(level, value):
    """The jaw rises and returns without a dwell: 0 mm and 80 mm only at (or a rounding from)
    0 and 180 deg, samples of the check's grid. Touching its level from above, the jaw is in its
    zone the whole cycle but at a point (a full turn: it collides where the knife enters, found
    by the dense scan); from below never in it."""
    machine = machine_with(jaw__motion__laws=['cycloidal', 'cycloidal'],
                           jaw__motion__start_deg=[0.0, 180.0],
                           jaw__motion__end_deg=[180.0, 360.0],
                           jaw__motion__start_position=[0.0, 80.0],
                           jaw__motion__end_position=[80.0, 0.0],
                           interference__zone_a=[0.0, level])
    jaw, knife = file_y(machine, 'jaw'), file_y(machine, 'knife')
    side = -np.sign(value) * (jaw(SCAN) - level)  # >= 0: the side the jaw keeps to
    assert side.min() == 0.0 and np.count_nonzero(side == 0.0) < 10  # touched, never crossed
    zones = check_interference(machine)[1]
    assert zones.value == value and zones.ok is (value > 0)
    if value < 0:
        roots, entering = crossings(lambda t: knife(t) - 320.0)
        assert zones.at == pytest.approx(roots[entering][0], abs=1e-9)
