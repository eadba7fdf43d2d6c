"""`cam_ros report|sample MACHINE` and --axis: figures against machine_support's references."""
from __future__ import annotations

import csv
import io
import json
import math
import re
from fractions import Fraction

import numpy as np
import pytest
from cli_support import assert_one_error_line, DEFAULT_CONFIG, run_cli
from machine_support import (CAM_SPEED, coupled, crossings, DEG, edited_machine, jaw_s,
                             knife_s, MACHINE, MM, NAMES, reference_positions, SCAN,
                             smallest, TWO_PI)

Q = np.linspace(0.0, TWO_PI, SCAN)
GAP_LINE = re.compile(r'clearance feeder-jaw: smallest gap (\S+) mm \((\S+) m\) at (\S+) deg, '
                      r'limit >= 15 mm: (ok|COLLIDES)$')
MARGIN_LINE = re.compile(r'zones jaw-knife: smallest margin (\S+) deg of machine angle, from one '
                         r'leaving the zone at (\S+) deg to the other entering: limit >= 20 deg: '
                         r'(ok|COLLIDES)$')


def gap(q: np.ndarray) -> np.ndarray:
    """Return the pusher-jaw gap (m): 310 mm - feeder - jaw."""
    positions = reference_positions(q, KNIFE)
    return 0.31 - positions['feeder'] - positions['jaw']


KNIFE = knife_s()


def knife_zone(q: np.ndarray) -> np.ndarray:
    """Return a function > 0 exactly while the knife is in its zone (above 320 deg mod a turn)."""
    return np.sin(0.5 * (coupled(q, KNIFE, 100.0 * DEG, -20.0 * DEG, TWO_PI) - 320.0 * DEG)
                  ) * np.sin(0.5 * coupled(q, KNIFE, 100.0 * DEG, -20.0 * DEG, TWO_PI))


def zone_margin(jaw_offset: float = 0.0) -> tuple[float, float]:
    """Return the smallest margin (rad) between jaw leaving/knife entering and back, and where.

    Each axis's zone is between its entering and leaving crossings (refined by brentq).
    """
    def jaw_zone(q: np.ndarray) -> np.ndarray:
        return coupled(q, jaw_s, jaw_offset) - 0.06
    jaw_in, jaw_out = crossings(jaw_zone, Q)
    knife_in, knife_out = crossings(knife_zone, Q)
    options = [(float(np.mod(enter - leave, TWO_PI)), float(leave))
               for leaves, enters in ((jaw_out, knife_in), (knife_out, jaw_in))
               for leave in leaves for enter in enters]
    return min(options)


def floored(text: str, value: float, digits: int = 6) -> None:
    """Check a printed figure reads at or below value, within one unit of its 6th digit."""
    unit = Fraction(10) ** (math.floor(math.log10(abs(value))) - digits + 1)
    assert Fraction(text) <= Fraction(value) < Fraction(text) + unit, (text, value)


def test_report_prints_each_axis_under_its_name_and_each_pair_rounded_down(capsys):
    run = run_cli(capsys, 'report', MACHINE)
    assert run.code == 0 and run.err == ''
    lines = run.out.splitlines()
    for name in NAMES:
        heading = lines.index(f'Axis {name}')
        assert lines[heading + 1] == '=' * len(f'Axis {name}')
        assert lines[heading + 2] == f'Cam design report: {MACHINE}, axis {name}'
    assert run.out.count('Verdict: meets its limits') == 3
    smallest_gap, at = smallest(gap, Q)
    (gap_line,) = [line.strip() for line in lines if 'clearance feeder-jaw' in line]
    millimetres, metres, at_deg, state = GAP_LINE.fullmatch(gap_line).groups()
    floored(millimetres, smallest_gap / MM)
    floored(metres, smallest_gap)
    assert abs(float(at_deg) - math.degrees(at)) <= 0.005 and state == 'ok'
    margin, leaves = zone_margin()
    (margin_line,) = [line.strip() for line in lines if 'zones jaw-knife' in line]
    degrees, at_deg, state = MARGIN_LINE.fullmatch(margin_line).groups()
    floored(degrees, math.degrees(margin))
    assert abs(float(at_deg) - math.degrees(leaves)) <= 0.005 and state == 'ok'
    assert lines[-1] == 'Verdict: every axis meets its limits, no pair collides'


def test_report_json_has_the_exact_keys_and_refined_figures(capsys):
    run = run_cli(capsys, 'report', MACHINE, '--json')
    assert run.code == 0
    data = json.loads(run.out)
    assert list(data) == ['axes', 'interference', 'ok'] and data['ok'] is True
    single = json.loads(run_cli(capsys, 'report', DEFAULT_CONFIG, '--json').out)
    assert [axis['name'] for axis in data['axes']] == list(NAMES)
    for axis in data['axes']:
        assert set(axis) == {'name', *single}
        assert axis['ok'] is True and axis['follower'] == {'type': 'none'}
    clearance, zones = data['interference']
    assert list(clearance) == ['axis_a', 'axis_b', 'type', 'min_clearance', 'at_deg', 'ok']
    assert list(zones) == ['axis_a', 'axis_b', 'type', 'min_margin_deg', 'at_deg', 'ok']
    smallest_gap, at = smallest(gap, Q)
    assert clearance['min_clearance'] == pytest.approx(smallest_gap, abs=1e-15)
    assert clearance['at_deg'] == pytest.approx(math.degrees(at), abs=1e-5)
    margin, leaves = zone_margin()
    assert zones['min_margin_deg'] == pytest.approx(math.degrees(margin), abs=1e-9)
    assert zones['at_deg'] == pytest.approx(math.degrees(leaves), abs=1e-9)
    assert (clearance['ok'], zones['ok']) == (True, True)


def colliding(tmp_path, name='colliding', jaw_offset=-100.0, min_clearance=45.0):
    """Write the shipped machine with the jaw earlier and the gap's limit raised."""
    def edit(parameters):
        parameters['jaw']['master'] = {'offset_deg': jaw_offset}
        parameters['interference']['min_clearance'][0] = min_clearance
    return edited_machine(tmp_path, name, edit)


def test_a_colliding_pair_fails_the_report_and_names_the_pair(tmp_path, capsys):
    path = colliding(tmp_path)
    run = run_cli(capsys, 'report', path, '--json')
    assert run.code == 1
    data = json.loads(run.out)
    assert data['ok'] is False and all(axis['ok'] for axis in data['axes'])
    clearance, zones = data['interference']
    shifted = -100.0 * DEG

    def shifted_gap(q):
        return 0.31 - coupled(q, lambda t: reference_positions(t, KNIFE)['feeder']) \
            - coupled(q, jaw_s, shifted)
    assert clearance['min_clearance'] == pytest.approx(smallest(shifted_gap, Q)[0], abs=1e-15)
    assert clearance['ok'] is False

    # Both in the zone: the margin is minus the overlap, from the jaw entering to the knife
    # leaving (one overlap arc).
    def jaw_zone(q):
        return coupled(q, jaw_s, shifted) - 0.06
    (jaw_in,), _ = crossings(jaw_zone, Q)
    _, (knife_out,) = crossings(knife_zone, Q)
    assert zones['min_margin_deg'] == pytest.approx(-math.degrees(knife_out - jaw_in), abs=1e-9)
    assert zones['at_deg'] == pytest.approx(math.degrees(jaw_in), abs=1e-9)
    assert zones['ok'] is False
    text = run_cli(capsys, 'report', path)
    assert text.code == 1
    overlap = re.search(r'both in the zone for (\S+) deg of machine angle from (\S+) deg '
                        r'\(margin (\S+) deg\)', text.out)
    assert Fraction(overlap[1]) >= Fraction(math.degrees(knife_out - jaw_in))  # rounded up
    floored(overlap[3], -math.degrees(knife_out - jaw_in))
    assert text.out.splitlines()[-1] == ('Verdict: clearance feeder-jaw COLLIDES; '
                                         'zones jaw-knife COLLIDES')


def test_an_axis_failing_its_own_verdict_fails_the_report(tmp_path, capsys):
    def edit(parameters):  # a jaw cam far too small for its stroke
        parameters['jaw']['follower'] = {'type': 'translating_roller', 'base_radius': 5.0,
                                         'roller_radius': 2.0}
    run = run_cli(capsys, 'report', edited_machine(tmp_path, 'small_jaw', edit), '--json')
    assert run.code == 1
    data = json.loads(run.out)
    assert [axis['ok'] for axis in data['axes']] == [True, True, False]
    assert data['ok'] is False and all(pair['ok'] for pair in data['interference'])


def test_sample_json_is_each_axis_as_commanded_at_cam_speed(capsys):
    run = run_cli(capsys, 'sample', MACHINE, '--step-deg', 0.5, '--json')
    assert run.code == 0 and run.err == ''
    data = json.loads(run.out)
    assert list(data) == ['angle', 'axes'] and list(data['axes']) == list(NAMES)
    angle = np.array(data['angle'])
    np.testing.assert_allclose(angle, np.radians(np.arange(720) * 0.5), rtol=0.0, atol=1e-15)
    reference = reference_positions(angle, KNIFE)
    h = 1e-6
    slope = {name: (reference_positions(angle + h, KNIFE)[name]
                    - reference_positions(angle - h, KNIFE)[name]) / (2 * h) for name in NAMES}
    for name in NAMES:
        axis = data['axes'][name]
        assert list(axis) == ['position', 'velocity', 'acceleration', 'jerk']
        np.testing.assert_allclose(axis['position'], reference[name], rtol=0.0, atol=1e-14)
        velocity = np.array(axis['velocity'])
        smooth = np.isfinite(slope[name])  # the knife's cut has a velocity kink: off the grid
        np.testing.assert_allclose(velocity[smooth], slope[name][smooth] * CAM_SPEED, rtol=0.0,
                                   atol=1e-6 * np.abs(velocity).max())


def test_sample_csv_and_text_hold_the_same_values_per_axis(capsys):
    data = json.loads(run_cli(capsys, 'sample', MACHINE, '--step-deg', 30, '--json').out)
    run = run_cli(capsys, 'sample', MACHINE, '--step-deg', 30, '--csv')
    rows = list(csv.reader(io.StringIO(run.out)))
    units = {'feeder': 'm', 'knife': 'rad', 'jaw': 'm'}
    assert rows[0] == ['angle_rad'] + [
        f'{name}_{field}_{units[name]}{suffix}' for name in NAMES
        for field, suffix in (('position', ''), ('velocity', '_per_s'),
                              ('acceleration', '_per_s2'), ('jerk', '_per_s3'))]
    values = np.array(rows[1:], dtype=float)
    np.testing.assert_array_equal(values[:, 0], data['angle'])
    for index, name in enumerate(NAMES):
        for column, field in enumerate(('position', 'velocity', 'acceleration', 'jerk')):
            np.testing.assert_array_equal(values[:, 1 + 4 * index + column],
                                          data['axes'][name][field])
    text = run_cli(capsys, 'sample', MACHINE, '--step-deg', 30).out
    blocks = text.split('\n\n')
    assert [block.split(':')[0] for block in blocks] == [f'Axis {name}' for name in NAMES]
    knife_rows = blocks[1].splitlines()[2:]
    assert len(knife_rows) == 12
    assert [float(row.split()[1]) for row in knife_rows] == pytest.approx(
        data['axes']['knife']['position'], rel=1e-5)


def test_one_axis_alone_is_its_cam_over_its_own_cam_angle(capsys):
    run = run_cli(capsys, 'sample', MACHINE, '--axis', 'jaw', '--step-deg', 1, '--json')
    assert run.code == 0
    data = json.loads(run.out)
    np.testing.assert_allclose(data['position'], jaw_s(np.array(data['angle'])), rtol=0.0,
                               atol=1e-15)
    report = json.loads(run_cli(capsys, 'report', MACHINE, '--axis', 'knife', '--json').out)
    assert report['name'] == 'knife' and report['position_unit'] == 'rad'
    assert report['advance'] == pytest.approx(TWO_PI, abs=1e-15)


@pytest.mark.parametrize('argv, fragments', [
    (('plot', MACHINE, '-o', 'x.png'), ('axes = ', 'machine file', '--axis NAME',
                                        '--timing-diagram')),
    (('export', MACHINE, '-o', 'x.nc', '--machining', '--cutter-radius', '5', '--tolerance',
      '0.01'),
     ('machine file', '--axis NAME')),
    (('export', MACHINE, '-o', 'x.dxf'), ('machine file', '--axis NAME')),
    (('report', DEFAULT_CONFIG, '--axis', 'jaw'), ('--axis', 'machine files', 'one cam')),
    (('report', MACHINE, '--axis', 'knfe'), ("'knfe'", 'not an axis', 'did you mean knife')),
    (('plot', DEFAULT_CONFIG, '--timing-diagram', '-o', 'x.png'),
     ('--timing-diagram', 'one cam, not a machine file')),
    (('plot', MACHINE, '--timing-diagram', '--axis', 'jaw', '-o', 'x.png'),
     ('--axis', 'cannot go with --timing-diagram')),
])
def test_single_cam_uses_of_a_machine_are_refused_in_one_line(capsys, tmp_path, argv, fragments):
    argv = tuple(tmp_path / arg if str(arg).startswith('x.') else arg for arg in argv)
    assert_one_error_line(run_cli(capsys, *argv), argv[0], *fragments)
