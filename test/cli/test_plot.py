"""`cam_ros plot`: valid PNG/SVG files, and a drawing whose follower really touches the cam."""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from cli_support import (assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, follower_config,
                         FOLLOWERS, png_size, run_cli, SHIPPED_CONFIGS, write_config)

from cam_ros.commands.common import load_design
from cam_ros.output.plot import _follower_lines, _rotation, design_figure, DPI, FIGURE_SIZE_IN

DRAWING_TOLERANCE_MM = 1e-9
ANGLES_DEG = (0.0, 45.0, 130.0, 200.0, 300.0)
DENSE_SAMPLES = 3600  # a multiple of 360: the drawn angles are among the samples
SAMPLE_GAP_MM = 1e-6


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return the z component of the cross product of 2-D vectors (arrays of shape (2, ...))."""
    return a[0] * b[1] - a[1] * b[0]


def test_png_has_the_documented_size(tmp_path, capsys):
    target = tmp_path / 'cam.png'
    run = run_cli(capsys, 'plot', DEFAULT_CONFIG, '-o', target, '--angle-deg', 130)
    assert run.code == 0 and run.err == '' and str(target) in run.out
    width, height = png_size(target.read_bytes())
    assert (width, height) == (FIGURE_SIZE_IN[0] * DPI, FIGURE_SIZE_IN[1] * DPI)


def test_svg_holds_the_diagrams_and_the_drawing(tmp_path, capsys):
    target = tmp_path / 'cam.svg'
    assert run_cli(capsys, 'plot', DEFAULT_CONFIG, '-o', target).code == 0
    root = ET.parse(target).getroot()
    assert root.tag == '{http://www.w3.org/2000/svg}svg'
    text = target.read_text()
    for label in ('position (cm)', 'velocity (cm/s)', 'jerk', 'cam angle (deg)', 'cam surface',
                  'pitch curve', 'base circle', 'follower'):
        assert label in text, label


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
@pytest.mark.parametrize('angle_deg', ANGLES_DEG)
def test_drawn_follower_touches_the_cam_where_the_geometry_says(kind, angle_deg, tmp_path):
    design = load_design(follower_config(tmp_path, kind))
    angle = math.radians(angle_deg)
    sigma = -1.0 if design.clockwise else 1.0
    lines = _follower_lines(design, angle, _rotation(sigma * angle))
    follower = design.follower
    # Independent of the drawing code: the contact point of the cam frame, turned by the cam.
    geometry = design.geometry(360)
    index = int(round(angle_deg))
    turned = _rotation(sigma * angle) @ np.array(
        [geometry.surface_x[index], geometry.surface_y[index]]) * 1000.0
    np.testing.assert_allclose(lines['contact'], turned, atol=DRAWING_TOLERANCE_MM)
    if 'roller' in lines:
        centre, radius = lines['roller']
        assert np.hypot(*(lines['contact'] - centre)) == pytest.approx(radius)
    else:
        start, end = lines['face'].T
        # The contact lies on the drawn face segment.
        assert abs(cross(end - start, lines['contact'] - start)) / np.hypot(*(end - start)) \
            == pytest.approx(0.0, abs=DRAWING_TOLERANCE_MM)
        along = np.dot(lines['contact'] - start, end - start) / np.dot(end - start, end - start)
        assert 0.0 < along < 1.0
    if kind.startswith('oscillating'):
        pivot = np.array([0.0, follower.pivot_distance * 1000.0])
        np.testing.assert_allclose(lines['pivot'], pivot)
        if kind == 'oscillating_roller':
            assert np.hypot(*(lines['roller'][0] - pivot)) == pytest.approx(
                follower.arm_length * 1000.0)
        else:  # the face is at face_offset from the pivot
            start, end = lines['face'].T
            distance = abs(cross(end - start, pivot - start)) / np.hypot(*(end - start))
            assert distance == pytest.approx(abs(follower.face_offset) * 1000.0)
    if kind == 'translating_roller':
        assert lines['roller'][0][0] == pytest.approx(follower.offset * 1000.0)
    if kind == 'translating_flat':  # the face stays horizontal
        start, end = lines['face'].T
        assert start[1] == pytest.approx(end[1])


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
@pytest.mark.parametrize('angle_deg', ANGLES_DEG)
def test_drawn_follower_never_cuts_into_the_drawn_cam(kind, angle_deg, tmp_path):
    design = load_design(follower_config(tmp_path, kind))
    assert design.check.ok  # no undercut: the follower touches the cam from outside
    angle = math.radians(angle_deg)
    turn = _rotation((-1.0 if design.clockwise else 1.0) * angle)
    lines = _follower_lines(design, angle, turn)
    geometry = design.geometry(DENSE_SAMPLES)
    surface = turn @ np.array([geometry.surface_x, geometry.surface_y]) * 1000.0
    if 'roller' in lines:
        centre, radius = lines['roller']
        gap = np.hypot(*(surface - centre[:, None])) - radius
    else:
        start, end = lines['face'].T
        side = cross(end - start, -start)  # the cam centre's side of the face line
        gap = np.sign(side) * cross(end - start, surface - start[:, None]) \
            / np.hypot(*(end - start))
    assert gap.min() >= -DRAWING_TOLERANCE_MM
    assert gap.min() <= SAMPLE_GAP_MM  # and it touches


@pytest.mark.parametrize('config', SHIPPED_CONFIGS, ids=lambda path: path.name)
def test_every_shipped_config_plots(config, tmp_path, capsys):
    target = tmp_path / f'{config.stem}.png'
    run = run_cli(capsys, 'plot', config, '-o', target, '--angle-deg', 100)
    design = load_design(config)
    assert run.code == (0 if design.ok else 1)
    width = FIGURE_SIZE_IN[0] / (3 if design.follower is None else 1)  # no cam: diagrams only
    assert png_size(target.read_bytes()) == (round(width * DPI), FIGURE_SIZE_IN[1] * DPI)


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
def test_every_follower_plots(kind, tmp_path, capsys):
    target = tmp_path / f'{kind}.png'
    assert run_cli(capsys, 'plot', follower_config(tmp_path, kind), '-o', target).code == 0
    assert png_size(target.read_bytes())


@pytest.mark.parametrize('argv, fragments', [
    (['-o', 'cam.pdf'], ["-o = 'cam.pdf'", 'must end in .png, .svg']),
    (['-o', 'cam.png', '--angle-deg', 'inf'], ['--angle-deg', 'finite']),
    ([], ['required: -o/--output']),
    (['-o', '/no/such/dir/cam.png'], ['cannot be written']),
])
def test_bad_plot_arguments_exit_2(argv, fragments, capsys):
    assert_one_error_line(run_cli(capsys, 'plot', DEFAULT_CONFIG, *argv), 'plot', *fragments)


def test_svaj_are_in_the_config_unit_with_joints_named_and_a_velocity_jump_drawn_as_one(
        tmp_path):
    # Dwell, then constant velocity from 90 deg: ds/dtheta jumps from 0 to 2 cm / (pi/2) there.
    def edit(parameters):
        motion = parameters['motion']
        motion['laws'] = ['dwell', 'constant_velocity', 'dwell', 'cycloidal']
        parameters['limits']['allow_velocity_jumps'] = True
    design = load_design(write_config(tmp_path, 'jump', edit))
    figure = design_figure(design)
    position, velocity, acceleration, jerk = figure.axes[:4]
    assert position.get_ylabel() == 'position (cm)' and velocity.get_ylabel() == 'velocity (cm/s)'
    labels = [text.get_text() for text in position.texts]
    assert labels == ['dwell', 'constant_velocity', 'dwell', 'cycloidal']
    # The plotted velocity steps at 90 deg from 0 to omega * 2 cm / 90 deg, in cm/s, between
    # two neighbouring floats of angle: drawn vertical, not as a slope between grid samples.
    x, v = velocity.lines[0].get_data()
    at = np.flatnonzero(np.isclose(x, 90.0, rtol=0.0, atol=1e-9))
    assert len(at) == 2 and at[1] == at[0] + 1
    omega = design.config.cam_speed
    assert v[at].tolist() == pytest.approx([0.0, omega * 2.0 / (math.pi / 2.0)], abs=1e-9)

    def marks(ax, name):
        return [line.get_xdata()[0] for line in ax.lines if line.get_gid() == f'{name} jump']

    # Constant velocity starts and ends with a velocity jump; the cycloidal return meets its
    # dwells with zero acceleration, so no acceleration jump is marked on the jerk diagram.
    assert marks(acceleration, 'velocity') == pytest.approx([90.0, 180.0])
    assert marks(jerk, 'acceleration') == []


def test_the_follower_of_a_polydyne_cam_is_drawn_on_the_compensated_cam():
    design = load_design(CONFIG_DIR / 'polydyne.yaml')
    angle = math.radians(50.0)  # mid-rise, where the train's deflection y - s is largest
    lines = _follower_lines(design, angle, _rotation(angle))  # counter-clockwise
    geometry = design.geometry(360)
    contact = _rotation(angle) @ np.array([geometry.surface_x[50], geometry.surface_y[50]])
    np.testing.assert_allclose(lines['contact'], contact * 1000.0, atol=DRAWING_TOLERANCE_MM)
    lift = design.surface.evaluate(angle).s - design.program.evaluate(angle).s
    assert abs(lift) > 1e-4  # m: the drawing would miss the cam if it used s
