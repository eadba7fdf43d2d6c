"""`cam_ros report` and `plot --vibration` with an elastic follower train."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cli_support import (assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, png_size, run_cli,
                         write_config)

from cam_ros.commands.common import load_design
from cam_ros.output.plot import DPI
from cam_ros.output.vibration_plot import FIGURE_SIZE_IN, vibration_figure

KEYS = {'natural_frequency_hz', 'frequency_ratio', 'rigid_ok', 'segments', 'max_output_deviation',
        'peak_output_acceleration'}


def train_config(tmp_path, frequency: float):
    """Seed 000 (cycloidal rise over 90 deg, harmonic return over 120 deg at 1 rev/s), a train."""
    def edit(parameters):
        parameters['dynamics'] = {'train_natural_frequency': frequency}
    return write_config(tmp_path, f'train_{frequency:g}', edit)


def test_report_json_has_the_vibration_figures_in_si(tmp_path, capsys):
    run = run_cli(capsys, 'report', train_config(tmp_path, 6.0), '--json')
    assert run.err == ''
    vibration = json.loads(run.out)['vibration']
    assert KEYS <= set(vibration)
    assert vibration['natural_frequency_hz'] == 6.0 and vibration['frequency_ratio'] == 6.0
    assert vibration['rigid_ok'] is False
    rise, fall = vibration['segments']
    # r = T fn: 0.25 s x 6 Hz and 1/3 s x 6 Hz; closed forms of the cycloidal and harmonic laws.
    assert (rise['index'], rise['r'], fall['index'], fall['r']) == (1, 1.5, 3, pytest.approx(2.0))
    assert rise['residual_ratio'] == pytest.approx(1.0 / (1.5 * math.pi * 1.25), abs=1e-12)
    assert fall['residual_ratio'] == pytest.approx(1.0 / 15.0, abs=1e-12)
    assert rise['residual_amplitude'] == pytest.approx(0.02 * rise['residual_ratio'])
    assert vibration['peak_output_acceleration'] > vibration['peak_rigid_acceleration']
    assert json.loads(run_cli(capsys, 'report', DEFAULT_CONFIG, '--json').out)['vibration'] \
        is None


def test_report_text_says_when_the_rigid_model_does_not_hold(tmp_path, capsys):
    run = run_cli(capsys, 'report', train_config(tmp_path, 6.0))
    assert run.code == 0  # a warning, not a violated limit
    assert 'Vibration' in run.out and 'UNDER the 10 x VDI 2149' in run.out
    assert 'after segment 1: residual 0.00339531 m' in run.out
    stiff = run_cli(capsys, 'report', train_config(tmp_path, 60.0)).out
    assert 'rigid model holds' in stiff and 'VDI 2149 asks' not in stiff


def test_report_says_the_cam_is_compensated_and_its_output_is_the_motion(capsys):
    run = run_cli(capsys, 'report', CONFIG_DIR / 'polydyne.yaml', '--json')
    assert run.code == 0 and run.err == ''
    vibration = json.loads(run.out)['vibration']
    assert vibration['compensated'] is True
    assert vibration['max_output_deviation'] <= 1e-9 * 0.025  # of the 25 mm stroke
    text = run_cli(capsys, 'report', CONFIG_DIR / 'polydyne.yaml').out
    assert 'cam compensated for the train at 47.1239 rad/s (polydyne)' in text
    assert 'at this speed only' in text


def test_plot_vibration_draws_closed_form_spectra_and_the_design_s_points(tmp_path, capsys):
    config = train_config(tmp_path, 6.0)
    target = tmp_path / 'vibration.png'
    run = run_cli(capsys, 'plot', config, '-o', target, '--vibration')
    assert run.code == 0 and str(target) in run.out
    assert png_size(target.read_bytes()) == (FIGURE_SIZE_IN[0] * DPI, FIGURE_SIZE_IN[1] * DPI)
    spectrum, output = vibration_figure(load_design(config)).axes[:2]
    cycloidal, harmonic = spectrum.get_lines()[0::2]
    r = cycloidal.get_xdata()
    assert (r[0], r[-1]) == (0.5, 10.0)
    for line, closed_form, poles in (
            (cycloidal, lambda r: np.abs(np.sin(np.pi * r)) / (np.pi * r * np.abs(1 - r ** 2)), 1),
            (harmonic, lambda r: np.abs(np.cos(np.pi * r)) / np.abs(1 - 4 * r ** 2), 2)):
        away = np.abs(poles * r - np.round(poles * r)) > 1e-3  # removable singularities
        np.testing.assert_allclose(line.get_ydata()[away],
                                   np.maximum(closed_form(r[away]), 1e-12), atol=1e-12)
    points = [line for line in spectrum.get_lines() if line.get_gid() == 'operating point']
    report = json.loads(run_cli(capsys, 'report', config, '--json').out)['vibration']
    assert [(float(p.get_xdata()[0]), float(p.get_ydata()[0])) for p in points] == [
        pytest.approx((s['r'], s['residual_ratio'])) for s in report['segments']]
    designed, x = output.get_lines()[:2]
    deviation = np.max(np.abs(x.get_ydata() - designed.get_ydata())) / 100.0  # cm -> m
    assert deviation == pytest.approx(report['max_output_deviation'], rel=1e-3)
    assert deviation <= report['max_output_deviation']  # the report's is refined, never less


def test_plot_vibration_without_a_train_is_one_clear_error(tmp_path, capsys):
    target = tmp_path / 'none.png'
    run = run_cli(capsys, 'plot', DEFAULT_CONFIG, '-o', target, '--vibration')
    assert_one_error_line(run, 'plot', '--vibration', 'dynamics.train_natural_frequency')
    assert not target.exists()
