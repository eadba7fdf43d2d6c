"""`cam_ros export MACHINE`: the timing diagram's curves, one axis's cam table, the tracks."""
from __future__ import annotations

import csv

import numpy as np
import pytest
from cli_support import assert_one_error_line, DEFAULT_CONFIG, run_cli
from machine_support import (feeder_s, jaw_s, knife_s, MACHINE, MM, NAMES,
                             reference_positions)

from cam_ros.core.machine import load_machine

HEADER = ['machine_angle_deg', 'feeder_position_mm', 'knife_position_deg', 'jaw_position_mm']
KNIFE = knife_s()


def read_csv(path):
    """Return a CSV file's header and its numbers, comment lines (#) left out."""
    with path.open(newline='') as stream:
        rows = [row for row in csv.reader(stream) if not row[0].startswith('#')]
    return rows[0], np.array(rows[1:], dtype=float)


@pytest.mark.parametrize('points', [None, 7])
def test_the_timing_diagram_csv_is_each_axis_as_commanded_in_file_units(tmp_path, capsys, points):
    target = tmp_path / 'timing.csv'
    argv = ('export', MACHINE, '--timing-diagram', '-o', target)
    run = run_cli(capsys, *argv, *(() if points is None else ('--points', points)))
    count = 360 if points is None else points
    assert run.code == 0 and run.err == ''
    assert run.out == (f'wrote {target}: timing diagram of 3 axes, {count + 1} machine angles '
                       'over 0-360 deg (csv)\n')
    header, values = read_csv(target)
    assert header == HEADER and values.shape == (count + 1, 4)
    np.testing.assert_allclose(values[:, 0], np.arange(count + 1) * 360.0 / count, rtol=0.0,
                               atol=1e-12)
    theta = np.radians(values[:, 0])
    reference = reference_positions(theta, KNIFE)
    scale = {'feeder': 1.0 / MM, 'knife': 180.0 / np.pi, 'jaw': 1.0 / MM}
    commanded = load_machine(MACHINE).positions(theta)
    for column, name in enumerate(NAMES, start=1):
        np.testing.assert_allclose(values[:, column], reference[name] * scale[name], rtol=0.0,
                                   atol=1e-10, err_msg=name)
        np.testing.assert_allclose(values[:, column], commanded[:, column - 1] * scale[name],
                                   rtol=1e-15, atol=0.0, err_msg=name)
    # The knife advances a turn per machine cycle, as commanded (not modulo a turn).
    assert values[-1, 2] - values[0, 2] == pytest.approx(360.0, abs=1e-9)


def test_one_axis_cam_table_is_its_cam_over_its_own_cam_angle(tmp_path, capsys):
    target = tmp_path / 'jaw.csv'
    run = run_cli(capsys, 'export', MACHINE, '--axis', 'jaw', '--cam-table', '-o', target)
    assert run.code == 0
    _, values = read_csv(tmp_path / 'jaw.csv')
    np.testing.assert_allclose(values[:, 1], jaw_s(np.radians(values[:, 0])) / MM, rtol=0.0,
                               atol=1e-9)


def test_the_switch_tracks_of_a_machine_are_on_the_machine_angle(tmp_path, capsys):
    target = tmp_path / 'tracks.csv'
    run = run_cli(capsys, 'export', MACHINE, '--switches', '-o', target)
    assert run.code == 0
    with target.open(newline='') as stream:
        rows = [row for row in csv.reader(stream) if not row[0].startswith('#')]
    assert rows == [['name', 'on_deg', 'off_deg', 'lead_time_s', 'hysteresis_deg'],
                    ['glue', '20.0', '60.0', '0.0', '0.1']]
    assert '# cam angle = (master - 0.0 deg) / 1.0' in target.read_text()


@pytest.mark.parametrize('argv, fragments', [
    (('--timing-diagram', '--format', 'st'), ('--format', "'st'", 'takes csv')),
    (('--timing-diagram', '--axis', 'jaw'), ('--axis', 'cannot go with --timing-diagram')),
    (('--timing-diagram', '--cam-table'), ('--cam-table', 'cannot go with --timing-diagram')),
    (('--switches', '--axis', 'jaw'), ('--axis', 'cannot go with --switches')),
    (('--machining', '--tolerance', '0.01', '--cutter-radius', '5'), ('machine file',
                                                                      '--axis NAME')),
])
def test_export_options_a_machine_cannot_take_are_refused(tmp_path, capsys, argv, fragments):
    run = run_cli(capsys, 'export', MACHINE, '-o', tmp_path / 'out.csv', *argv)
    assert_one_error_line(run, 'export', *fragments)


def test_a_single_cam_has_no_timing_diagram(tmp_path, capsys):
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '--timing-diagram', '-o', tmp_path / 'x.csv')
    assert_one_error_line(run, 'export', '--timing-diagram', 'one cam, not a machine file')


def test_a_machine_exports_one_cam_table_per_axis_into_a_folder(tmp_path, capsys):
    folder = tmp_path / 'tables'
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--points', 72, '-o', folder)
    assert run.code == 0 and run.err == ''
    assert sorted(path.name for path in folder.iterdir()) == [f'{name}.csv' for name in
                                                              sorted(NAMES)]
    for name, s, scale in (('feeder', feeder_s, 1.0 / MM), ('jaw', jaw_s, 1.0 / MM),
                           ('knife', KNIFE, 180.0 / np.pi)):
        assert f'wrote {folder / name}.csv: cam table of 73 points' in run.out
        with (folder / f'{name}.csv').open(newline='') as stream:  # names in a # comment
            values = np.array([row for row in csv.reader(stream) if not row[0].startswith('#')],
                              dtype=float)
        degrees = values[:, 0]  # the axis's own cam angle, not the machine's: every 5 deg
        np.testing.assert_array_equal(degrees, np.arange(73) * 5.0)
        advance = 360.0 * (degrees >= 360.0) if name == 'knife' else 0.0  # a turn per cycle
        np.testing.assert_allclose(values[:, 1], s(np.radians(degrees % 360.0)) * scale
                                   + advance, rtol=0, atol=1e-9)


def test_a_machine_table_tolerance_that_fits_no_axis_unit_is_refused_before_writing(
        tmp_path, capsys):
    folder = tmp_path / 'tables'
    run = run_cli(capsys, 'export', MACHINE, '--cam-table', '--tolerance', '1um', '-o', folder)
    assert_one_error_line(run, 'export', '--tolerance', 'for axis knife')
    assert not folder.exists()  # a format that cannot take an axis: test_machine_table_export
