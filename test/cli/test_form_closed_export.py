"""Export of form-closed cams: both groove flanks and both conjugate cams, drawings and cutter
paths, against the pitch curve of seed 000 written out in closed form (test_machining_export).

A groove's flanks lie at w = Rr + clearance/2 on either side of the pitch curve; a cutter of
radius w cuts it in one pass along the pitch curve, a narrower one runs at w - Rc from it on
each side; the second cam of a conjugate yoke is traced by roller 2 at (e, d + s - B),
B = 2 d + s_max + s_min.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import pytest
from cli_support import (assert_one_error_line, BASE_RADIUS, OFFSET, RISE, ROLLER_RADIUS,
                         run_cli, seed_000_motion, SIGMA, write_config)
from test_machining_export import (contour_of, distance_to, MM, pitch_curve, read_gcode,
                                   ROUNDING, signed_area)

CLEARANCE = 0.2e-3  # m: 0.02 cm
HALF = ROLLER_RADIUS + CLEARANCE / 2


def closed(tmp_path, closure):
    def edit(parameters):
        parameters['follower']['closure'] = closure
        if closure == 'groove':
            parameters['follower']['groove_clearance'] = 0.02
    return write_config(tmp_path, closure, edit)


def second_pitch_curve(samples=2_000_000) -> np.ndarray:
    """Return roller 2's path on the second cam (m, cam frame)."""
    theta = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    s = seed_000_motion(theta)[0]
    d = math.sqrt((BASE_RADIUS + ROLLER_RADIUS) ** 2 - OFFSET ** 2)
    x, y = OFFSET, d + s - (2 * d + RISE)
    c, n = np.cos(theta), np.sin(SIGMA * theta)
    return np.column_stack((c * x + n * y, -n * x + c * y))


def test_a_groove_drawing_has_both_flanks_either_side_of_the_pitch_curve(tmp_path, capsys):
    target = tmp_path / 'groove.dxf'
    run = run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', target)
    assert run.code == 0, run
    document = ezdxf.readfile(target)
    flanks = {line.dxf.layer: np.array([(x, y) for x, y, *_ in line.get_points()]) * MM
              for line in document.modelspace().query('LWPOLYLINE')}
    assert set(flanks) == {'CAM_INNER', 'CAM_OUTER'}
    curve = pitch_curve()
    for points in flanks.values():
        assert distance_to(curve, points) == pytest.approx(HALF, abs=1e-9)
    middle = 0.5 * (flanks['CAM_INNER'] + flanks['CAM_OUTER'])
    assert distance_to(curve, middle).max() < 1e-9
    svg = tmp_path / 'groove.svg'
    assert run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', svg).code == 0
    ids = [path.get('id') for path in ET.parse(svg).getroot().iter(
        '{http://www.w3.org/2000/svg}path')]
    assert ids == ['cam_inner', 'cam_outer']
    table = tmp_path / 'groove.csv'
    assert run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', table).code == 0
    header, *rows = table.read_text().splitlines()
    assert header == 'x_mm,y_mm,curve'
    assert {row.rsplit(',', 1)[1] for row in rows} == {'inner', 'outer'}


def test_a_cutter_of_the_groove_width_runs_once_along_the_pitch_curve(tmp_path, capsys):
    target = tmp_path / 'groove.nc'
    run = run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', target, '--machining',
                  '--cutter-radius', f'{HALF / 0.01!r}', '--tolerance', '0.001')
    assert run.code == 0, run
    _, points, text = read_gcode(target)
    path = contour_of(points)
    assert distance_to(pitch_curve(), path).max() <= ROUNDING
    middles = 0.5 * (path[1:] + path[:-1])
    assert distance_to(pitch_curve(), middles).max() <= 0.01 * MM
    assert '(' not in text.split('G90')[1]  # one contour, no titles


def test_a_narrower_cutter_runs_along_each_flank(tmp_path, capsys):
    target = tmp_path / 'groove.nc'
    cutter = 0.4e-2  # m
    run = run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', target, '--machining',
                  '--cutter-radius', '0.4', '--tolerance', '0.001')
    assert run.code == 0, run
    lines, points, text = read_gcode(target)
    assert '(INNER FLANK)' in text and '(OUTER FLANK)' in text
    moves = [line for line in lines if line.command in (('G', 0), ('G', 1))]
    starts = [i for i, line in enumerate(moves) if line.command == ('G', 0)]
    assert len(starts) == 2
    inner, outer = points[starts[0] + 1:starts[1] - 1], points[starts[1] + 1:-1]
    curve = pitch_curve()
    for path in inner, outer:
        assert np.abs(distance_to(curve, path) - (HALF - cutter)).max() <= ROUNDING
        middles = 0.5 * (path[1:] + path[:-1])
        assert np.abs(distance_to(curve, middles) - (HALF - cutter)).max() <= 0.01 * MM
    # the inner flank's path encloses the cam, the outer one's the groove's outside: the cutter
    # keeps to the left of its path (climb milling with M3)
    assert signed_area(inner) < 0 < signed_area(outer)
    assert np.hypot(*inner[0]) < np.hypot(*outer[0])
    # both lead in from the middle of the groove (the first point and its lead each rounded)
    assert distance_to(curve, points[[starts[0], starts[1]]]).max() <= 2 * ROUNDING


def test_a_cutter_wider_than_the_groove_is_refused(tmp_path, capsys):
    target = tmp_path / 'groove.nc'
    run = run_cli(capsys, 'export', closed(tmp_path, 'groove'), '-o', target, '--machining',
                  '--cutter-radius', '1.02', '--tolerance', '0.001')
    assert_one_error_line(run, 'export', "--cutter-radius = '1.02'", 'wider than the groove',
                          'at most half its width, 1.01 cm')
    assert not target.exists()


def test_conjugate_cams_are_drawn_and_cut_each_on_its_roller(tmp_path, capsys):
    config = closed(tmp_path, 'conjugate')
    drawing = tmp_path / 'pair.dxf'
    assert run_cli(capsys, 'export', config, '-o', drawing).code == 0
    layers = {line.dxf.layer: np.array([(x, y) for x, y, *_ in line.get_points()]) * MM
              for line in ezdxf.readfile(drawing).modelspace().query('LWPOLYLINE')}
    assert set(layers) == {'CAM_FIRST', 'CAM_SECOND'}
    first = distance_to(pitch_curve(), layers['CAM_FIRST'])
    assert first == pytest.approx(ROLLER_RADIUS, abs=1e-9)
    assert distance_to(second_pitch_curve(), layers['CAM_SECOND']) == pytest.approx(
        ROLLER_RADIUS, abs=1e-9)
    target = tmp_path / 'pair.nc'
    run = run_cli(capsys, 'export', config, '-o', target, '--machining', '--cutter-radius',
                  '1.0', '--tolerance', '0.001')
    assert run.code == 0, run
    _, points, text = read_gcode(target)
    assert '(FIRST CAM)' in text and '(SECOND CAM)' in text
    curves = (pitch_curve(), second_pitch_curve())
    on = [min(distance_to(curve, points[1:-1])) for curve in curves]
    assert max(on) <= ROUNDING  # each cam's cutter path is its roller's pitch curve
    near = np.minimum(distance_to(curves[0], points), distance_to(curves[1], points))
    approach = near > ROUNDING
    assert np.count_nonzero(approach) == 4  # the two lead-ins and the two exits
