"""`cam_ros export --machining`: G-code read back with an independent parser (gcodeparser), every
point and chord midpoint against the exact curve written out in closed form here.

References: with the cutter radius equal to the roller's, the cutter path of seed 000's cam is
its pitch curve, Rot(-sigma theta) (e, d + s(theta)) in the cam frame; the nominal contour lies
at the roller radius from that pitch curve; a translating flat face on a full-turn simple
harmonic motion rides an eccentric circle (the Scotch yoke).
"""
from __future__ import annotations

import math
import re

import ezdxf
import numpy as np
import pytest
from cli_support import (assert_one_error_line, BASE_RADIUS, CM, DEFAULT_CONFIG, OFFSET,
                         ROLLER_RADIUS, run_cli, seed_000_motion, seed_000_roller, SIGMA,
                         write_config)
from gcodeparser import parse_gcode_lines
from scipy.spatial import cKDTree

MM = 1e-3
ROUNDING = math.sqrt(2) * 0.5e-4 * MM  # m: G-code coordinates to 4 decimals of mm
TOLERANCE_CM = '0.001'  # 0.01 mm


def pitch_curve(samples=2_000_000) -> np.ndarray:
    """Return seed 000's pitch curve (m, cam frame) as (samples, 2), densely."""
    theta = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    s = seed_000_motion(theta)[0]
    d = math.sqrt((BASE_RADIUS + ROLLER_RADIUS) ** 2 - OFFSET ** 2)
    x, y = OFFSET, d + s
    c, n = np.cos(theta), np.sin(SIGMA * theta)
    return np.column_stack((c * x + n * y, -n * x + c * y))


def distance_to(curve: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Return the distance of points to the closed polyline through curve's samples."""
    _, nearest = cKDTree(curve).query(points)
    best = np.full(len(points), np.inf)
    for step in (-1, 0):  # the segments before and after the nearest vertex
        a = curve[(nearest + step) % len(curve)]
        b = curve[(nearest + step + 1) % len(curve)]
        along = np.clip(np.sum((points - a) * (b - a), axis=1) / np.sum((b - a) ** 2, axis=1),
                        0, 1)
        best = np.minimum(best, np.hypot(*(points - a - along[:, None] * (b - a)).T))
    return best


def read_gcode(path) -> tuple[list, np.ndarray, list[str]]:
    """Return the parsed lines, the G1 contour points (m) and the comment-free words."""
    text = path.read_text()
    lines = list(parse_gcode_lines(text))
    moves = [line for line in lines if line.command in (('G', 0), ('G', 1))]
    points = np.array([(line.params['X'], line.params['Y']) for line in moves]) * MM
    return lines, points, text


def contour_of(points: np.ndarray) -> np.ndarray:
    """Return the contour of a program's moves: without the approach and the exit (G0 / last)."""
    return points[1:-1]  # approach (G0), contour closed back on its first point, exit


def signed_area(points: np.ndarray) -> float:
    x, y = points.T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def export(capsys, target, *options, config=DEFAULT_CONFIG):
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--tolerance',
                  TOLERANCE_CM, *options)
    assert run.code == 0 and run.err == '', run
    return run


def test_cutter_path_of_the_roller_size_is_the_pitch_curve_within_the_tolerance(tmp_path, capsys):
    target = tmp_path / 'cam.nc'
    run = export(capsys, target, '--cutter-radius', '1.0')
    lines, points, text = read_gcode(target)
    commands = [line.command for line in lines]
    assert commands[:3] == [('G', 21), ('G', 17), ('G', 90)]
    assert commands[-1] == ('M', 30) and ('G', 41) not in commands
    assert '(CUTTER RADIUS 10.0000 MM)' in text and '(CHORDAL TOLERANCE 0.0100 MM' in text
    contour = contour_of(points)
    assert np.array_equal(contour[0], contour[-1])  # one closed contour
    curve = pitch_curve()
    on = distance_to(curve, contour)
    assert on.max() <= ROUNDING
    middles = 0.5 * (contour[1:] + contour[:-1])
    off = distance_to(curve, middles)
    stated = float(text.split('WORST DEVIATION ')[1].split(' MM')[0]) * MM
    assert off.max() <= 0.01 * MM
    assert off.max() <= stated  # the stated worst is never below what a chord shows
    assert off.max() > 0.3 * 0.01 * MM  # and the points are not wastefully dense
    assert signed_area(contour) < 0  # clockwise: climb milling outside with M3
    assert f'of {len(contour) - 1} points' in run.out
    for line in text.splitlines():  # ISO comments: one pair of parentheses, no words in them
        assert line == '%' or re.fullmatch(r'\([^()]*\)', line) or re.fullmatch(
            r'([GMXYD]-?\d+(\.\d+)? ?)+', line), line


@pytest.mark.parametrize('side, code, turning', [('left', 41, -1), ('right', 42, 1)])
def test_compensation_writes_the_nominal_contour_with_g41_or_g42(side, code, turning, tmp_path,
                                                                 capsys):
    target = tmp_path / 'cam.nc'
    export(capsys, target, '--cutter-radius', '0.5', '--compensation', side)
    lines, points, text = read_gcode(target)
    on = [line for line in lines if line.command == ('G', code)]
    assert len(on) == 1 and on[0].params == {'D': 1}
    assert [line.command for line in lines].count(('G', 40)) == 1
    assert '(SET D1 = CUTTER RADIUS 5.0000 MM)' in text
    contour = contour_of(points)
    # the cam surface lies at the roller radius inside the pitch curve
    gap = distance_to(pitch_curve(), contour) - ROLLER_RADIUS
    assert np.abs(gap).max() <= ROUNDING
    middles = 0.5 * (contour[1:] + contour[:-1])
    assert np.abs(distance_to(pitch_curve(), middles) - ROLLER_RADIUS).max() <= 0.01 * MM
    assert np.sign(signed_area(contour)) == turning
    approach = points[0]
    assert np.hypot(*(approach - contour[0])) == pytest.approx(2 * 5 * MM, abs=2 * ROUNDING)


def test_csv_is_the_nominal_contour_with_unit_normals(tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    export(capsys, target, '--format', 'csv')
    header, *rows = target.read_text().splitlines()
    assert header == 'x_mm,y_mm,nx,ny'
    values = np.array([[float(cell) for cell in row.split(',')] for row in rows])
    points, normals = values[:, :2] * MM, values[:, 2:]
    assert np.hypot(*normals.T) == pytest.approx(1.0, abs=1e-8)
    # normal = from the surface point out to the roller centre on the pitch curve
    centres = points + ROLLER_RADIUS * normals
    assert distance_to(pitch_curve(), centres).max() <= 2 * ROUNDING


def test_dxf_holds_the_same_path_as_the_gcode(tmp_path, capsys):
    export(capsys, tmp_path / 'cam.nc', '--cutter-radius', '1.0')
    export(capsys, tmp_path / 'cam.dxf', '--cutter-radius', '1.0', '--format', 'dxf')
    document = ezdxf.readfile(tmp_path / 'cam.dxf')
    assert document.header['$INSUNITS'] == 4
    (polyline,) = document.modelspace().query('LWPOLYLINE')
    assert polyline.closed and polyline.dxf.layer == 'CUTTER_PATH'
    points = np.array([(x, y) for x, y, *_ in polyline.get_points()]) * MM
    assert points == pytest.approx(contour_of(read_gcode(tmp_path / 'cam.nc')[1])[:-1],
                                   abs=1e-12)


def scotch_yoke(tmp_path, length_unit='mm'):
    """A translating flat face on a full-turn simple harmonic motion: an eccentric circle."""
    factor = {'mm': 1.0, 'in': 1 / 25.4}[length_unit]

    def edit(parameters):
        parameters['length_unit'] = length_unit
        parameters['follower'] = {'type': 'translating_flat', 'base_radius': 40.0 * factor}
        parameters['motion'] = {'laws': ['simple_harmonic', 'simple_harmonic'],
                                'start_deg': [0.0, 180.0], 'end_deg': [180.0, 360.0],
                                'start_position': [0.0, 20.0 * factor],
                                'end_position': [20.0 * factor, 0.0]}
        parameters['limits'] = {'min_radius_of_curvature': 0.0}
    return write_config(tmp_path, f'yoke_{length_unit}', edit)


def test_inch_configs_get_g20_and_the_eccentric_circle(tmp_path, capsys):
    config = scotch_yoke(tmp_path, 'in')
    target = tmp_path / 'yoke.nc'
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--cutter-radius',
                  '0.25', '--tolerance', '0.0004')
    assert run.code == 0, run
    lines, points, text = read_gcode(target)
    assert lines[0].command == ('G', 20) and 'CUTTER RADIUS 0.25000 IN' in text
    contour = contour_of(points) / MM * 0.0254  # inch -> m
    radius = (40 + 10) * MM + 0.25 * 0.0254
    centre = np.array([0.0, -10 * MM])
    rounding = math.sqrt(2) * 0.5e-5 * 0.0254
    assert np.abs(np.hypot(*(contour - centre).T) - radius).max() <= rounding
    middles = 0.5 * (contour[1:] + contour[:-1])
    sagitta = radius - np.hypot(*(middles - centre).T)
    assert sagitta.max() <= 0.0004 * 0.0254 + rounding


def test_a_cutter_larger_than_a_concave_radius_is_refused(tmp_path, capsys):
    config = write_config(tmp_path, 'small', lambda p: p['follower'].update(base_radius=1.5))
    theta = np.linspace(0.0, 2 * math.pi, 720_000, endpoint=False)
    rho = seed_000_roller(theta, base_radius=1.5 * CM)[1]
    concave = -rho[rho < 0].max()  # smallest concave radius of the surface, m
    assert concave > 0
    target = tmp_path / 'small.nc'
    too_big = f'{concave / CM * (1 + 1e-6):.9f}'
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--cutter-radius',
                  too_big, '--tolerance', TOLERANCE_CM)
    assert_one_error_line(run, 'export', f"--cutter-radius = '{too_big}'",
                          'smallest concave radius of the cam surface', ' cm at cam angle',
                          ' deg: the cutter would gouge it')
    assert not target.exists()
    fits = f'{concave / CM * (1 - 1e-6):.9f}'
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--cutter-radius',
                  fits, '--tolerance', TOLERANCE_CM)
    assert target.exists() and run.code in (0, 1)  # 1: the small cam breaks its limits


@pytest.mark.parametrize('options, fragments', [
    (['--machining', '--cutter-radius', '0.5'], ['--tolerance = None', 'required']),
    (['--machining', '--tolerance', '0.001'], ['--cutter-radius = None', 'required',
                                               'gcode']),
    (['--machining', '--tolerance', '0.001', '--format', 'sew'], ["--format = 'sew'",
                                                                  'gcode, csv, dxf']),
    (['--machining', '--tolerance', '0.001', '--format', 'csv', '--compensation', 'left'],
     ['--compensation', 'gcode']),
    (['--machining', '--cam-table'], ['--machining', '--cam-table']),
    (['--machining', '--tolerance', '0', '--cutter-radius', '1'], ['--tolerance', '> 0']),
    (['--machining', '--tolerance', '1e-6', '--cutter-radius', '1'],
     ["--tolerance = '1e-6'", '10 x the output resolution 1e-05 cm']),
    (['--machining', '--tolerance', '0.001', '--cutter-radius', '-1'],
     ["--cutter-radius = '-1'", '> 0']),
    (['--cutter-radius', '1'], ['--cutter-radius', 'add --machining']),
    (['--machining', '--tolerance', '0.001', '--cutter-radius', '1', '--derivatives'],
     ['--derivatives', 'cam tables only']),
])
def test_bad_machining_input_exits_2_and_writes_nothing(options, fragments, tmp_path, capsys):
    target = tmp_path / 'cam.nc'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, *options)
    assert_one_error_line(run, 'export', *fragments)
    assert not target.exists()


def arc_samples(lines, count=200) -> tuple[np.ndarray, list[float]]:
    """Return points along every G2/G3 move (m) and each arc's radius mismatch (m).

    The arcs are read back as the control would: centre = start + (I, J), G2 clockwise, G3
    counter-clockwise from the start to the end point.
    """
    samples, mismatch, position = [], [], None
    for line in lines:
        if line.command in (('G', 0), ('G', 1)):
            position = np.array((line.params['X'], line.params['Y'])) * MM
        elif line.command in (('G', 2), ('G', 3)):
            end = np.array((line.params['X'], line.params['Y'])) * MM
            centre = position + np.array((line.params['I'], line.params['J'])) * MM
            radius = np.hypot(*(position - centre))
            mismatch.append(abs(np.hypot(*(end - centre)) - radius))
            start_angle = math.atan2(*(position - centre)[::-1])
            sweep = math.atan2(*(end - centre)[::-1]) - start_angle
            sweep = sweep % (2 * math.pi) if line.command == ('G', 3) else \
                -((-sweep) % (2 * math.pi))
            angles = start_angle + sweep * np.linspace(0.0, 1.0, count)
            samples.append(centre + radius * np.column_stack((np.cos(angles), np.sin(angles))))
            position = end
    return np.concatenate(samples), mismatch


def test_arcs_stay_within_the_tolerance_of_the_exact_path(tmp_path, capsys):
    target = tmp_path / 'arcs.nc'
    run = export(capsys, target, '--cutter-radius', '1.0', '--arcs')
    assert 'arcs in' in run.out
    lines, points, text = read_gcode(target)
    arcs = [line for line in lines if line.command in (('G', 2), ('G', 3))]
    assert 3 <= len(arcs) < 60  # far fewer moves than the 200-odd chords
    along, mismatch = arc_samples(lines)
    off = distance_to(pitch_curve(), along)
    stated = float(text.split('WORST DEVIATION ')[1].split(' MM')[0]) * MM
    assert off.max() <= 0.01 * MM and max(mismatch) <= 0.01 * MM
    assert off.max() <= stated


def test_an_eccentric_circle_becomes_a_few_arcs_of_its_radius(tmp_path, capsys):
    config = scotch_yoke(tmp_path, 'mm')
    target = tmp_path / 'yoke.nc'
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--cutter-radius',
                  '6', '--tolerance', '0.01', '--arcs')
    assert run.code == 0, run
    lines, _, _ = read_gcode(target)
    arcs = [line for line in lines if line.command in (('G', 2), ('G', 3))]
    assert len(arcs) in (3, 4) and all(line.command == ('G', 2) for line in arcs)  # clockwise
    along, mismatch = arc_samples(lines)
    radius, centre = (50 + 6) * MM, np.array([0.0, -10 * MM])
    assert np.abs(np.hypot(*(along - centre).T) - radius).max() <= 0.01 * MM
    for line in arcs:
        assert math.hypot(line.params['I'], line.params['J']) == pytest.approx(56.0, abs=2e-4)


def test_arcs_are_for_gcode_only(tmp_path, capsys):
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', tmp_path / 'cam.csv', '--machining',
                  '--tolerance', '0.001', '--format', 'csv', '--arcs')
    assert_one_error_line(run, 'export', '--arcs = True', 'applies to --format gcode')


def test_printed_worst_deviation_is_rounded_up(tmp_path, capsys, monkeypatch):
    """A worst deviation of 0.1234564 mm prints as 0.123457 (to nearest it would read 0.123456,
    below the truth)."""
    import dataclasses

    from cam_ros.commands import machining

    real = machining.lines_only

    def worst_of_0_1234564_mm(path):
        return dataclasses.replace(real(path), worst_deviation=0.1234564 * MM)

    monkeypatch.setattr(machining, 'lines_only', worst_of_0_1234564_mm)
    run = export(capsys, tmp_path / 'cam.csv', '--format', 'csv')
    assert 'worst deviation 0.123457 mm within 0.01 mm' in run.out, run.out
