"""`export --cam-table` for Beckhoff motion functions, Rockwell, Lenze and Kollmorgen.

Every file is read back here by an independent reader (a regular expression for the ST array,
xml.etree for the L5X, a few lines for the text formats) and compared with seed 000 in closed
form (cli_support.seed_000_motion) or, for the motion functions, evaluated with the VDI 2143
polynomials written below: the line, the rest-to-rest quintic 10u^3 - 15u^4 + 6u^5 and the
quintic through position, velocity and acceleration at both ends (one 6 x 6 solve per piece).
"""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from cli_support import (assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, run_cli,
                         seed_000_motion, write_config)

CM = 0.01
STROKE_CM = 2.0
DENSE_DEG = np.linspace(0.0, 360.0, 10_001)
FIELDS = ('PointIndex', 'FunctionType', 'PointType', 'RelIndexNextPoint', 'MasterPos',
          'SlavePos', 'SlaveVelo', 'SlaveAcc', 'SlaveJerk')


def export(capsys, target, *options, config=DEFAULT_CONFIG) -> tuple[str, str]:
    run = run_cli(capsys, 'export', config, '-o', target, '--cam-table', *options)
    assert run.code == 0 and run.err == '', run
    return target.read_text(), run.out


def seed_cm(master_deg) -> np.ndarray:
    return seed_000_motion(np.radians(master_deg))[0] / CM


def read_motion_function(text) -> list[dict]:
    """Return the MC_MotionFunctionPoint initialisers of the ST array, field by field."""
    match = re.search(r'^VAR_GLOBAL CONSTANT\n    CamFunction : ARRAY\[1\.\.(\d+)\] OF '
                      r'MC_MotionFunctionPoint := \[\n(.*)\];\nEND_VAR\n\Z', text, re.S | re.M)
    assert match
    points = []
    for row in re.findall(r'\(([^()]*)\)', match.group(2)):
        pairs = [item.split(' := ') for item in row.split(', ')]
        assert [name for name, _ in pairs] == list(FIELDS)
        points.append({name: value for name, value in pairs})
    assert len(points) == int(match.group(1))
    return points


def evaluate_motion_function(points, x) -> np.ndarray:
    """Return the slave at master positions x from the points and their function types."""
    master = np.array([float(p['MasterPos']) for p in points])
    y = np.array([float(p['SlavePos']) for p in points])
    v = np.array([float(p['SlaveVelo']) for p in points])
    a = np.array([float(p['SlaveAcc']) for p in points])
    result = np.empty_like(x)
    index = np.clip(np.searchsorted(master, x, side='right') - 1, 0, len(points) - 2)
    for i in np.unique(index):
        at = index == i
        x0, x1, h = master[i], master[i + 1], y[i + 1] - y[i]
        u = (x[at] - x0) / (x1 - x0)
        kind = points[i]['FunctionType']
        if kind == 'MOTIONFUNCTYPE_POLYNOM1':
            result[at] = y[i] + h * u
        elif kind == 'MOTIONFUNCTYPE_POLYNOM5':
            assert v[i] == v[i + 1] == a[i] == a[i + 1] == 0.0
            result[at] = y[i] + h * (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5)
        else:
            assert kind == 'MOTIONFUNCTYPE_POLYNOM5_MM'
            d = x1 - x0
            rows = [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
                    [1, d, d ** 2, d ** 3, d ** 4, d ** 5],
                    [0, 1, 2 * d, 3 * d ** 2, 4 * d ** 3, 5 * d ** 4],
                    [0, 0, 2, 6 * d, 12 * d ** 2, 20 * d ** 3]]
            c = np.linalg.solve(np.array(rows, float),
                                [y[i], v[i], a[i], y[i + 1], v[i + 1], a[i + 1]])
            result[at] = np.polyval(c[::-1], x[at] - x0)
    return result


def test_motion_function_of_seed_000_meets_the_stated_deviations(tmp_path, capsys):
    text, out = export(capsys, tmp_path / 'cam.st', '--format', 'twincat-functions',
                       '--tolerance', '1um')
    points = read_motion_function(text)
    assert [p['PointIndex'] for p in points] == [str(i) for i in range(1, len(points) + 1)]
    master = np.array([float(p['MasterPos']) for p in points])
    assert master[0] == 0.0 and master[-1] == 360.0 and np.all(np.diff(master) > 0)
    error = np.abs(evaluate_motion_function(points, DENSE_DEG) - seed_cm(DENSE_DEG))
    # The dwells are lines, exact; the cycloid and the harmonic are pieces within 1 um.
    dwell = (DENSE_DEG <= 90.0) | ((DENSE_DEG >= 180.0) & (DENSE_DEG <= 240.0))
    assert error[dwell].max() <= 1e-12 * STROKE_CM
    stated = [float(value) for value in re.findall(r'worst deviation ([0-9.]+) cm', text)]
    assert len(stated) == 2 and max(stated) <= 1e-4
    assert error.max() <= max(stated)
    assert error.max() > 0.5e-4  # the pieces use the tolerance (a real test of the bound)
    assert 'segment 0 (dwell, 0-90 deg): MOTIONFUNCTYPE_POLYNOM1' in text
    assert 'segment 1 (cycloidal, 90-180 deg): no native function' in text
    assert '2 of 4 segments as quintic pieces' in out


def quintic_config(directory):
    """Seed 000 with polynomial_345 rise and return: every law native to the target."""
    def edit(parameters):
        parameters['motion']['laws'] = ['dwell', 'polynomial_345', 'dwell', 'polynomial_345']
    return write_config(directory, 'quintic.yaml', edit)


def test_native_laws_are_exact(tmp_path, capsys):
    text, _ = export(capsys, tmp_path / 'cam.st', '--format', 'twincat-functions',
                     config=quintic_config(tmp_path))
    points = read_motion_function(text)
    assert [p['FunctionType'][len('MOTIONFUNCTYPE_'):] for p in points[:-1]] == [
        'POLYNOM1', 'POLYNOM5', 'POLYNOM1', 'POLYNOM5']
    assert [p['PointType'] for p in points] == ['MOTIONPOINTTYPE_REST'] * 5
    u_rise = np.clip((DENSE_DEG - 90.0) / 90.0, 0.0, 1.0)
    u_fall = np.clip((DENSE_DEG - 240.0) / 120.0, 0.0, 1.0)
    p345 = lambda u: 10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5  # noqa: E731
    exact = STROKE_CM * (p345(u_rise) - p345(u_fall))
    error = np.abs(evaluate_motion_function(points, DENSE_DEG) - exact)
    assert error.max() <= 1e-12 * STROKE_CM


def read_l5x(text) -> np.ndarray:
    """Return (Master, Slave, SegmentType) rows of the CAM array tag (1756-RM084 layout)."""
    root = ET.fromstring(text)
    assert root.tag == 'RSLogix5000Content' and root.get('TargetType') == 'Tag'
    tag = root.find('./Controller/Tags/Tag')
    assert tag.get('DataType') == 'CAM' and tag.get('Name') == root.get('TargetName')
    array = tag.find("./Data[@Format='Decorated']/Array")
    assert array.get('DataType') == 'CAM' and array.get('Dimensions') == tag.get('Dimensions')
    rows = []
    for index, element in enumerate(array.findall('Element')):
        assert element.get('Index') == f'[{index}]'
        members = element.findall("./Structure[@DataType='CAM']/DataValueMember")
        assert [(m.get('Name'), m.get('DataType')) for m in members] == [
            ('Master', 'REAL'), ('Slave', 'REAL'), ('SegmentType', 'DINT')]
        rows.append([float(np.float32(m.get('Value'))) for m in members])  # as a REAL reads
    assert len(rows) == int(tag.get('Dimensions'))
    return np.array(rows)


def test_rockwell_l5x_holds_reals_within_the_tolerance(tmp_path, capsys):
    text, out = export(capsys, tmp_path / 'cam.L5X', '--format', 'rockwell',
                       '--tolerance', '1um')
    rows = read_l5x(text)
    assert np.all(rows[:, 2] == 0)  # linear segments
    assert rows[0, 0] == 0.0 and rows[-1, 0] == 360.0 and np.all(np.diff(rows[:, 0]) > 0)
    description = ET.fromstring(text).find('.//Tag/Description').text
    stated = float(re.search(r'worst deviation from the exact law ([0-9.]+) cm',
                             description).group(1))
    error = np.abs(np.interp(DENSE_DEG, rows[:, 0], rows[:, 1]) - seed_cm(DENSE_DEG))
    assert error.max() <= stated <= 1e-4
    assert 'REAL (single precision): their rounding adds at most' in description
    assert 'segment 1 cycloidal 90-180 deg' in description
    assert 'worst deviation 0.0000' in out


def test_rockwell_cubic_states_no_deviation(tmp_path, capsys):
    text, _ = export(capsys, tmp_path / 'cam.L5X', '--format', 'rockwell', '--points', '36',
                     '--interpolation', 'cubic')
    rows = read_l5x(text)
    assert np.all(rows[:, 2] == 1) and len(rows) == 37
    assert 'its deviation is not stated' in ET.fromstring(text).find('.//Description').text


def test_lenze_is_x_y_lines_with_comments(tmp_path, capsys):
    text, _ = export(capsys, tmp_path / 'cam.txt', '--format', 'lenze', '--points', '72')
    lines = text.splitlines()
    values = np.array([[float(cell) for cell in line.split('//')[0].split()]
                       for line in lines])
    assert values.shape == (73, 2) and np.all(np.diff(values[:, 0]) > 0)
    np.testing.assert_allclose(values[:, 1], seed_cm(values[:, 0]), rtol=0,
                               atol=1e-12 * STROKE_CM)
    comments = [line.split(' // ', 1)[1] for line in lines if ' // ' in line]
    assert comments[0].startswith('cam table of default.yaml')
    assert any(c.startswith('segment 3 simple_harmonic 240-360 deg') for c in comments)


def test_kollmorgen_is_the_kas_csv(tmp_path, capsys):
    text, out = export(capsys, tmp_path / 'cam.csv', '--format', 'kollmorgen', '--points', '8')
    lines = text.splitlines()
    assert lines[:2] == ['CYCLIC;YES;', 'TABLE_BEGIN;;'] and lines[-1] == 'TABLE_END;;'
    rows = [line.split(';') for line in lines[2:-1]]
    assert all(row[2] == 'SPLINE' for row in rows) and len(rows) == 9
    values = np.array([[float(row[0]), float(row[1])] for row in rows])
    np.testing.assert_allclose(values[:, 1], seed_cm(values[:, 0]), rtol=0,
                               atol=1e-12 * STROKE_CM)
    assert 'no comment syntax' in out


def characteristic(text, segment, name) -> tuple[float, float, float, float]:
    """Return (min, at, max, at) of a quantity on a segment's characteristics line."""
    line = next(line for line in text.splitlines() if f'segment {segment} ' in line
                and f'{name} ' in line and '@' in line)
    found = re.search(name + r' (-?[0-9.]+) @ ([0-9.]+) \.\. (-?[0-9.]+) @ ([0-9.]+)', line)
    return tuple(float(value) for value in found.groups())


@pytest.mark.parametrize('fmt', ['csv', 'rockwell', 'twincat-functions', 'lenze'])
def test_characteristic_values_bracket_the_closed_form(fmt, tmp_path, capsys):
    text, _ = export(capsys, tmp_path / 'cam.txt', '--format', fmt, '--tolerance', '10um')

    def digit(value):  # one unit of the 6th significant digit: the rounding's most
        return 10.0 ** (math.floor(math.log10(abs(value))) - 5)

    # Cycloid, h = 2 cm over beta = 90 deg: peak velocity 2h/beta at 135 deg, peak
    # acceleration 2 pi h / beta^2 at 112.5 deg; harmonic return over 120 deg: pi h / (2 beta).
    _, _, v_max, v_at = characteristic(text, 1, 'velocity')
    assert v_at == 135.0 and 0 <= v_max - 4.0 / 90.0 < digit(v_max)  # rounded up
    _, _, a_max, a_at = characteristic(text, 1, 'acceleration')
    assert a_at == 112.5 and 0 <= a_max - 2 * math.pi * 2.0 / 90.0 ** 2 < digit(a_max)
    v_min, v_at, _, _ = characteristic(text, 3, 'velocity')
    peak = math.pi * 2.0 / (2 * 120.0)
    assert v_at == 300.0 and 0 <= -v_min - peak < digit(peak)  # rounded down


@pytest.mark.parametrize('options, fragments', [
    (['--format', 'kollmorgen', '--points', '3'], ['--points = 3', 'at least 5',
                                                   'at least 4 spline segments']),
    (['--format', 'twincat-functions'], ['--tolerance', 'segment 1 (cycloidal)']),
    (['--format', 'twincat-functions', '--points', '36'], ['--points', '--tolerance']),
    (['--format', 'twincat-functions', '--tolerance', '1um', '--no-end-point'],
     ['--end-point', 'ends the last segment']),
    (['--format', 'lenze', '--interpolation', 'cubic'], ['--interpolation', 'lenze']),
])
def test_bad_vendor_combinations_are_one_line(options, fragments, tmp_path, capsys):
    target = tmp_path / 'cam.txt'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, '--cam-table', *options)
    assert_one_error_line(run, 'export', *fragments)
    assert not target.exists()


@pytest.mark.parametrize('fmt, source', [('rockwell', 'Logix CAM data type'),
                                         ('kollmorgen', 'KAS cam CSV import'),
                                         ('lenze', 'Cam Loader')])
def test_a_rotary_slave_is_refused_where_its_manual_states_no_advance(
        fmt, source, tmp_path, capsys):
    target = tmp_path / 'cam.txt'
    run = run_cli(capsys, 'export', CONFIG_DIR / 'rotary_knife.yaml', '-o', target,
                  '--cam-table', '--format', fmt, '--points', '36')
    assert_one_error_line(run, 'export', f"--format = '{fmt}'", source, 'advances 360 deg')
    assert not target.exists()
