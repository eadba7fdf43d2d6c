"""`cam_ros export MACHINE --cam-table`: a --tolerance per kind of unit, and the axes a vendor
format cannot take skipped by name while the others are written. Every file is read back here,
independently of the writers, and checked against the closed forms of machine_support."""
from __future__ import annotations

import csv
import re

import numpy as np
import pytest
from cli_support import assert_one_error_line, DEFAULT_CONFIG, run_cli
from machine_support import feeder_s, jaw_s, knife_s, MACHINE, MM
from test_vendor_cam_tables import read_l5x

DENSE_DEG = np.linspace(0.0, 360.0, 200001)
KNIFE = knife_s()
#: Each axis's cam in its table's unit (mm, or deg for the rotary knife), over its cam angle.
REFERENCE = {'feeder': lambda deg: feeder_s(np.radians(deg)) / MM,
             'jaw': lambda deg: jaw_s(np.radians(deg)) / MM,
             'knife': lambda deg: np.degrees(KNIFE(np.radians(deg % 360.0)))
             + 360.0 * (deg >= 360.0)}


def read_table_csv(path):
    """Return (master deg, slave) columns of a csv cam table (its header is a # comment)."""
    with path.open(newline='') as stream:
        rows = [row for row in csv.reader(stream) if not row[0].startswith('#')]
    return np.array(rows, dtype=float)[:, :2]


def read_lenze(path):
    """Return the x y lines of a Lenze cam text (comments after //)."""
    lines = path.read_text().splitlines()
    return np.array([[float(cell) for cell in line.split('//')[0].split()] for line in lines
                     if line.split('//')[0].strip()])


def read_kollmorgen(path):
    """Return the master;slave rows between TABLE_BEGIN and TABLE_END of a KAS cam CSV."""
    lines = path.read_text().splitlines()
    body = lines[lines.index('TABLE_BEGIN;;') + 1:lines.index('TABLE_END;;')]
    return np.array([[float(cell) for cell in line.split(';')[:2]] for line in body])


def test_a_tolerance_per_kind_of_unit_places_each_axis_within_its_own(tmp_path, capsys):
    folder = tmp_path / 'tables'
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--tolerance', '10um',
                  '--tolerance', '0.001deg', '--format', 'csv', '-o', folder)
    assert run.code == 0 and run.err == ''
    for name, allowed, unit in (('feeder', 0.01, 'mm'), ('jaw', 0.01, 'mm'),
                                ('knife', 0.001, 'deg')):
        assert re.search(rf'wrote {folder / name}\.csv: cam table of \d+ points \(csv, linear '
                         rf'interpolation\) within a tolerance of {allowed} {unit}', run.out)
        table = read_table_csv(folder / f'{name}.csv')
        assert table[0, 0] == 0.0 and table[-1, 0] == 360.0
        error = np.abs(np.interp(DENSE_DEG, *table.T) - REFERENCE[name](DENSE_DEG))
        assert error.max() <= allowed, name
        assert error.max() > 0.5 * allowed, name  # placed for this tolerance, not a finer one
        assert len(table) < 400, name


def test_an_axis_whose_kind_has_no_tolerance_is_refused_before_anything_is_written(
        tmp_path, capsys):
    folder = tmp_path / 'tables'
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--tolerance', '10um', '-o', folder)
    assert_one_error_line(run, 'export', "--tolerance = '10um'", 'no angle tolerance for axis '
                          'knife (in deg)', 'add --tolerance 0.001deg')
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--tolerance', '0.001deg', '-o',
                  folder)
    assert_one_error_line(run, 'export', "--tolerance = '0.001deg'", 'no length tolerance for '
                          'axis feeder (in mm)', 'add --tolerance 10um')
    assert not folder.exists()


@pytest.mark.parametrize('tolerances, fragments', [
    (('10um', '1mm'), ("--tolerance = '1mm'", "a second length tolerance (after '10um')")),
    (('0.01', '0.001deg'), ("--tolerance = '0.01'", 'needs its unit')),
    (('1deg', '2rad'), ("--tolerance = '2rad'", 'a second angle tolerance')),
])
def test_tolerances_that_do_not_say_which_axis_takes_them_are_refused(tmp_path, capsys,
                                                                      tolerances, fragments):
    folder = tmp_path / 'tables'
    options = [item for text in tolerances for item in ('--tolerance', text)]
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', *options, '-o', folder)
    assert_one_error_line(run, 'export', *fragments)
    assert not folder.exists()


def test_a_single_cam_takes_the_tolerance_of_its_unit_and_refuses_one_it_cannot(
        tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '--cam-table', '--tolerance', '0.5deg',
                  '--tolerance', '10um', '-o', target)
    assert_one_error_line(run, 'export', "--tolerance = '0.5deg'", 'is an angle tolerance, but '
                          'this cam is in cm')
    assert not target.exists()


@pytest.mark.parametrize('fmt, suffix, reader', [
    ('kollmorgen', '.csv', read_kollmorgen), ('lenze', '.txt', read_lenze),
    ('rockwell', '.L5X', lambda path: read_l5x(path.read_text())[:, :2])])
def test_a_format_without_an_advance_writes_the_other_axes_and_names_the_skipped_one(
        tmp_path, capsys, fmt, suffix, reader):
    folder = tmp_path / 'tables'
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--format', fmt, '--points', 72,
                  '-o', folder)
    assert run.code == 1
    assert run.err.splitlines() == [run.err.strip()]  # one line: the skipped axis and why
    assert run.err.startswith(f"cam_ros export: skipped axis knife: --format = '{fmt}': ")
    assert 'this slave advances 360 deg per cycle' in run.err
    assert sorted(path.name for path in folder.iterdir()) == [f'feeder{suffix}', f'jaw{suffix}']
    for name in ('feeder', 'jaw'):
        assert f'wrote {folder / name}{suffix}: cam table of 73 points' in run.out
        table = reader(folder / f'{name}{suffix}')
        np.testing.assert_array_equal(table[:, 0], np.arange(73) * 5.0)
        rounding = 2e-5 if fmt == 'rockwell' else 1e-9  # REAL: 24 bits of 200 mm
        np.testing.assert_allclose(table[:, 1], REFERENCE[name](table[:, 0]), rtol=0,
                                   atol=rounding, err_msg=name)
