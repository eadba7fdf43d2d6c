"""`cam_ros export`: CSV, DXF and SVG round trips equal design.geometry() in millimetres."""
from __future__ import annotations

import io
import re
import sys
import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import pytest
from cli_support import (assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, follower_config,
                         FOLLOWERS, run_cli, SHIPPED_CAMS)

from cam_ros.cli import main
from cam_ros.commands.common import load_design

MM = 1000.0
CSV_TOLERANCE_MM = 1e-9  # written with 9 decimals
DXF_TOLERANCE_MM = 1e-9  # DXF stores doubles as text with enough digits
SVG_TOLERANCE_MM = 1e-6  # written with 6 decimals
DEFAULT_SAMPLES = 3600
SVG = '{http://www.w3.org/2000/svg}'


def surface(config, samples) -> np.ndarray:
    """Return the expected surface points in mm straight from the design."""
    geometry = load_design(config).geometry(samples)
    return np.column_stack((geometry.surface_x, geometry.surface_y)) * MM


def export(capsys, config, target, *extra) -> None:
    run = run_cli(capsys, 'export', config, '-o', target, *extra)
    assert run.code == 0 and run.err == '', run
    assert str(target) in run.out


def read_svg_points(path) -> tuple[np.ndarray, ET.Element]:
    root = ET.parse(path).getroot()
    element = root.find(f'.//{SVG}path')
    data = element.get('d')
    assert data.startswith('M ') and data.endswith(' Z')  # one closed path
    pairs = re.findall(r'(-?\d+\.\d+),(-?\d+\.\d+)', data)
    return np.array(pairs, dtype=float), root


def test_csv_round_trip_equals_the_geometry(tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    export(capsys, DEFAULT_CONFIG, target, '--samples', 720)
    assert target.read_text().splitlines()[0] == 'x_mm,y_mm'
    points = np.loadtxt(target, delimiter=',', skiprows=1)
    np.testing.assert_allclose(points, surface(DEFAULT_CONFIG, 720), atol=CSV_TOLERANCE_MM,
                               rtol=0)
    # Seed 000 at cam angle 0 (dwell on the base circle): the contact is on the line from the
    # roller centre (e, sqrt(Rp^2 - e^2)) to the cam centre, at the base radius, 40 mm.
    np.testing.assert_allclose(points[0], np.array([5.0, np.sqrt(50.0 ** 2 - 5.0 ** 2)]) * 0.8,
                               atol=CSV_TOLERANCE_MM)


def test_dxf_is_one_closed_polyline_in_millimetres(tmp_path, capsys):
    target = tmp_path / 'cam.dxf'
    export(capsys, DEFAULT_CONFIG, target, '--samples', 500)
    document = ezdxf.readfile(target)
    assert document.header['$INSUNITS'] == 4  # millimetres
    entities = list(document.modelspace())
    assert [entity.dxftype() for entity in entities] == ['LWPOLYLINE']
    polyline = entities[0]
    assert polyline.closed and len(polyline) == 500
    points = np.array([vertex[:2] for vertex in polyline.get_points('xy')])
    np.testing.assert_allclose(points, surface(DEFAULT_CONFIG, 500), atol=DXF_TOLERANCE_MM,
                               rtol=0)
    assert document.audit().has_errors is False


def test_svg_is_one_closed_path_with_y_up(tmp_path, capsys):
    target = tmp_path / 'cam.svg'
    export(capsys, DEFAULT_CONFIG, target, '--samples', 360)
    points, root = read_svg_points(target)
    np.testing.assert_allclose(points, surface(DEFAULT_CONFIG, 360), atol=SVG_TOLERANCE_MM,
                               rtol=0)
    assert root.find(f'.//{SVG}g').get('transform') == 'scale(1,-1)'
    assert root.get('width').endswith('mm') and root.get('height').endswith('mm')
    # The view box holds every point after the y flip.
    x0, y0, width, height = (float(value) for value in root.get('viewBox').split())
    assert x0 < points[:, 0].min() and points[:, 0].max() < x0 + width
    assert y0 < -points[:, 1].max() and -points[:, 1].min() < y0 + height


def test_default_sample_count(tmp_path, capsys):
    target = tmp_path / 'cam.csv'
    export(capsys, DEFAULT_CONFIG, target)
    assert len(target.read_text().splitlines()) == 1 + DEFAULT_SAMPLES


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
def test_every_follower_exports_a_closed_curve_around_the_cam_centre(kind, tmp_path, capsys):
    config = follower_config(tmp_path, kind)
    target = tmp_path / f'{kind}.dxf'
    export(capsys, config, target, '--samples', 360)
    polyline = next(iter(ezdxf.readfile(target).modelspace()))
    points = np.array([vertex[:2] for vertex in polyline.get_points('xy')])
    np.testing.assert_allclose(points, surface(config, 360), atol=DXF_TOLERANCE_MM, rtol=0)
    # Winding number 1 around the origin: the curve goes once around the cam centre.
    angles = np.unwrap(np.arctan2(points[:, 1], points[:, 0]))
    turn = angles[-1] - angles[0] + np.angle(complex(*points[0]) / complex(*points[-1]))
    assert abs(turn) == pytest.approx(2 * np.pi)


def expected_curves(config, samples) -> list[np.ndarray]:
    """Return the curves an export draws (mm): the surface; a groove's two flanks.

    A groove's flanks lie at w = Rr + clearance/2 either side of the pitch curve, along the
    roller's normal (pitch - surface) / Rr.
    """
    design = load_design(config)
    geometry = design.geometry(samples)
    pitch = np.column_stack((geometry.pitch_x, geometry.pitch_y)) * MM
    cam = np.column_stack((geometry.surface_x, geometry.surface_y)) * MM
    if design.config.follower.closure != 'groove':
        return [cam]
    roller = design.follower.roller_radius * MM
    normal = (pitch - cam) / roller
    half = roller + design.config.follower.groove_clearance * MM / 2
    return [pitch - half * normal, pitch + half * normal]


@pytest.mark.parametrize('suffix', ['.csv', '.dxf', '.svg'])
@pytest.mark.parametrize('config', SHIPPED_CAMS, ids=lambda path: path.name)
def test_every_shipped_config_exports(config, suffix, tmp_path, capsys):
    target = tmp_path / f'{config.stem}{suffix}'
    run = run_cli(capsys, 'export', config, '-o', target, '--samples', 400)
    assert run.code == (0 if load_design(config).ok else 1)
    expected = expected_curves(config, 400)
    if suffix == '.csv':
        values = np.loadtxt(target, delimiter=',', skiprows=1, usecols=(0, 1))
        curves = np.split(values, len(expected))
    elif suffix == '.dxf':
        polylines = list(ezdxf.readfile(target).modelspace())
        assert all(polyline.closed for polyline in polylines)
        curves = [np.array([vertex[:2] for vertex in polyline.get_points('xy')])
                  for polyline in polylines]
    else:
        root = ET.parse(target).getroot()
        curves = [np.array(re.findall(r'(-?\d+\.\d+),(-?\d+\.\d+)', path.get('d')),
                           dtype=float) for path in root.iter(f'{SVG}path')]
    assert len(curves) == len(expected)
    for points, wanted in zip(curves, expected):
        np.testing.assert_allclose(points, wanted, atol=SVG_TOLERANCE_MM, rtol=0)


@pytest.mark.parametrize('argv, fragments', [
    (['-o', 'cam.stl'], ["-o = 'cam.stl'", 'must end in .csv, .dxf, .svg']),
    (['-o', 'cam.csv', '--samples', '2'], ['--samples', "'2'", 'integer >= 3']),
    (['-o', 'cam.csv', '--samples', '1.5'], ['--samples', 'integer >= 3']),
    (['-o', '/no/such/dir/cam.dxf'], ['cannot be written']),
])
def test_bad_export_arguments_exit_2(argv, fragments, capsys):
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, *argv)
    assert_one_error_line(run, 'export', *fragments)


class Terminal(io.StringIO):
    """A stderr that claims to be a terminal."""

    def isatty(self) -> bool:
        return True


def test_progress_shows_on_a_terminal_only(tmp_path, monkeypatch):
    terminal = Terminal()
    monkeypatch.setattr(sys, 'stderr', terminal)
    assert main(['export', str(DEFAULT_CONFIG), '-o', str(tmp_path / 'cam.svg')]) == 0
    shown = terminal.getvalue()
    assert shown.startswith(f'\rcam_ros export: writing {tmp_path / "cam.svg"}')
    assert shown.endswith('\r\x1b[K')  # and cleared when done
    piped = io.StringIO()
    monkeypatch.setattr(sys, 'stderr', piped)
    assert main(['export', str(DEFAULT_CONFIG), '-o', str(tmp_path / 'cam.csv')]) == 0
    assert piped.getvalue() == ''


@pytest.mark.parametrize('options', [
    [], ['--machining', '--cutter-radius', '5', '--tolerance', '0.01']])
def test_a_motion_only_design_has_no_cam_to_export(options, tmp_path, capsys):
    target = tmp_path / 'knife.dxf'
    run = run_cli(capsys, 'export', CONFIG_DIR / 'rotary_knife.yaml', '-o', target, *options)
    assert_one_error_line(run, 'export', "follower.type = 'none'", 'motion-only design has no cam')
    assert not target.exists()
