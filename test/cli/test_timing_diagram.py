"""`cam_ros plot MACHINE --timing-diagram`: curves, switch bars, conflicts against references."""
from __future__ import annotations

import math

import numpy as np
import pytest
from cli_support import png_size, run_cli
from machine_support import (coupled, crossings, DEG, edited_machine, feeder_s, jaw_s, knife_s,
                             MACHINE, NAMES, reference_positions, SCAN, TWO_PI)
from matplotlib.colors import to_rgba

from cam_ros.core.machine import check_interference, load_machine
from cam_ros.output.timing_diagram import (COLLISION, DIAGRAM_SAMPLES, NEAR_MISS,
                                           timing_figure)

Q = np.linspace(0.0, TWO_PI, SCAN)
GRID_DEG = 360.0 / (DIAGRAM_SAMPLES - 1)  # the drawing's step: where a shaded edge may fall
KNIFE = knife_s()


def figure_of(path):
    """Return the timing figure of a machine file and its panels."""
    machine = load_machine(path)
    figure = timing_figure(machine, check_interference(machine), 'test')
    return figure, figure.axes


def spans(ax, colour):
    """Return the (start, end) deg of the conflicts of one colour shaded on a panel."""
    return sorted((patch.get_x(), patch.get_x() + patch.get_width()) for patch in ax.patches
                  if str(patch.get_gid()).startswith('conflict')
                  and patch.get_facecolor()[:3] == to_rgba(colour)[:3])


def test_plot_writes_the_diagram(tmp_path, capsys):
    target = tmp_path / 'machine.png'
    run = run_cli(capsys, 'plot', MACHINE, '--timing-diagram', '-o', target)
    assert run.code == 0 and run.err == ''
    assert run.out == f'wrote {target}: timing diagram of 3 axes\n'
    width, height = png_size(target.read_bytes())
    assert width >= 1200 and height >= 900


def test_each_axis_is_drawn_as_commanded_in_its_file_unit():
    _, axes = figure_of(MACHINE)
    assert [ax.get_ylabel() for ax in axes] == [
        'feeder\n(mm)', 'knife\n(deg, mod 360)', 'jaw\n(mm)', 'gap feeder-\njaw (mm)', 'switches']
    for ax, name in zip(axes, NAMES):
        (line,) = ax.get_lines()[:1]
        x, y = (np.asarray(values, dtype=float) for values in line.get_data())
        drawn = np.isfinite(x)
        theta = np.radians(x[drawn])
        expected = reference_positions(theta, KNIFE)[name]
        expected = np.degrees(np.mod(expected, TWO_PI)) if name == 'knife' else expected * 1e3
        np.testing.assert_allclose(y[drawn], expected, rtol=0.0, atol=1e-9)
        assert x[drawn][0] == 0.0 and x[drawn][-1] == pytest.approx(360.0, abs=1e-12)
    # The gap panel: 310 mm less both axes.
    x, y = axes[3].get_lines()[0].get_data()
    theta = np.radians(np.asarray(x))
    np.testing.assert_allclose(y, 310.0 - 1e3 * (feeder_s(theta) + jaw_s(theta)), rtol=0.0,
                               atol=1e-9)


def test_switch_tracks_are_bars_on_the_machine_angle():
    _, axes = figure_of(MACHINE)
    (bars,) = axes[-1].collections
    (vertices,) = [path.vertices for path in bars.get_paths()]
    assert (vertices[:, 0].min(), vertices[:, 0].max()) == pytest.approx((20.0, 60.0),
                                                                         abs=1e-12)
    assert [label.get_text() for label in axes[-1].get_yticklabels()] == ['glue']


def shifted(tmp_path, jaw_offset, min_clearance=15.0):
    def edit(parameters):
        parameters['jaw']['master'] = {'offset_deg': jaw_offset}
        parameters['interference']['min_clearance'][0] = min_clearance
    return edited_machine(tmp_path, f'jaw_{-jaw_offset:g}', edit)


def test_a_gap_below_its_limit_is_shaded_where_it_is(tmp_path):
    _, axes = figure_of(shifted(tmp_path, -100.0, 45.0))

    def short(q):
        return 0.31 - coupled(q, feeder_s) - coupled(q, jaw_s, -100.0 * DEG) - 0.045
    (starts,), (ends,) = crossings(lambda q: -short(q), Q)
    for ax in (axes[0], axes[2], axes[3]):
        ((start, end),) = [span for span in spans(ax, COLLISION) if span[1] - span[0] > 40.0]
        assert abs(start - math.degrees(starts)) <= GRID_DEG
        assert abs(end - math.degrees(ends)) <= GRID_DEG
    assert spans(axes[1], NEAR_MISS) == []
    assert 'COLLIDES' in axes[0].get_legend().get_texts()[0].get_text()


def test_a_short_margin_shades_the_min_margin_after_one_leaving(tmp_path, capsys):
    path = shifted(tmp_path, -70.0)
    _, axes = figure_of(path)
    (jaw_in,), _ = crossings(lambda q: coupled(q, jaw_s, -70.0 * DEG) - 0.06, Q)
    knife = reference_positions(Q, KNIFE)['knife']
    turn = np.flatnonzero(np.diff(np.floor(knife / TWO_PI)))[0]  # where it passes a turn
    knife_out = math.degrees(Q[turn])
    assert 0.0 < math.degrees(jaw_in) - knife_out < 20.0
    for ax in (axes[1], axes[2]):
        ((start, end),) = spans(ax, NEAR_MISS)
        assert abs(start - knife_out) <= GRID_DEG
        assert abs(end - (knife_out + 20.0)) <= GRID_DEG  # the min_margin the jaw enters in
        assert spans(ax, COLLISION) == []
    run = run_cli(capsys, 'plot', path, '--timing-diagram', '-o', tmp_path / 'near.svg')
    assert run.code == 1
    (warning,) = run.err.splitlines()
    assert warning.startswith('cam_ros plot: warning: zones jaw-knife: smallest margin ')
