"""`cam_ros report/sample/plot` on designs with follower dynamics: keys, units, exit codes."""
from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import yaml
from cli_support import CONFIG_DIR, DEFAULT_CONFIG, run_cli

H, RB, WIDTH_MM = 0.02, 0.05, 10.0  # m, m, mm
M, K, P = 1.2, 8000.0, 60.0  # kg, N/m, N
E_STAR = 207e9 / (2 * (1 - 0.3 ** 2))  # Pa, steel on steel


def cosine_cam(tmp_path, omega: float = 30.0, **extra: dict) -> str:
    """Write a flat-faced cam with lift H/2 (1 - cos theta) and an undamped spring train (mm)."""
    parameters = {
        'length_unit': 'mm', 'rotation': 'counterclockwise', 'cam_speed': omega,
        'follower': {'type': 'translating_flat', 'base_radius': RB * 1e3},
        'motion': {'laws': ['simple_harmonic', 'simple_harmonic'],
                   'start_deg': [0.0, 180.0], 'end_deg': [180.0, 360.0],
                   'start_position': [0.0, H * 1e3], 'end_position': [H * 1e3, 0.0]},
        'dynamics': {'mass': M, 'spring_rate': K, 'spring_preload': P},
        'contact': {'face_width': WIDTH_MM},
    }
    for section, values in extra.items():
        parameters.setdefault(section, {}).update(values)
    path = tmp_path / f'cosine_{omega:g}.yaml'
    path.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    return str(path)


def closed_form_force(theta: np.ndarray, omega: float) -> np.ndarray:
    """Return N = m a + k s + P of the cosine cam (a flat face: N = Q)."""
    return M * omega ** 2 * H / 2 * np.cos(theta) + K * H / 2 * (1 - np.cos(theta)) + P


def test_report_json_dynamics_keys_in_si_and_degrees(tmp_path, capsys):
    omega = 30.0
    run = run_cli(capsys, 'report', cosine_cam(tmp_path, omega), '--json')
    assert run.code == 0, run.err
    data = json.loads(run.out)
    assert data['dynamics'] is True and data['jump'] is False and data['jump_angles_deg'] == []
    amplitude = abs(M * omega ** 2 - K) * H / 2
    assert math.isclose(data['contact_force_min'], K * H / 2 + P - amplitude, rel_tol=1e-12)
    assert math.isclose(data['contact_force_max'], K * H / 2 + P + amplitude, rel_tol=1e-12)
    at = 0.0 if M * omega ** 2 < K else 180.0  # the spring dominates: least force at s = 0
    assert abs((data['contact_force_min_deg'] - at + 180.0) % 360.0 - 180.0) < 1e-6
    assert math.isclose(data['jump_speed'], math.sqrt((2 * K + 2 * P / H) / M), rel_tol=1e-12)
    peak = math.sqrt(data['contact_force_max'] / (WIDTH_MM * 1e-3) * E_STAR
                     / (math.pi * (RB + H / 2)))
    assert math.isclose(data['contact_stress_max'], peak, rel_tol=1e-12)
    assert math.isclose(data['power_max'], omega * data['camshaft_torque_max'], rel_tol=1e-15)
    for key in ('spring_preload_needed', 'camshaft_torque_rms', 'contact_stress_max_deg',
                'camshaft_torque_max_deg'):
        assert isinstance(data[key], float)


def test_report_exits_1_when_the_follower_jumps_and_says_where(tmp_path, capsys):
    omega_jump = math.sqrt((2 * K + 2 * P / H) / M)
    config = cosine_cam(tmp_path, 1.2 * omega_jump)
    run = run_cli(capsys, 'report', config, '--json')
    data = json.loads(run.out)
    assert run.code == 1 and data['jump'] is True and data['ok'] is False
    ((start, end),) = data['jump_angles_deg']
    theta = np.radians(np.linspace(0.0, 360.0, 36001))
    negative = np.degrees(theta[closed_form_force(theta, 1.2 * omega_jump) < 0.0])
    assert start < negative.min() + 0.01 and negative.max() - 0.01 < end
    assert math.isclose((start + end) / 2, 180.0, abs_tol=1e-6)  # mass dominates: about 180
    text = run_cli(capsys, 'report', config)
    assert text.code == 1 and 'LEAVES the cam' in text.out and 'VIOLATES' in text.out


def test_report_exits_1_over_the_allowable_contact_stress(tmp_path, capsys):
    config = cosine_cam(tmp_path, limits={'contact_stress': 1e8})
    data = json.loads(run_cli(capsys, 'report', config, '--json').out)
    assert data['contact_stress_ok'] is False and data['jump'] is False
    run = run_cli(capsys, 'report', config)
    assert run.code == 1 and 'limit 100 MPa: VIOLATED' in run.out


def test_text_report_has_a_dynamics_section(tmp_path, capsys):
    run = run_cli(capsys, 'report', CONFIG_DIR / 'machine_dynamics.yaml')
    assert run.code == 0, run.out
    for label in ('Dynamics', 'Contact force', 'Jump speed', 'Spring preload',
                  'Camshaft torque', 'Contact stress'):
        assert any(line.startswith(label) for line in run.out.splitlines()), label


def test_sample_columns_follow_the_closed_form(tmp_path, capsys):
    omega = 30.0
    run = run_cli(capsys, 'sample', cosine_cam(tmp_path, omega), '--step-deg', '15', '--json')
    data = json.loads(run.out)
    assert data['units']['contact_force'] == 'N'
    assert data['units']['camshaft_torque'] == 'Nm'
    assert data['units']['contact_stress'] == 'Pa'
    theta = np.array(data['angle'])
    force = closed_form_force(theta, omega)
    np.testing.assert_allclose(data['contact_force'], force, rtol=1e-12)
    np.testing.assert_allclose(data['camshaft_torque'], force * H / 2 * np.sin(theta),
                               rtol=1e-12, atol=1e-12)
    csv = run_cli(capsys, 'sample', cosine_cam(tmp_path, omega), '--csv').out.splitlines()
    assert csv[0].endswith(',contact_force_N,camshaft_torque_Nm,contact_stress_Pa')


def test_a_design_without_dynamics_has_no_dynamics_keys_or_columns(capsys):
    data = json.loads(run_cli(capsys, 'report', DEFAULT_CONFIG, '--json').out)
    assert data['dynamics'] is False and 'contact_force_min' not in data
    sample = json.loads(run_cli(capsys, 'sample', DEFAULT_CONFIG, '--json').out)
    assert 'contact_force' not in sample and 'contact_force' not in sample['units']


@pytest.mark.parametrize('section, values, fragment', [
    ('dynamics', {'mass': -2.0}, 'dynamics.mass = -2.0: must be >= 0'),
    ('contact', {'cam_poisson': 0.5}, 'contact.cam_poisson = 0.5: must be in [0, 0.5)'),
    ('contact', {'face_width': 0.0}, 'contact.face_width = 0.0: must be > 0'),
])
def test_bad_dynamics_values_are_one_line_errors(tmp_path, capsys, section, values, fragment):
    run = run_cli(capsys, 'report', cosine_cam(tmp_path, **{section: values}))
    assert run.code == 2 and run.out == ''
    assert len(run.err.splitlines()) == 1 and fragment in run.err, run.err


def test_plot_adds_geometry_and_dynamics_panels(tmp_path, capsys):
    target = tmp_path / 'machine.svg'
    assert run_cli(capsys, 'plot', CONFIG_DIR / 'machine_dynamics.yaml', '-o', target).code == 0
    text = target.read_text()
    for label in ('pressure angle (deg)', 'radius of curvature (mm)', 'contact force',
                  'spring force', 'camshaft torque (N m)', 'contact stress (MPa)', 'allowable'):
        assert label in text, label
    assert 'follower leaves the cam' not in text
    fast = tmp_path / 'fast.svg'
    run_cli(capsys, 'plot', cosine_cam(tmp_path, 1.2 * math.sqrt((2 * K + 2 * P / H) / M)),
            '-o', fast)
    assert 'follower leaves the cam' in fast.read_text()
    plain = tmp_path / 'default.svg'
    assert run_cli(capsys, 'plot', DEFAULT_CONFIG, '-o', plain).code == 0
    assert 'pressure angle (deg)' in plain.read_text()
    assert 'contact force' not in plain.read_text()


def jump_span_deg(omega: float) -> tuple[float, float]:
    """Return where the cosine cam's closed-form contact force is negative (deg)."""
    start = math.degrees(math.acos(-(K * H / 2 + P) / ((M * omega ** 2 - K) * H / 2)))
    return start, 360.0 - start


def test_every_command_fails_a_jumping_design_as_the_report_does(tmp_path, capsys):
    omega = 1.2 * math.sqrt((2 * K + 2 * P / H) / M)
    config = cosine_cam(tmp_path, omega)
    start, end = jump_span_deg(omega)
    warning = (f'the follower leaves the cam between {start:.1f} and {end:.1f} deg at '
               f'{omega:.6g} rad/s')
    data = json.loads(run_cli(capsys, 'report', config, '--json').out)
    assert data['ok'] is False and warning in data['warnings'], data['warnings']
    for argv in (['sample', config, '--json'], ['plot', config, '-o', tmp_path / 'jump.svg']):
        run = run_cli(capsys, *argv)
        assert run.code == 1, argv
        assert f'cam_ros {argv[0]}: warning: {warning}' in run.err.splitlines(), run.err


def test_every_command_fails_a_design_over_the_allowable_stress(tmp_path, capsys):
    config = cosine_cam(tmp_path, limits={'contact_stress': 1e8})
    force = K * H + P - M * 30.0 ** 2 * H / 2  # at 180 deg, where the spring is most compressed
    peak = math.sqrt(force / (WIDTH_MM * 1e-3) * E_STAR / (math.pi * (RB + H / 2)))
    warning = (f'contact stress reaches {peak / 1e6:.6g} MPa at 180.0 deg, over the '
               'allowable 100 MPa')
    assert warning in json.loads(run_cli(capsys, 'report', config, '--json').out)['warnings']
    run = run_cli(capsys, 'sample', config, '--step-deg', '30')
    assert run.code == 1 and run.err.splitlines() == [f'cam_ros sample: warning: {warning}']


def test_a_design_within_its_dynamics_limits_passes_every_command(tmp_path, capsys):
    config = cosine_cam(tmp_path, limits={'contact_stress': 1e9})
    assert json.loads(run_cli(capsys, 'report', config, '--json').out)['warnings'] == []
    run = run_cli(capsys, 'sample', config, '--step-deg', '30')
    assert run.code == 0 and run.err == ''


def test_no_cam_angle_prints_as_360_degrees(capsys):
    # The shipped example's least contact force is the preload P = 80 N on its closing dwell
    # (280-360 deg, s = 0, pressure angle 0): a refined minimum there may sit just short of 360.
    text = run_cli(capsys, 'report', CONFIG_DIR / 'machine_dynamics.yaml').out
    (line,) = [line for line in text.splitlines() if line.startswith('Contact force')]
    at = float(line.split(' at ')[1].split()[0])
    assert line.split()[3] == '80' and (at == 0.0 or 280.0 <= at < 360.0), line
    angles = [float(angle) for angle in re.findall(r' at (\S+) deg', text)]
    assert angles and max(angles) < 360.0
    data = json.loads(run_cli(capsys, 'report', CONFIG_DIR / 'machine_dynamics.yaml',
                              '--json').out)
    for key in ('contact_force_min_deg', 'contact_force_max_deg', 'camshaft_torque_max_deg',
                'contact_stress_max_deg', 'pressure_angle_max_at_deg',
                'radius_of_curvature_min_at_deg'):
        assert 0.0 <= data[key] < 360.0, (key, data[key])
