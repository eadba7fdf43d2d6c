"""`cam_ros report` and `plot --vibration` with an elastic follower train."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml
from cli_support import (assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, load_parameters,
                         png_size, run_cli, write_config)

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


def cv_config(tmp_path):
    """The issue's case as a file: the machine cam with constant-velocity rise and return."""
    parameters = load_parameters(CONFIG_DIR / 'machine_dynamics.yaml')
    parameters['motion']['laws'] = ['constant_velocity', 'dwell', 'constant_velocity', 'dwell']
    parameters['limits'].update(allow_velocity_jumps=True, pressure_angle_deg=60.0)
    parameters['dynamics'].update(train_natural_frequency=2500.0, train_damping_ratio=0.05)
    path = tmp_path / 'cv_2500.yaml'
    path.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    return path


def test_an_unbounded_rigid_acceleration_reads_null_and_says_where(tmp_path, capsys):
    config = cv_config(tmp_path)
    vibration = json.loads(run_cli(capsys, 'report', config, '--json').out)['vibration']
    assert vibration['peak_rigid_acceleration'] is None  # JSON has no infinity
    assert vibration['peak_rigid_acceleration_unbounded_deg'] == [0.0, 100.0, 180.0, 280.0]
    assert vibration['resonance_harmonic'] is None
    # the closed form of test/core/test_periodic.py: 4.39198975584e-05 m
    assert vibration['max_output_deviation'] == pytest.approx(4.39198975584e-05, rel=1e-10)
    text = run_cli(capsys, 'report', config).out
    assert ('(rigid: unbounded, the velocity jumps at 0.0, 100.0, 180.0, 280.0 deg)' in text)
    assert 'max |x - s| 4.39199e-05 m (0.0439199 mm) at ' in text
    smooth = json.loads(run_cli(capsys, 'report', train_config(tmp_path, 6.0), '--json').out)
    assert smooth['vibration']['peak_rigid_acceleration_unbounded_deg'] == []
    assert smooth['vibration']['peak_rigid_acceleration'] == pytest.approx(
        0.02 * 2.0 * math.pi / (math.pi / 2) ** 2 * (2.0 * math.pi) ** 2)


def test_a_g_g_residual_says_it_is_of_the_law_s_amplitude(tmp_path, capsys):
    # config/flying_shear.yaml's synchronous section as a cycloidal G-G rise of 36 mm, 30 of
    # them on the 0.5 mm/deg ramp: the ratio is of the other 6 mm.
    parameters = load_parameters(CONFIG_DIR / 'flying_shear.yaml')
    parameters['motion'].update(
        laws=['poly5', 'cycloidal', 'poly5', 'cycloidal'],
        start_position=[0.0, 20.0, 56.0, 70.0], end_position=[20.0, 56.0, 70.0, 0.0],
        start_velocity=[math.nan, 0.5, math.nan, math.nan],
        end_velocity=[math.nan, 0.5, math.nan, math.nan])
    parameters['limits']['pressure_angle_deg'] = 60.0
    parameters['dynamics'] = {'train_natural_frequency': 20.0}
    config = tmp_path / 'gg.yaml'
    config.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    vibration = json.loads(run_cli(capsys, 'report', config, '--json').out)['vibration']
    [rise] = [s for s in vibration['segments'] if s['index'] == 1]
    assert rise['law_amplitude'] == pytest.approx(0.006)
    assert rise['residual_amplitude'] == pytest.approx(0.006 * rise['residual_ratio'])
    text = run_cli(capsys, 'report', config).out
    line = next(line for line in text.splitlines() if 'after segment 1:' in line)
    assert "of the law's amplitude |h - v beta| 0.006 m (6 mm)" in line
    assert 'of the stroke at' in next(line for line in text.splitlines()
                                      if 'after segment 3:' in line)


@pytest.mark.filterwarnings('error')
def test_an_undamped_train_at_resonance_is_said_unbounded(tmp_path, capsys):
    def edit(parameters):
        parameters['dynamics'] = {'train_natural_frequency': 6.0, 'train_damping_ratio': 0.0}
    config = write_config(tmp_path, 'resonant', edit)
    run = run_cli(capsys, 'report', config, '--json')
    assert run.code == 1
    vibration = json.loads(run.out)['vibration']
    assert vibration['resonance_harmonic'] == 6
    assert vibration['max_output_deviation'] is None
    assert vibration['peak_output_acceleration'] is None
    text = run_cli(capsys, 'report', config).out
    assert 'output at speed: NO steady state: harmonic 6 of the cam motion' in text
    assert 'grows without bound' in text and 'VIOLATES' in text
    target = tmp_path / 'resonant.png'
    assert run_cli(capsys, 'plot', config, '-o', target, '--vibration').code == 1
    assert target.exists()
    note = vibration_figure(load_design(config)).axes[1].texts[0].get_text()
    assert note.startswith('No steady output: the undamped follower train resonates')
