"""`cam_ros export --cam-table`: every format read back equals the core; units; bad input."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from cli_support import (assert_one_error_line, DEFAULT_CONFIG, follower_config, run_cli,
                         SHIPPED_CONFIGS, write_config)
from scipy.interpolate import CubicHermiteSpline

from cam_ros.commands.common import load_design

CM = 0.01
RISE_CM = 2.0  # seed 000's stroke in its file unit
#: Written values must equal the core's to this fraction of the stroke (the issue asks 1e-9).
ROUND_TRIP = 1e-12
DENSE_DEG = np.linspace(0.0, 360.0, 720_001)


def export_table(capsys, target, *options, config=DEFAULT_CONFIG) -> str:
    """Run export --cam-table and return the file's text."""
    run = run_cli(capsys, 'export', config, '-o', target, '--cam-table', *options)
    assert run.code == 0 and run.err == '', run
    assert run.out.startswith(f'wrote {target}: cam table of ')
    return target.read_text()


def read_csv(text) -> tuple[list[str], list[str], np.ndarray]:
    """Return the notes, the column names and the values of a csv/xyva cam table."""
    header = [line[2:] for line in text.splitlines() if line.startswith('# ')]
    rows = [line for line in text.splitlines() if not line.startswith('#')]
    values = np.array([[float(cell) for cell in row.split(',')] for row in rows])
    return header[:-1], header[-1].split(','), values


def exact_cm(master_deg, config=DEFAULT_CONFIG) -> np.ndarray:
    """Return the core's slave position (cm) at master angles in degrees."""
    return load_design(config).program.evaluate(np.radians(master_deg)).s / CM


def worst_deviation(notes) -> float:
    """Return the worst deviation the header states, in the file's slave unit."""
    match = re.search(r'worst deviation from the exact law ([0-9.]+) ', ' '.join(notes))
    return float(match.group(1))


def test_csv_points_equal_the_core_with_units_in_the_header(tmp_path, capsys):
    notes, names, values = read_csv(export_table(capsys, tmp_path / 'cam.csv', '--points', 72))
    assert names == ['master_deg', 'slave_cm']
    np.testing.assert_array_equal(values[:, 0], 5.0 * np.arange(73))  # ascending, 0 to 360
    np.testing.assert_allclose(values[:, 1], exact_cm(values[:, 0]), rtol=0,
                               atol=ROUND_TRIP * RISE_CM)
    # Seed 000 in closed form: cycloidal rise of 2 cm over 90-180 deg, s(135) = 1 cm.
    assert values[27, 1] == pytest.approx(1.0, abs=1e-12)
    assert 'the periodic end point 360 deg included' in notes[0]
    assert 'interpolation assumed: linear' in notes[2]


def test_derivatives_per_degree_match_differences_of_the_written_positions(tmp_path, capsys):
    text = export_table(capsys, tmp_path / 'cam.csv', '--points', 36000, '--derivatives')
    notes, names, values = read_csv(text)
    assert names == ['master_deg', 'slave_cm', 'velocity_cm_per_deg',
                     'acceleration_cm_per_deg2']
    assert 'per deg and per deg^2 of master' in notes[3]
    master, s, v, a = values.T
    step = 0.01  # deg
    # Away from the segment joints (where derivatives may jump): central differences.
    inner = np.ones(master.size, bool)
    inner[[0, -1]] = False
    for joint in (90.0, 180.0, 240.0, 360.0):
        inner &= np.abs(master - joint) > 2.5 * step
    central = (s[2:] - s[:-2]) / (2 * step)
    second = (s[2:] - 2 * s[1:-1] + s[:-2]) / step ** 2
    scale_v = np.abs(v).max()
    scale_a = np.abs(a).max()
    np.testing.assert_allclose(v[1:-1][inner[1:-1]], central[inner[1:-1]], rtol=0,
                               atol=1e-6 * scale_v)
    np.testing.assert_allclose(a[1:-1][inner[1:-1]], second[inner[1:-1]], rtol=0,
                               atol=1e-5 * scale_a)
    # Cycloidal rise h over beta = 90 deg peaks at ds/dtheta = 2 h / beta = 2/90 cm per deg.
    assert scale_v == pytest.approx(2 * RISE_CM / 90.0, rel=1e-9)


@pytest.mark.parametrize('end_point, rows', [([], 13), (['--end-point'], 13),
                                             (['--no-end-point'], 12)])
def test_periodic_end_point_is_an_option(end_point, rows, tmp_path, capsys):
    notes, _, values = read_csv(export_table(capsys, tmp_path / 'cam.csv', '--points', 12,
                                             *end_point))
    assert len(values) == rows and values[-1, 0] == (360.0 if rows == 13 else 330.0)
    assert f'{rows} points' in notes[0]


def test_tolerance_table_interpolates_within_the_tolerance(tmp_path, capsys):
    notes, _, values = read_csv(export_table(capsys, tmp_path / 'cam.csv', '--tolerance', '1um'))
    master, slave = values.T
    error = np.abs(np.interp(DENSE_DEG, master, slave) - exact_cm(DENSE_DEG)).max()
    assert error <= 1e-6 / CM
    stated = worst_deviation(notes)
    assert error <= stated * (1 + 1e-9) and stated <= 1e-6 / CM
    assert 'placed for linear interpolation within a tolerance of 0.0001 cm' in notes[1]
    np.testing.assert_allclose(slave, exact_cm(master), rtol=0, atol=ROUND_TRIP * RISE_CM)
    assert len(values) < 250  # 184 measured; 502 equidistant points are needed for 1 um


def test_cubic_csv_is_hermite_within_the_tolerance(tmp_path, capsys):
    text = export_table(capsys, tmp_path / 'cam.csv', '--tolerance', '1um', '--interpolation',
                        'cubic')
    notes, names, values = read_csv(text)
    assert len(names) == 4 and 'cubic Hermite' in notes[2]
    master, slave, velocity, _ = values.T
    # Slopes per degree against master in degrees: the Hermite spline the PLC builds.
    spline = CubicHermiteSpline(master, slave, velocity)
    assert np.abs(spline(DENSE_DEG) - exact_cm(DENSE_DEG)).max() <= 1e-6 / CM
    assert len(values) < 40


def parse_xyva(text) -> tuple[str, np.ndarray]:
    """Return the header text and the X, Y, V, A rows of an xyva file, read plainly."""
    header, rows = [], []
    for line in text.splitlines():
        if line.startswith('#'):
            header.append(line.lstrip('# '))
        else:
            rows.append([float(cell) for cell in line.split(',')])
    return ' '.join(header), np.array(rows)


def codesys_xyva(rows, x) -> np.ndarray:
    """Evaluate an XYVA cam at master positions x as documented: on each interval the
    fifth-degree polynomial through Y, V = dY/dX and A = d2Y/dX2 at both ends (quintic Hermite
    basis in t = (x - X0) / h)."""
    master, y, v, a = rows.T
    i = np.clip(np.searchsorted(master, x, side='right') - 1, 0, len(master) - 2)
    h = master[i + 1] - master[i]
    t = (x - master[i]) / h
    t3, t4, t5 = t ** 3, t ** 4, t ** 5
    basis = (1 - 10 * t3 + 15 * t4 - 6 * t5, t - 6 * t3 + 8 * t4 - 3 * t5,
             (t ** 2 - 3 * t3 + 3 * t4 - t5) / 2, 10 * t3 - 15 * t4 + 6 * t5,
             -4 * t3 + 7 * t4 - 3 * t5, (t3 - 2 * t4 + t5) / 2)
    ends = (y[i], h * v[i], h ** 2 * a[i], y[i + 1], h * v[i + 1], h ** 2 * a[i + 1])
    return sum(value * weight for value, weight in zip(ends, basis))


def seed_000_cm(master_deg) -> np.ndarray:
    """Seed 000 in closed form (cm): dwell, cycloidal rise of 2 cm over 90-180 deg, dwell,
    simple harmonic return over 240-360 deg."""
    x = np.asarray(master_deg, dtype=float) % 360.0
    rise = np.clip((x - 90.0) / 90.0, 0.0, 1.0)
    back = np.clip((x - 240.0) / 120.0, 0.0, 1.0)
    return np.where(x < 240.0, RISE_CM * (rise - np.sin(2 * np.pi * rise) / (2 * np.pi)),
                    RISE_CM * (1 + np.cos(np.pi * back)) / 2)


#: Master positions of the independent check of an XYVA file.
XYVA_CHECK_DEG = np.linspace(0.0, 360.0, 10_000)


@pytest.mark.parametrize('spacing', [['--tolerance', '1um'], ['--tolerance', '0.1um'],
                                     ['--points', '36']])
def test_xyva_under_codesys_interpolation_stays_within_its_stated_deviation(
        tmp_path, capsys, spacing):
    text = export_table(capsys, tmp_path / 'cam.xyva', *spacing, '--format', 'xyva')
    header, rows = parse_xyva(text)
    assert 'quintic Hermite' in header and 'CODESYS' in header
    stated = float(re.search(r'worst deviation from the exact law ([0-9.]+) cm', header)[1])
    deviation = np.abs(codesys_xyva(rows, XYVA_CHECK_DEG) - seed_000_cm(XYVA_CHECK_DEG)).max()
    # The stated figure is refined per interval and rounded up to 6 digits: at or above what
    # 10,000 positions find, and above it by no more than a sampled peak can miss.
    assert deviation <= stated <= deviation * (1 + 1e-4)
    if spacing[0] == '--tolerance':
        assert stated <= float(spacing[1][:-2]) * 1e-4  # um in cm


def test_xyva_keeps_both_sides_of_an_acceleration_jump(tmp_path, capsys):
    """Seed 000's acceleration jumps at 240 deg (dwell into the simple harmonic return, to
    -pi^2 h / (2 * 120^2) cm/deg^2) and at 360 (back from +pi^2 h / (2 * 120^2)): the joint's row
    carries the segment that starts there, a row just before it the one that ends there."""
    _, rows = parse_xyva(export_table(capsys, tmp_path / 'cam.xyva', '--tolerance', '1um',
                                      '--format', 'xyva'))
    master, _, _, a = rows.T
    jump = np.pi ** 2 * RISE_CM / (2 * 120.0 ** 2)
    for joint, left, right in ((240.0, 0.0, -jump), (360.0, jump, 0.0)):
        at = int(np.flatnonzero(np.isclose(master, joint, rtol=0, atol=1e-9))[0])
        assert a[at] == pytest.approx(right, abs=1e-15)
        assert joint - 1e-3 < master[at - 1] < joint
        assert a[at - 1] == pytest.approx(left, rel=1e-6, abs=1e-15)


def test_sew_is_a_count_then_master_semicolon_slave(tmp_path, capsys):
    text = export_table(capsys, tmp_path / 'cam.txt', '--points', 10, '--format', 'sew')
    lines = text.splitlines()
    assert lines[0] == '11' and len(lines) == 12
    pairs = np.array([[float(cell) for cell in line.split(';')] for line in lines[1:]])
    np.testing.assert_array_equal(pairs[:, 0], 36.0 * np.arange(11))
    np.testing.assert_allclose(pairs[:, 1], exact_cm(pairs[:, 0]), rtol=0,
                               atol=ROUND_TRIP * RISE_CM)


def test_structured_text_array_holds_the_same_points(tmp_path, capsys):
    text = export_table(capsys, tmp_path / 'cam.st', '--points', 20, '--format', 'st')
    _, _, csv_values = read_csv(export_table(capsys, tmp_path / 'cam.csv', '--points', 20))
    match = re.search(r'^    CamTable : ARRAY\[0\.\.(\d+), 0\.\.1\] OF LREAL := \[\n(.*?)\];\n'
                      r'END_VAR\n\Z', text, re.S | re.M)
    assert match and int(match.group(1)) == 20
    assert text.splitlines()[0].startswith('(* cam table of default.yaml')
    numbers = [float(cell) for cell in match.group(2).replace('\n', ' ').split(',')]
    np.testing.assert_array_equal(np.reshape(numbers, (21, 2)), csv_values)
    for cell in match.group(2).replace(',', ' ').split():
        assert '.' in cell and 'e' not in cell.lower()  # IEC 61131-3 LREAL literals


def test_oscillating_follower_slave_is_in_degrees(tmp_path, capsys):
    config = follower_config(tmp_path, 'oscillating_roller')
    _, names, values = read_csv(export_table(capsys, tmp_path / 'osc.csv', '--points', 36,
                                             '--derivatives', config=config))
    assert names[1:] == ['slave_deg', 'velocity_deg_per_deg', 'acceleration_deg_per_deg2']
    program = load_design(config).program.evaluate(np.radians(values[:, 0]))
    np.testing.assert_allclose(values[:, 1], np.degrees(program.s), rtol=0, atol=1e-12)
    # d(psi in deg)/d(theta in deg) = dpsi/dtheta (rad/rad): the same number.
    np.testing.assert_allclose(values[:, 2], program.ds, rtol=0, atol=1e-14)
    np.testing.assert_allclose(values[:, 3], np.radians(program.d2s), rtol=0, atol=1e-14)


@pytest.mark.parametrize('config', SHIPPED_CONFIGS, ids=lambda path: path.name)
def test_every_shipped_config_exports_a_table(config, tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    run = run_cli(capsys, 'export', config, '-o', target, '--cam-table', '--points', 90)
    assert run.code == (0 if load_design(config).ok else 1)
    _, _, values = read_csv(target.read_text())
    assert values.shape == (91, 2) and np.all(np.diff(values[:, 0]) > 0)


@pytest.mark.parametrize('options, fragments', [
    (['--points', '0'], ['--points', "'0'", 'integer >= 2']),
    (['--points', '-4'], ['--points', 'integer >= 2']),
    (['--tolerance', '0'], ['--tolerance', 'must be > 0']),
    (['--tolerance=-1e-6'], ['--tolerance', 'must be > 0']),
    (['--tolerance', '5'], ["--tolerance = '5'", 'must be in [', '2] cm']),
    (['--tolerance', '0.1deg'], ['--tolerance', 'must be a length here', 'bare number in cm']),
    (['--tolerance', '1 parsec'], ['--tolerance', "unknown unit 'parsec'"]),
    (['--format', 'dxf'], ['--format', "'dxf'", 'a cam table takes one of csv, sew, xyva, st']),
    (['--format', 'sew', '--interpolation', 'cubic'], ['--interpolation', 'sew']),
    (['--format', 'st', '--interpolation', 'quintic'], ['--interpolation', 'accelerations',
                                                        'use csv or xyva']),
    (['--format', 'xyva', '--interpolation', 'cubic'], ["--interpolation = 'cubic'",
                                                        'CODESYS', 'give quintic']),
    (['--format', 'st', '--derivatives'], ['--derivatives', 'st']),
    (['--points', '20000', '--format', 'sew'], ['--points = 20000', 'at most 16383']),
    (['--samples', '10'], ['--samples', 'a cam table takes --points or --tolerance']),
    (['--points', '10', '--tolerance', '1um'], ['not allowed with argument']),
])
def test_bad_cam_table_input_exits_2_and_writes_nothing(options, fragments, tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, '--cam-table', *options)
    assert_one_error_line(run, 'export', *fragments)
    assert not target.exists()


@pytest.mark.parametrize('option, name', [(['--points', '10'], '--points'),
                                          (['--format', 'st'], '--format'),
                                          (['--derivatives'], '--derivatives'),
                                          (['--no-end-point'], '--end-point = False')])
def test_table_options_need_cam_table(option, name, tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, *option)
    assert_one_error_line(run, 'export', name, 'add --cam-table')
    assert not target.exists()


def test_unwritable_target_is_one_line(capsys):
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', '/no/such/dir/cam.csv', '--cam-table')
    assert_one_error_line(run, 'export', 'cannot be written')


def test_default_table_is_one_point_per_degree(tmp_path, capsys):
    _, _, values = read_csv(export_table(capsys, tmp_path / 'cam.csv'))
    np.testing.assert_array_equal(values[:, 0], np.arange(361.0))
    assert math.isclose(values[:, 1].max(), RISE_CM)


def mm_config(directory):
    """Seed 000 written in millimetres (the same cam)."""
    def in_mm(parameters):
        parameters['length_unit'] = 'mm'
        for key in ('base_radius', 'roller_radius', 'offset'):
            parameters['follower'][key] *= 10.0
        for key in ('start_position', 'end_position'):
            parameters['motion'][key] = [10.0 * value for value in parameters['motion'][key]]
        parameters['limits']['min_radius_of_curvature'] *= 10.0
    return write_config(directory, 'seed_000_mm', in_mm)


@pytest.mark.parametrize('tolerance', ['0.01', '0.01mm', '10um', '1e-5m', '0.001cm'])
def test_a_bare_tolerance_is_in_the_tables_unit_and_a_suffix_is_its_own(
        tmp_path, capsys, tolerance):
    config = mm_config(tmp_path)
    target = tmp_path / 'cam.csv'
    run = run_cli(capsys, 'export', config, '-o', target, '--cam-table', '--tolerance', tolerance)
    assert run.code == 0, run
    assert 'within a tolerance of 0.01 mm' in run.out
    notes, names, values = read_csv(target.read_text())
    assert names == ['master_deg', 'slave_mm']
    assert 'within a tolerance of 0.01 mm' in notes[1]
    master, slave = values.T
    exact = exact_cm(DENSE_DEG, config) * 10.0  # mm
    error = np.abs(np.interp(DENSE_DEG, master, slave) - exact).max()
    assert 0.005 < error <= 0.01  # a table for 0.01 mm, not for 0.01 m (10 mm, 3 points)


def test_an_oscillating_table_takes_degrees(tmp_path, capsys):
    config = follower_config(tmp_path, 'oscillating_roller')
    texts = []
    for tolerance in ('0.01', '0.01deg', f'{math.radians(0.01)!r}rad'):
        target = tmp_path / f'cam{len(texts)}.csv'
        run = run_cli(capsys, 'export', config, '-o', target, '--cam-table', '--tolerance',
                      tolerance)
        assert run.code == 0 and 'within a tolerance of 0.01 deg' in run.out, run
        texts.append(target.read_text())
    assert texts[0] == texts[1] and len(texts[0].splitlines()) == len(texts[2].splitlines())
    run = run_cli(capsys, 'export', config, '-o', tmp_path / 'x.csv', '--cam-table',
                  '--tolerance', '0.01mm')
    assert_one_error_line(run, 'export', "--tolerance = '0.01mm'", 'must be an angle here')


def test_help_states_rows_and_tolerance_unit_and_claims_no_fewest(capsys):
    run = run_cli(capsys, 'export', '--help')
    text = ' '.join(run.out.split())
    assert run.code == 0
    assert 'N + 1 rows with the end point 360 deg' in text
    assert "T in the table's unit" in text and '0.01mm' in text
    assert 'fewest' not in text


@pytest.mark.parametrize('points, noted', [(1023, False), (1024, True), (2000, True)])
def test_a_sew_table_over_the_default_list_size_gets_a_note(tmp_path, capsys, points, noted):
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', tmp_path / 'cam.txt', '--cam-table',
                  '--points', points, '--format', 'sew')
    assert run.code == 0
    rows = int((tmp_path / 'cam.txt').read_text().splitlines()[0])
    assert rows == points + 1
    assert ('default list size' in run.out) is noted
    if noted:
        assert f'{rows} points exceed' in run.out and 'default list size of 1024' in run.out


def one_unit_of_the_sixth_digit(value: float) -> float:
    return 10.0 ** (math.floor(math.log10(value)) - 5)


@pytest.mark.parametrize('options', [['--points', '7'], ['--points', '36', '--format', 'xyva'],
                                     ['--tolerance', '0.3um', '--interpolation', 'cubic']])
def test_printed_worst_deviation_is_rounded_up(tmp_path, capsys, options):
    """The printed and the stated figure are at or above the table's worst deviation (built
    here by the core from the same options) and above it by less than a unit of the 6th digit."""
    from cam_ros.core.ecam.cam_table import equidistant_table, tolerance_table

    target = tmp_path / 'cam.txt'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, '--cam-table', *options)
    assert run.code == 0, run
    program = load_design(DEFAULT_CONFIG).program
    interpolation = ('quintic' if 'xyva' in options else
                     'cubic' if 'cubic' in options else 'linear')
    table = (equidistant_table(program, int(options[1]), interpolation)
             if options[0] == '--points' else tolerance_table(program, 0.3e-6, interpolation))
    truth = table.max_error / CM
    printed = float(re.search(r'worst deviation ([0-9.]+) cm$', run.out.strip())[1])
    stated = float(re.search(r'worst deviation from the exact law ([0-9.]+) cm',
                             target.read_text())[1])
    for figure in (printed, stated):
        assert truth <= figure < truth + one_unit_of_the_sixth_digit(truth)
