"""`cam_ros report`: values against independent closed forms, exit codes, invalid configs."""
from __future__ import annotations

import contextlib
import io
import json
import math

import numpy as np
import pytest
from cli_support import (assert_one_error_line, BASE_RADIUS, CM, DEFAULT_CONFIG, follower_config,
                         FOLLOWERS, load_parameters, MIN_RADIUS, OMEGA, PRESSURE_LIMIT_DEG,
                         RETURN_SPAN, RISE, RISE_SPAN, ROLLER_RADIUS, run_cli, seed_000_motion,
                         seed_000_roller, SHIPPED_CONFIGS, write_config)

from cam_ros.cli import main

#: Dense grid of the independent references (the report samples 7200 angles per turn).
REFERENCE_SAMPLES = 720_000
#: The report refines its extremes between its 0.05 deg samples; the references' own error on
#: 720,000 samples is ~ f'' h^2 / 8 (h = 8.7e-6 rad): angle values agree to this (deg) ...
EXTREME_TOLERANCE_DEG = 1e-8
#: ... lengths to this relative tolerance, angles of the extremes to a reference sample (deg).
RELATIVE_TOLERANCE = 1e-9
ANGLE_AT_TOLERANCE_DEG = 1e-3
#: The smallest base radius holds the limit exactly; 1e-12 m less (about 1e-11 rad of
#: pressure angle) violates it.
SIZING_TOLERANCE_M = 1e-12
STEP_BELOW_M = 1e-12


def report_json(capsys, config) -> tuple[int, dict]:
    run = run_cli(capsys, 'report', config, '--json')
    assert run.err == ''
    return run.code, json.loads(run.out)


def edited(tmp_path, name, **changes):
    """Write seed 000 with dotted parameters changed, e.g. follower__base_radius=3.0."""
    def edit(parameters):
        for dotted, value in changes.items():
            *path, leaf = dotted.split('__')
            section = parameters
            for key in path:
                section = section[key]
            section[leaf] = value
    return write_config(tmp_path, name, edit)


@pytest.fixture(scope='module')
def default_report():
    """Run `cam_ros report config/default.yaml --json` once for the module."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(['report', str(DEFAULT_CONFIG), '--json'])
    return code, json.loads(out.getvalue())


def test_default_design_meets_its_limits(default_report):
    code, data = default_report
    assert code == 0
    assert data['ok'] is True
    assert data['undercut'] is False and data['cusp_angles_deg'] == []
    assert data['pressure_angle_ok'] is True and data['radius_of_curvature_ok'] is True
    assert data['face_width'] is None  # a roller
    assert data['limits'] == {'pressure_angle_deg': PRESSURE_LIMIT_DEG,
                              'pressure_angle_return_deg': PRESSURE_LIMIT_DEG,  # by default
                              'min_radius_of_curvature': pytest.approx(MIN_RADIUS)}


def test_pressure_angle_and_curvature_match_the_closed_forms(default_report):
    _, data = default_report
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    phi, rho = seed_000_roller(theta)
    assert data['pressure_angle_max_deg'] == pytest.approx(
        np.degrees(phi.max()), abs=EXTREME_TOLERANCE_DEG)
    assert data['pressure_angle_min_deg'] == pytest.approx(
        np.degrees(phi.min()), abs=EXTREME_TOLERANCE_DEG)
    assert data['pressure_angle_max_at_deg'] == pytest.approx(
        np.degrees(theta[phi.argmax()]), abs=ANGLE_AT_TOLERANCE_DEG)
    convex = rho > 0
    assert data['radius_of_curvature_min'] == pytest.approx(
        rho[convex].min(), rel=RELATIVE_TOLERANCE)
    assert data['radius_of_curvature_min_at_deg'] == pytest.approx(
        np.degrees(theta[convex][rho[convex].argmin()]), abs=ANGLE_AT_TOLERANCE_DEG)


def test_segments_carry_the_laws_characteristic_values_and_peaks_at_speed(default_report):
    _, data = default_report
    laws = [(s['law'], s['start_deg'], s['end_deg']) for s in data['segments']]
    assert laws == [('dwell', 0, 90), ('cycloidal', 90, 180), ('dwell', 180, 240),
                    ('simple_harmonic', 240, 360)]
    cycloidal, harmonic = data['segments'][1], data['segments'][3]
    # Cycloidal: Cv = 2, Ca = 2 pi, Cj = 4 pi^2; simple harmonic: pi/2, pi^2/2, pi^3/2.
    assert (cycloidal['cv'], cycloidal['ca'], cycloidal['cj']) == pytest.approx(
        (2.0, 2 * math.pi, 4 * math.pi ** 2))
    assert (harmonic['cv'], harmonic['ca'], harmonic['cj']) == pytest.approx(
        (math.pi / 2, math.pi ** 2 / 2, math.pi ** 3 / 2))
    # Peak velocity of the cycloidal rise: 2 h / beta * omega (0.16 m/s); and so on.
    assert cycloidal['peak_velocity'] == pytest.approx(2 * RISE / RISE_SPAN * OMEGA)
    assert cycloidal['peak_velocity'] == pytest.approx(0.16)
    assert cycloidal['peak_acceleration'] == pytest.approx(
        2 * math.pi * RISE / RISE_SPAN ** 2 * OMEGA ** 2)
    assert cycloidal['peak_jerk'] == pytest.approx(
        4 * math.pi ** 2 * RISE / RISE_SPAN ** 3 * OMEGA ** 3)
    assert harmonic['peak_velocity'] == pytest.approx(math.pi / 2 * RISE / RETURN_SPAN * OMEGA)
    assert harmonic['peak_acceleration'] == pytest.approx(
        math.pi ** 2 / 2 * RISE / RETURN_SPAN ** 2 * OMEGA ** 2)
    for dwell in data['segments'][0], data['segments'][2]:
        assert dwell['peak_velocity'] == dwell['peak_acceleration'] == dwell['peak_jerk'] == 0


def test_peaks_equal_the_sampled_motion_maxima(default_report):
    _, data = default_report
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    _, ds, d2s, d3s = seed_000_motion(theta)
    rise = (theta >= math.pi / 2) & (theta < math.pi)
    segment = data['segments'][1]
    for key, values, power in (('peak_velocity', ds, 1), ('peak_acceleration', d2s, 2),
                               ('peak_jerk', d3s, 3)):
        assert segment[key] == pytest.approx(np.abs(values[rise]).max() * OMEGA ** power,
                                             rel=RELATIVE_TOLERANCE)


def test_continuity_lists_the_acceleration_and_jerk_steps_of_seed_000(default_report):
    _, data = default_report
    found = {(round(j['angle_deg'], 6), j['order']): j['jump'] for j in data['continuity']}
    # SHM return: d2s = -h/2 k^2 cos(x), k = pi / beta: -0.0225 m/rad^2 at 240 deg, +0.0225 at
    # 360 deg (jump -0.0225 into the dwell). Cycloidal jerk 4 pi^2 h / beta^3 at 90 and 180 deg.
    step = RISE / 2 * (math.pi / RETURN_SPAN) ** 2
    jerk = 4 * math.pi ** 2 * RISE / RISE_SPAN ** 3
    assert found == pytest.approx({(0.0, 2): -step, (90.0, 3): jerk, (180.0, 3): -jerk,
                                   (240.0, 2): -step})


def test_min_base_radius_is_where_the_pressure_angle_limit_is_reached(default_report):
    _, data = default_report
    smallest = data['min_base_radius']
    assert data['min_base_radius_governing'] == 'pressure_angle'
    assert 0.0 < smallest < BASE_RADIUS  # the default cam stays under 30 deg
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    phi, _ = seed_000_roller(theta, base_radius=smallest)
    assert np.degrees(np.abs(phi).max()) == pytest.approx(PRESSURE_LIMIT_DEG,
                                                          abs=EXTREME_TOLERANCE_DEG)


def test_min_base_radius_meets_the_limit_and_just_below_violates_it(default_report, tmp_path,
                                                                    capsys):
    smallest = default_report[1]['min_base_radius']
    at = edited(tmp_path, 'at', follower__base_radius=smallest / 0.01)
    below = edited(tmp_path, 'below', follower__base_radius=(smallest - STEP_BELOW_M) / 0.01)
    code, data = report_json(capsys, at)
    assert code == 0 and data['pressure_angle_ok'] is True
    assert data['pressure_angle_max_deg'] == pytest.approx(PRESSURE_LIMIT_DEG, abs=1e-12)
    code, data = report_json(capsys, below)
    assert code == 1 and data['pressure_angle_ok'] is False and data['ok'] is False
    assert data['min_base_radius'] == pytest.approx(smallest, abs=SIZING_TOLERANCE_M)


def test_quick_estimate_follows_seed_002(default_report):
    _, data = default_report
    estimate = data['quick_estimate']
    # R = Cv h / (beta tan phi_max), base radius R - h/2 - roller radius, size index R / h.
    mean = 2 * RISE / (RISE_SPAN * math.tan(math.radians(PRESSURE_LIMIT_DEG)))
    assert estimate['segment'] == 1
    assert estimate['mean_radius'] == pytest.approx(mean)
    assert estimate['base_radius'] == pytest.approx(mean - RISE / 2 - ROLLER_RADIUS)
    assert estimate['size_index'] == pytest.approx(mean / RISE)
    assert estimate['big_cam'] is (mean / RISE > 5)


def test_a_quick_estimate_never_prints_a_negative_radius(tmp_path, capsys):
    # A lax limit: R = Cv h / (beta tan 60 deg) = 1.47 cm is under h/2 + roller = 2 cm.
    config = edited(tmp_path, 'lax', limits__pressure_angle_deg=60.0)
    code, data = report_json(capsys, config)
    mean = 2 * RISE / (RISE_SPAN * math.tan(math.radians(60.0)))
    assert mean - RISE / 2 - ROLLER_RADIUS < 0.0
    assert data['quick_estimate']['base_radius'] is None
    assert data['quick_estimate']['mean_radius'] == pytest.approx(mean)
    text = run_cli(capsys, 'report', config).out
    [line] = [line for line in text.splitlines() if 'does not apply' in line]
    assert 'needs no base radius' in line
    estimate = text[text.index('Quick estimate'):text.index('Segments')]
    assert ' -0.' not in estimate and 'seed 002' not in estimate


def test_text_report_names_the_verdict_and_the_numbers(capsys):
    run = run_cli(capsys, 'report', DEFAULT_CONFIG)
    assert run.code == 0 and run.err == ''
    text = run.out
    for fragment in ('translating roller', 'clockwise at 6.28319 rad/s (60 rpm)',
                     'limit |pressure angle| <= 30 deg: ok', 'cycloidal', 'simple_harmonic',
                     'Verdict: meets its limits', 'Undercut             none',
                     'smallest meeting the limits: 0.03396',
                     'from the steepest rise (segment 1) at the pressure-angle limit',
                     'base radius 0.0241063 m'):
        assert fragment in text, fragment


def test_flat_face_width_is_the_range_of_ds_dtheta(tmp_path, capsys):
    code, data = report_json(capsys, follower_config(tmp_path, 'translating_flat'))
    assert code == 0
    # Contact offset on a translating flat face = ds/dtheta: from the return's
    # -pi/2 h / beta_return to the rise's 2 h / beta_rise.
    low, high = data['face_width']
    assert low == pytest.approx(-math.pi / 2 * RISE / RETURN_SPAN, rel=RELATIVE_TOLERANCE)
    assert high == pytest.approx(2 * RISE / RISE_SPAN, rel=RELATIVE_TOLERANCE)
    assert data['pressure_angle_max_deg'] == data['pressure_angle_min_deg'] == 0.0
    assert data['quick_estimate'] is None  # seed 002's method is for roller followers


def test_flat_face_min_base_radius_keeps_the_surface_radius_above_the_limit(tmp_path, capsys):
    code, data = report_json(capsys, follower_config(tmp_path, 'translating_flat'))
    # rho = Rb + s + d2s/dtheta2 >= limit everywhere: Rb >= limit - min(s + d2s).
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    s, _, d2s, _ = seed_000_motion(theta)
    assert data['min_base_radius_governing'] == 'radius'
    assert data['min_base_radius'] == pytest.approx(MIN_RADIUS - (s + d2s).min(),
                                                    rel=RELATIVE_TOLERANCE)


@pytest.mark.parametrize('kind', sorted(FOLLOWERS))
def test_every_follower_reports_in_its_position_unit(kind, tmp_path, capsys):
    code, data = report_json(capsys, follower_config(tmp_path, kind))
    assert code == 0
    assert data['follower']['type'] == kind
    assert data['position_unit'] == ('rad' if kind.startswith('oscillating') else 'm')
    assert (data['face_width'] is None) == kind.endswith('roller')
    assert data['min_base_radius'] > 0
    if kind.startswith('oscillating'):  # bounded base radius: both ends of the feasible range
        assert data['max_base_radius'] > data['min_base_radius']
        assert data['max_base_radius_governing'] in ('pressure_angle', 'radius', 'geometry',
                                                     'search_bound')
    else:
        assert data['max_base_radius'] is None and data['max_base_radius_governing'] is None


def test_text_report_gives_both_ends_of_a_bounded_base_radius(tmp_path, capsys):
    config = follower_config(tmp_path, 'oscillating_roller')
    _, data = report_json(capsys, config)
    run = run_cli(capsys, 'report', config)
    assert run.err == ''
    assert (f"largest meeting the limits: {data['max_base_radius']:.6g} m (set by "
            f"{data['max_base_radius_governing'].replace('_', ' ')})") in run.out


@pytest.mark.parametrize('changes, violated', [
    ({'limits__pressure_angle_deg': 20.0}, 'pressure_angle_ok'),
    ({'limits__min_radius_of_curvature': 4.0}, 'radius_of_curvature_ok'),
    # Same prime circle as seed 000 (pitch curve radius >= 4 cm) with a 4.5 cm roller.
    ({'follower__roller_radius': 4.5, 'follower__base_radius': 0.5}, 'undercut'),
])
def test_a_violated_limit_exits_1(changes, violated, tmp_path, capsys):
    code, data = report_json(capsys, edited(tmp_path, 'bad', **changes))
    assert code == 1 and data['ok'] is False
    assert data[violated] is (violated == 'undercut')
    text = run_cli(capsys, 'report', edited(tmp_path, 'bad', **changes))
    assert text.code == 1 and 'Verdict: VIOLATES its limits' in text.out


def _unknown_key(p):
    p['follower']['roler_radius'] = p['follower'].pop('roller_radius')


def _gap(p):
    p['motion']['start_deg'][2] = 185.0


INVALID = [
    (_unknown_key, 'follower.roler_radius', 'did you mean follower.roller_radius'),
    (lambda p: p['follower'].update(base_radius=4), 'follower.base_radius', 'must be a double'),
    (lambda p: p['motion']['laws'].__setitem__(1, 'cycloid'), 'motion.laws[1]', 'cycloidal'),
    (_gap, 'motion.start_deg[2]', 'gap of 5 deg'),
    (lambda p: p['follower'].update(type='rocker'), 'follower.type', 'must be one of'),
    (lambda p: p['motion'].update(end_deg=[90.0, 180.0, 240.0]), 'motion.end_deg',
     'must have 4 entries'),
]


@pytest.mark.parametrize('edit, parameter, rule', INVALID,
                         ids=['unknown_key', 'wrong_type', 'unknown_law', 'gap', 'bad_choice',
                              'short_array'])
@pytest.mark.parametrize('command', ['report', 'sample', 'plot', 'export'])
def test_invalid_config_exits_2_with_one_line_naming_the_parameter(
        command, edit, parameter, rule, tmp_path, capsys):
    config = write_config(tmp_path, 'invalid', edit)
    extra = {'plot': ['-o', tmp_path / 'cam.png'], 'export': ['-o', tmp_path / 'cam.csv']}
    run = run_cli(capsys, command, config, *extra.get(command, []))
    assert_one_error_line(run, command, parameter, rule)
    assert not (tmp_path / 'cam.png').exists() and not (tmp_path / 'cam.csv').exists()


@pytest.mark.parametrize('content, fragment', [
    (None, 'cannot be read'),
    ('follower: [unclosed', 'is not valid YAML'),
    ('just text', 'must be a mapping'),
    ('cam_node:\n  ros__parameters: {}\n', 'needs one of'),
])
def test_unreadable_config_exits_2(content, fragment, tmp_path, capsys):
    path = tmp_path / 'config.yaml'
    if content is not None:
        path.write_text(content)
    assert_one_error_line(run_cli(capsys, 'report', path), 'report', 'config = ', fragment)


@pytest.mark.parametrize('config', SHIPPED_CONFIGS, ids=lambda path: path.name)
def test_every_shipped_config_reports(config, capsys):
    code, data = report_json(capsys, config)
    assert code == (0 if data['ok'] else 1)
    assert data['segments'][0]['start_deg'] == pytest.approx(
        load_parameters(config)['motion']['start_deg'][0])
    assert data['min_base_radius'] is None or data['min_base_radius'] > 0
    text = run_cli(capsys, 'report', config)
    assert text.code == code and 'Verdict:' in text.out


def test_max_roller_radius_is_the_pitch_curves_smallest_convex_radius(default_report):
    _, data = default_report
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    _, rho = seed_000_roller(theta)
    pitch = rho + ROLLER_RADIUS
    assert data['max_roller_radius'] == pytest.approx(pitch[pitch > 0].min(),
                                                      rel=RELATIVE_TOLERANCE)
    assert data['max_roller_radius'] <= pitch[pitch > 0].min()  # refined: never above


def test_smallest_cam_meets_the_rise_and_return_limits(tmp_path, capsys):
    """The cam `smallest_cam` names, written into the config, meets both limits exactly."""
    split = edited(tmp_path, 'split', limits__pressure_angle_return_deg=45.0)
    code, data = report_json(capsys, split)
    assert code == 0
    cam = data['smallest_cam']
    assert set(cam) == {'base_radius', 'offset', 'prime_radius', 'governing'}
    assert cam['governing'] == 'pressure_angle_rise_and_return'
    assert cam['prime_radius'] == pytest.approx(cam['base_radius'] + ROLLER_RADIUS, rel=1e-12)
    assert cam['prime_radius'] < BASE_RADIUS + ROLLER_RADIUS
    # 1e-9 cm more base radius (the cm round trip costs an ulp): both limits hold, at equality
    sized = edited(tmp_path, 'sized', limits__pressure_angle_return_deg=45.0,
                   follower__base_radius=cam['base_radius'] / CM + 1e-9,
                   follower__offset=cam['offset'] / CM)
    code, at = report_json(capsys, sized)
    assert at['pressure_angle_ok'] is True
    assert at['pressure_angle_rise_max_deg'] == pytest.approx(30.0, abs=1e-6)
    assert at['pressure_angle_return_max_deg'] == pytest.approx(45.0, abs=1e-6)
    # the same cam 1e-6 cm smaller breaks a limit
    smaller = edited(tmp_path, 'smaller', limits__pressure_angle_return_deg=45.0,
                     follower__base_radius=cam['base_radius'] / CM - 1e-6,
                     follower__offset=cam['offset'] / CM)
    code, below = report_json(capsys, smaller)
    assert code == 1 and below['pressure_angle_ok'] is False


def test_a_groove_report_names_each_flank_and_its_radius(tmp_path, capsys):
    """Seed 000's cam as a groove (no clearance): the inner flank is the spring cam's surface."""
    groove = edited(tmp_path, 'groove', follower__closure='groove')
    code, data = report_json(capsys, groove)
    assert code == 0 and data['closure'] == 'groove' and 'cams' not in data
    assert set(data['flanks']) == {'inner', 'outer'}
    theta = np.linspace(0.0, 2 * math.pi, REFERENCE_SAMPLES, endpoint=False)
    _, rho = seed_000_roller(theta)
    pitch = rho + ROLLER_RADIUS
    inner, outer = data['flanks']['inner'], data['flanks']['outer']
    assert inner['radius_of_curvature_min'] == pytest.approx(rho[rho > 0].min(),
                                                             rel=RELATIVE_TOLERANCE)
    concave = -pitch[pitch < 0].max() - ROLLER_RADIUS if (pitch < 0).any() else None
    assert outer['radius_of_curvature_min'] == (None if concave is None else pytest.approx(
        concave, rel=RELATIVE_TOLERANCE))
    assert inner['undercut'] is outer['undercut'] is False
    assert 'carries_load_deg' not in inner  # no dynamics, no loads
    _, force = report_json(capsys, DEFAULT_CONFIG)
    assert force['closure'] == 'force' and 'flanks' not in force
