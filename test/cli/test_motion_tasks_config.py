"""Motion tasks from a config: config/flying_shear.yaml, motion.{start,end}_{velocity,
acceleration,jerk} and motion.inflection in the file's units, and the errors naming them.

References written here: the flying shear's numbers from its own dimensions (web 0.5 mm/deg at
360 deg/s = 0.18 m/s; an R-G quintic with H = v X / 2 has ds = v (3 z^2 - 2 z^3), so peak
acceleration 1.5 v / T and peak jerk 6 v / T^2 over its duration T; the cycloidal return's
2 H / T, 2 pi H / T^2, 4 pi^2 H / T^3); with H = v X the quintic peaks at 1.512 v (0.512 v of
overshoot); an entry per degree is value * metre * (180 / pi)^k per rad.
"""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
import yaml
from cli_support import assert_one_error_line, CONFIG_DIR, FOLLOWERS, load_parameters, run_cli

from cam_ros.commands.common import load_design
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.segment import segment_values

FLYING_SHEAR = CONFIG_DIR / 'flying_shear.yaml'
MM = 1e-3
PER_DEG = 180.0 / math.pi  # (per deg) / (per rad)
NAN = math.nan
#: Cam speed of the flying shear: one cut per second.
OMEGA = 2.0 * math.pi
#: Web speed: 0.5 mm per deg of cam at 360 deg/s.
WEB_MM_PER_DEG = 0.5
WEB_SPEED = WEB_MM_PER_DEG * MM * 360.0  # m/s
#: Agreement of two exact computations of the same quantity (relative).
EXACT_RTOL = 1e-9
#: A joint value read from one side agrees with the other to this (relative to its scale).
JOINT_RTOL = 1e-9


def shear_parameters() -> dict:
    return copy.deepcopy(load_parameters(FLYING_SHEAR))


def write(tmp_path, name: str, parameters: dict):
    path = tmp_path / f'{name}.yaml'
    path.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    return path


def shear_with(tmp_path, name: str, **motion) -> object:
    """Write the flying shear with motion entries replaced (nan written as .nan)."""
    parameters = shear_parameters()
    parameters['motion'].update(motion)
    return write(tmp_path, name, parameters)


def report_json(capsys, config) -> tuple[int, dict]:
    run = run_cli(capsys, 'report', config, '--json')
    assert run.err == '', run.err
    return run.code, json.loads(run.out)


# config/flying_shear.yaml --------------------------------------------------------------------

def test_flying_shear_report(capsys):
    code, data = report_json(capsys, FLYING_SHEAR)
    assert code == 0
    assert data['ok'] is True
    assert data['warnings'] == []
    segments = data['segments']
    assert [item['task'] for item in segments] == ['R-G', 'G-G', 'G-R', 'R-R']
    laws = ['poly5', 'constant_velocity', 'poly5', 'cycloidal']
    assert [item['law'] for item in segments] == laws
    assert [item['inflection'] for item in segments] == [0.5] * 4
    assert [item['velocity_overshoot'] for item in segments] == [0.0] * 4
    assert WEB_SPEED == pytest.approx(0.18)
    for item in segments[:3]:  # the quintics reach the web speed at their G end, no higher
        assert item['peak_velocity'] == pytest.approx(WEB_SPEED, rel=EXACT_RTOL)
    quintic_time = 80.0 / 360.0  # s
    for item in (segments[0], segments[2]):
        assert item['peak_acceleration'] == pytest.approx(1.5 * WEB_SPEED / quintic_time,
                                                          rel=EXACT_RTOL)
        assert item['peak_jerk'] == pytest.approx(6 * WEB_SPEED / quintic_time ** 2,
                                                  rel=EXACT_RTOL)
    assert segments[1]['peak_acceleration'] == 0.0
    back, back_time = 0.07, 140.0 / 360.0
    assert segments[3]['peak_velocity'] == pytest.approx(2 * back / back_time, rel=EXACT_RTOL)
    assert segments[3]['peak_acceleration'] == pytest.approx(
        2 * math.pi * back / back_time ** 2, rel=EXACT_RTOL)
    assert [jump for jump in data['continuity'] if jump['order'] <= 2] == []


def test_flying_shear_text_report_names_the_tasks(capsys):
    run = run_cli(capsys, 'report', FLYING_SHEAR)
    assert run.code == 0
    for task in ('R-G', 'G-G', 'G-R', 'R-R'):
        assert task in run.out


def test_flying_shear_runs_with_the_web():
    program = load_design(FLYING_SHEAR).program
    web = WEB_MM_PER_DEG * MM * PER_DEG  # m/rad
    theta = np.radians(np.linspace(80.0, 140.0, 61))
    values = program.evaluate(theta)
    assert values.ds == pytest.approx(np.full(theta.size, web), rel=EXACT_RTOL)
    assert values.d2s == pytest.approx(np.zeros(theta.size), abs=1e-12)
    for joint, before in ((80.0, 0), (140.0, 1), (220.0, 2), (360.0, 3)):
        left = segment_values(program.segments[before], 1.0)
        right = program.evaluate(math.radians(joint % 360.0))
        for k, name in enumerate(('s', 'ds', 'd2s')):
            scale = max(abs(float(left[k])), web / math.radians(80.0) ** (k - 1))
            assert abs(float(getattr(right, name)) - float(left[k])) <= JOINT_RTOL * scale, (
                joint, name)


# Given end values in the file's units ----------------------------------------------------------

#: poly5 R-G into a 3-4-5 G-G at 0.4 mm/deg, poly5 G-B to (0.1 mm/deg, -0.004 mm/deg^2), poly7
#: B-R from there with a start jerk of 1e-4 mm/deg^3, dwell, cycloidal return.
GIVEN_MOTION = {
    'laws': ['poly5', 'polynomial_345', 'poly5', 'poly7', 'dwell', 'cycloidal'],
    'start_deg': [0.0, 90.0, 150.0, 200.0, 240.0, 270.0],
    'end_deg': [90.0, 150.0, 200.0, 240.0, 270.0, 360.0],
    'start_position': [0.0, 20.0, 50.0, 60.0, 62.0, 62.0],
    'end_position': [20.0, 50.0, 60.0, 62.0, 62.0, 0.0],
    'start_velocity': [NAN, 0.4, NAN, NAN, NAN, NAN],
    'end_velocity': [0.4, 0.4, 0.1, NAN, NAN, NAN],
    'end_acceleration': [NAN, NAN, -0.004, NAN, NAN, NAN],
    'start_jerk': [NAN, NAN, NAN, 1e-4, NAN, NAN],
}


def given_config(tmp_path, **changes):
    parameters = shear_parameters()
    parameters['motion'] = {**GIVEN_MOTION, **changes}
    parameters['limits']['pressure_angle_deg'] = 60.0
    return write(tmp_path, 'given', parameters)


def both_sides(program, joint_deg, before):
    """Return the values where segment `before` ends and where the next starts (per rad)."""
    return (segment_values(program.segments[before], 1.0),
            segment_values(program.segments[before + 1], 0.0))


def test_given_values_per_degree_become_si_per_rad(tmp_path):
    assert '.nan' in given_config(tmp_path).read_text()  # written as docs/motion.md shows
    program = load_design(given_config(tmp_path)).program
    velocity = 0.4 * MM * PER_DEG
    for joint, before in ((90.0, 0), (150.0, 1)):
        for values in both_sides(program, joint, before):
            assert float(values.y1) == pytest.approx(velocity, rel=EXACT_RTOL)
            assert float(values.y2) == pytest.approx(0.0, abs=1e-12)
        assert float(program.evaluate(math.radians(joint)).ds) == pytest.approx(
            velocity, rel=EXACT_RTOL)
    for values in both_sides(program, 200.0, 2):  # the poly7 inherits what the poly5 was given
        assert float(values.y1) == pytest.approx(0.1 * MM * PER_DEG, rel=EXACT_RTOL)
        assert float(values.y2) == pytest.approx(-0.004 * MM * PER_DEG ** 2, rel=EXACT_RTOL)
    start_of_poly7 = program.evaluate(math.radians(200.0))
    assert float(start_of_poly7.d3s) == pytest.approx(1e-4 * MM * PER_DEG ** 3, rel=EXACT_RTOL)
    rest = segment_values(program.segments[3], 1.0)  # the poly7 stops for the dwell
    assert [float(rest.y1), float(rest.y2), float(rest.y3)] == pytest.approx([0, 0, 0],
                                                                             abs=1e-12)
    tasks = [item.task for item in program.segment_summary()]
    assert tasks == ['R-G', 'G-G', 'G-B', 'B-R', 'R-R', 'R-R']
    assert [jump for jump in program.continuity_report() if jump.order <= 2] == []


def test_oscillating_follower_gives_degrees_of_arm_per_degree(tmp_path):
    parameters = shear_parameters()
    parameters['length_unit'] = 'cm'
    parameters['follower'] = dict(FOLLOWERS['oscillating_roller'])
    parameters['motion'].update(start_position=[0.0, 4.0, 10.0, 14.0],
                                end_position=[4.0, 10.0, 14.0, 0.0],
                                end_velocity=[0.1, NAN, NAN, NAN],
                                start_velocity=[NAN, NAN, 0.1, NAN])
    parameters['limits']['pressure_angle_deg'] = 60.0
    program = load_design(write(tmp_path, 'arm', parameters)).program
    for joint, before in ((80.0, 0), (140.0, 1)):
        for values in both_sides(program, joint, before):
            assert float(values.y1) == pytest.approx(0.1, rel=EXACT_RTOL)  # rad/rad = deg/deg


def test_report_json_gives_inflection_and_overshoot_in_si(tmp_path, capsys):
    """R-G with H = v X (0 -> 40 mm over 80 deg at 0.5 mm/deg): 0.512 v of overshoot; an
    inflected cycloidal return (lambda 0.3): peak acceleration 2 pi H / (2 lambda) / T^2."""
    config = shear_with(tmp_path, 'overshoot', start_position=[0.0, 40.0, 70.0, 90.0],
                        end_position=[40.0, 70.0, 90.0, 0.0], inflection=[0.5, 0.5, 0.5, 0.3])
    _, data = report_json(capsys, config)
    segments = data['segments']
    assert [item['task'] for item in segments] == ['R-G', 'G-G', 'G-R', 'R-R']
    assert segments[0]['velocity_overshoot'] == pytest.approx(0.512 * WEB_SPEED, rel=1e-9)
    assert segments[0]['peak_velocity'] == pytest.approx(1.512 * WEB_SPEED, rel=1e-9)
    assert [item['velocity_overshoot'] for item in segments[1:]] == [0.0] * 3
    assert [item['inflection'] for item in segments] == [0.5, 0.5, 0.5, 0.3]
    back, back_time = 0.09, 140.0 / 360.0
    assert segments[3]['peak_acceleration'] == pytest.approx(
        2 * math.pi * back / (2 * 0.3) / back_time ** 2, rel=1e-9)
    assert segments[3]['peak_velocity'] == pytest.approx(2 * back / back_time, rel=1e-9)
    assert any('overshoot' in warning and 'segment 0' in warning
               for warning in data['warnings'])


# Errors in the file's terms ------------------------------------------------------------------

def refused(capsys, config, *fragments):
    """The report refuses the config with one error line holding every fragment."""
    run = run_cli(capsys, 'report', config)
    assert_one_error_line(run, 'report', *fragments)
    with pytest.raises(InvalidParameter):
        load_design(config)
    return run.err


def test_unequal_velocities_on_a_rest_to_rest_law(tmp_path, capsys):
    config = shear_with(tmp_path, 'unequal', start_velocity=[NAN, NAN, NAN, 0.1],
                        end_velocity=[NAN, NAN, NAN, 0.2])
    err = refused(capsys, config, 'motion.end_velocity[3]', 'poly5', 'poly7')
    assert '0.1 mm/deg' in err  # the start velocity as the file gives it


def test_given_end_acceleration_on_a_cycloidal(tmp_path, capsys):
    config = shear_with(tmp_path, 'acceleration', end_acceleration=[NAN, NAN, NAN, 0.001])
    refused(capsys, config, 'motion.end_acceleration[3] = 0.001', 'cycloidal', 'poly5')


def test_end_acceleration_message_quotes_the_laws_value_as_zero(tmp_path, capsys):
    """A cycloidal end has no acceleration: the message says 0, not sin(2 pi) rounding noise."""
    config = shear_with(tmp_path, 'acceleration', end_acceleration=[NAN, NAN, NAN, 0.001])
    err = refused(capsys, config, 'motion.end_acceleration[3]')
    assert 'has 0 mm/deg^2' in err, err


def test_the_cycloidals_own_end_acceleration_is_accepted(tmp_path):
    config = shear_with(tmp_path, 'zero', end_acceleration=[NAN, NAN, NAN, 0.0],
                        start_acceleration=[NAN, NAN, NAN, 0.0])
    assert load_design(config).program.segment_summary()[3].task == 'R-R'


def test_poly5_with_a_jerk(tmp_path, capsys):
    config = shear_with(tmp_path, 'jerk', start_jerk=[0.001, NAN, NAN, NAN])
    refused(capsys, config, 'motion.start_jerk[0]', 'poly7')


def test_adjacent_automatic_poly5_ends_name_both_fields(tmp_path, capsys):
    config = shear_with(tmp_path, 'automatic', laws=['poly5', 'poly5', 'poly5', 'cycloidal'])
    refused(capsys, config, 'motion.end_velocity[0]', 'motion.start_velocity[1]', '80 deg')


def test_reversal_behind_the_start(tmp_path, capsys):
    """poly5 G-U 140-220 deg from the web speed to a stop, but ending 10 mm behind its start."""
    config = shear_with(tmp_path, 'reversal', start_position=[0.0, 20.0, 50.0, 40.0],
                        end_position=[20.0, 50.0, 40.0, 0.0], end_velocity=[NAN, NAN, 0.0, NAN],
                        end_acceleration=[NAN, NAN, -0.01, NAN])
    err = refused(capsys, config, 'motion.end_position[2]', 'G-U', 'behind')
    # The quintic in mm and deg (the formula is unit-free): v0 = 0.5, a0 = 0, v1 = 0,
    # a1 = -0.01, H = -10, X = 80; ds/dx peaks at its ends or where d2s/dx2 = 0.
    low, high = quintic_velocity_range(-10.0, 80.0, (0.5, 0.0), (0.0, -0.01))
    assert low < 0 < high
    assert f'ds/dtheta from {low:.6g} mm/deg to {high:.6g} mm/deg' in err, err


def quintic_velocity_range(stroke, span, start, end) -> tuple[float, float]:
    """Return the least and largest slope of the quintic through (0, v0, a0), (H, v1, a1)."""
    (v0, a0), (v1, a1), h, x = start, end, stroke, span
    c3 = 10 * h - (6 * v0 + 4 * v1) * x - (3 * a0 - a1) * x ** 2 / 2
    c4 = -15 * h + (8 * v0 + 7 * v1) * x + (3 * a0 - 2 * a1) * x ** 2 / 2
    c5 = 6 * h - 3 * (v0 + v1) * x - (a0 - a1) * x ** 2 / 2
    slope = np.polynomial.Polynomial([0, v0 * x, a0 * x ** 2 / 2, c3, c4, c5]).deriv() / x
    z = [0.0, 1.0] + [r.real for r in slope.deriv().roots() if abs(r.imag) < 1e-12
                      and 0 < r.real < 1]
    return float(slope(z).min()), float(slope(z).max())


def loop_config(tmp_path, name: str, end_acceleration: float) -> object:
    """A motion-only program: a poly5 U-U loop 0-90 deg from 0 back to 0 mm with 0.01 mm/deg^2
    at its start, then a poly5 to 20 mm and a cycloidal return."""
    level = math.copysign(20.0, end_acceleration)
    return write(tmp_path, name, {
        'length_unit': 'mm', 'cam_speed': OMEGA, 'follower': {'type': 'none'},
        'motion': {'laws': ['poly5', 'poly5', 'cycloidal'], 'start_deg': [0.0, 90.0, 200.0],
                   'end_deg': [90.0, 200.0, 360.0], 'start_position': [0.0, 0.0, level],
                   'end_position': [0.0, level, 0.0], 'start_velocity': [0.0, NAN, NAN],
                   'end_velocity': [0.0, NAN, NAN], 'start_acceleration': [0.01, NAN, NAN],
                   'end_acceleration': [end_acceleration, NAN, NAN]}})


def test_a_zero_stroke_u_u_loop_peaks_at_its_closed_form(tmp_path, capsys):
    """s = a X^2/2 z^2 (1 - z)^2: ds/dtheta = a X z (1 - z)(1 - 2 z), peaks +-a X / (6 sqrt 3)
    = +-0.0866025 mm/deg for a = 0.01 mm/deg^2, X = 90 deg."""
    code, data = report_json(capsys, loop_config(tmp_path, 'loop', 0.01))
    assert code == 0
    loop = data['segments'][0]
    assert loop['task'] == 'U-U'
    peak_mm_per_deg = 0.01 * 90.0 / (6 * math.sqrt(3))
    assert peak_mm_per_deg == pytest.approx(0.0866025, abs=5e-8)
    assert loop['peak_velocity'] == pytest.approx(peak_mm_per_deg * MM * PER_DEG * OMEGA,
                                                  rel=EXACT_RTOL)
    assert loop['cv'] == pytest.approx(16 / (3 * math.sqrt(3)), rel=EXACT_RTOL)


def test_a_zero_stroke_loop_that_crosses_its_start_is_refused(tmp_path, capsys):
    """With -0.01 mm/deg^2 at its end, s = a X^2/2 z^2 (1 - z)^2 (1 - 2 z) crosses its start."""
    err = refused(capsys, loop_config(tmp_path, 'crossing', -0.01),
                  'motion.end_acceleration[0] = -0.01', 'zero stroke', 'of one sign')
    low, high = quintic_velocity_range(0.0, 90.0, (0.0, 0.01), (0.0, -0.01))
    assert f'ds/dtheta from {low:.6g} mm/deg to {high:.6g} mm/deg' in err, err


def test_inflection_on_poly5(tmp_path, capsys):
    config = shear_with(tmp_path, 'inflection', inflection=[0.3, 0.5, 0.5, 0.5])
    refused(capsys, config, 'motion.inflection[0] = 0.3', 'poly5')


def test_inflection_on_an_asymmetric_table(tmp_path, capsys):
    config = shear_with(tmp_path, 'table', laws=['poly5', 'constant_velocity', 'poly5', 'table'],
                        table_u=[0.0, 0.25, 0.5, 0.8, 1.0], table_y=[0.0, 0.1, 0.45, 0.9, 1.0],
                        inflection=[0.5, 0.5, 0.5, 0.3])
    refused(capsys, config, 'motion.inflection[3]', 'symmetric', 'table')


@pytest.mark.parametrize('field, value', [
    ('start_velocity', math.inf), ('end_velocity', -math.inf), ('start_acceleration', math.inf),
    ('end_jerk', -math.inf)])
def test_infinite_entry_is_refused(tmp_path, capsys, field, value):
    config = shear_with(tmp_path, 'infinite', **{field: [NAN, NAN, value, NAN]})
    refused(capsys, config, f'motion.{field}', 'finite')


@pytest.mark.parametrize('value', [NAN, math.inf, 0.0, 1.0, -0.2])
def test_inflection_must_be_inside_0_1(tmp_path, capsys, value):
    config = shear_with(tmp_path, 'lambda', inflection=[0.5, 0.5, 0.5, value])
    refused(capsys, config, 'motion.inflection')


@pytest.mark.parametrize('field', ['start_velocity', 'end_velocity', 'start_acceleration',
                                   'end_acceleration', 'start_jerk', 'end_jerk', 'inflection'])
@pytest.mark.parametrize('length', [3, 5])
def test_wrong_array_length_names_the_array(tmp_path, capsys, field, length):
    entries = [0.5 if field == 'inflection' else NAN] * length
    config = shear_with(tmp_path, 'length', **{field: entries})
    refused(capsys, config, f'motion.{field}', 'motion.laws')


def test_empty_arrays_mean_automatic(tmp_path):
    config = shear_with(tmp_path, 'empty', start_velocity=[], end_velocity=[], inflection=[])
    summary = load_design(config).program.segment_summary()
    assert [item.task for item in summary] == ['R-G', 'G-G', 'G-R', 'R-R']
