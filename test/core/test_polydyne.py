"""Polydyne compensation: the shaped cam makes the elastic train output the designed motion.

References independent of cam_ros/core/dynamics/polydyne.py: the train's ODE integrated by SciPy
(DOP853) with the compensated cam as input, and the compensation formula applied to the
program's own derivatives (not to the shaped polynomials).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from cam_ros.core import build_design, InvalidParameter, parse_parameters, size_base_radius
from cam_ros.core.geometry.cam_geometry import contact_measures
from cam_ros.core.report import design_report

STROKE_CM = 2.0
#: A polydyne machine cam: 9th-order rise and return with dwells, 300 rpm, a 40 Hz train.
DESIGN = {
    'length_unit': 'cm', 'rotation': 'counterclockwise', 'cam_speed': 10.0 * math.pi,
    'follower.type': 'translating_roller', 'follower.base_radius': 5.0,
    'follower.roller_radius': 1.0, 'follower.offset': 0.0,
    'motion.laws': ['polynomial_9', 'dwell', 'polynomial_9', 'dwell'],
    'motion.start_deg': [0.0, 120.0, 180.0, 300.0], 'motion.end_deg': [120.0, 180.0, 300.0, 360.0],
    'motion.start_position': [0.0, STROKE_CM, STROKE_CM, 0.0],
    'motion.end_position': [STROKE_CM, STROKE_CM, 0.0, 0.0],
    'dynamics.train_natural_frequency': 40.0, 'dynamics.train_damping_ratio': 0.08,
    'dynamics.compensate': True,
}
STROKE = STROKE_CM / 100.0
ODE_TOLERANCE = 1e-9  # of the stroke: what the issue asks of the simulated output


def design(**changes):
    return build_design(parse_parameters({**DESIGN, **changes}))


def test_the_simulated_output_of_the_compensated_cam_is_the_designed_motion():
    cam = design()
    omega, wn, zeta = cam.config.cam_speed, cam.config.train.omega_n, 0.08
    surface = cam.surface

    def train(t, state):
        y = surface.evaluate(omega * t).s
        return [state[1], wn * wn * (y - state[0]) - 2.0 * zeta * wn * state[1]]

    period = 2.0 * math.pi / omega
    t = np.linspace(0.0, 2.0 * period, 4001)
    start = cam.program.evaluate(0.0)
    result = solve_ivp(train, (0.0, t[-1]), [float(start.s), omega * float(start.ds)],
                       method='DOP853', t_eval=t, rtol=1e-12, atol=1e-16, max_step=period / 400)
    designed = cam.program.evaluate(omega * t).s
    assert np.max(np.abs(result.y[0] - designed)) <= ODE_TOLERANCE * STROKE
    # Uncompensated, the same train misses the motion by far more (the test can fail).
    plain = design(**{'dynamics.compensate': False})
    assert plain.vibration_check.max_output_deviation > 1e-3 * STROKE


def test_the_surface_is_the_compensation_formula_on_the_program_s_derivatives():
    cam = design()
    theta = np.linspace(0.0, 2.0 * math.pi, 2001, endpoint=False)
    omega, wn, zeta = cam.config.cam_speed, cam.config.train.omega_n, 0.08
    a, b = 2.0 * zeta * omega / wn, (omega / wn) ** 2
    s = cam.program.evaluate(theta)
    y = cam.surface.evaluate(theta)
    np.testing.assert_allclose(y.s, s.s + a * s.ds + b * s.d2s, rtol=0, atol=1e-12 * STROKE)
    np.testing.assert_allclose(y.ds, s.ds + a * s.d2s + b * s.d3s, rtol=0, atol=1e-10 * STROKE)
    # y'' holds s'''': checked against central differences of y' (away from the joints,
    # where y''' jumps).
    h = 1e-6
    near = np.min(np.abs(theta[:, None] - np.append(cam.program.breaks, 2 * math.pi)), axis=1)
    theta = theta[near > 10 * h]
    fd = (cam.surface.evaluate(theta + h).ds - cam.surface.evaluate(theta - h).ds) / (2 * h)
    np.testing.assert_allclose(cam.surface.evaluate(theta).d2s, fd, rtol=0, atol=1e-6 * STROKE)


def test_geometry_is_the_compensated_cam_s_and_the_service_serves_the_follower_motion():
    cam = design()
    theta = np.linspace(0.0, 2.0 * math.pi, 721)
    state = cam.evaluate(theta)
    s, y = cam.program.evaluate(theta), cam.surface.evaluate(theta)
    np.testing.assert_allclose(state.position, s.s, rtol=0, atol=1e-15)
    pressure, radius = contact_measures(cam.follower, theta, y.s, y.ds, y.d2s,
                                        clockwise=False)
    np.testing.assert_allclose(state.pressure_angle, pressure, rtol=0, atol=1e-15)
    np.testing.assert_allclose(state.radius_of_curvature, radius, rtol=0, atol=1e-12)
    plain = design(**{'dynamics.compensate': False})
    assert cam.check.pressure_angle_high[0] != pytest.approx(
        plain.check.pressure_angle_high[0], rel=1e-3)
    dense = np.linspace(0.0, 2.0 * math.pi, 200001)
    y = cam.surface.evaluate(dense)
    exact = contact_measures(cam.follower, dense, y.s, y.ds, y.d2s, clockwise=False)[0]
    assert cam.check.pressure_angle_high[0] >= float(np.max(exact)) - 1e-12
    assert cam.check.pressure_angle_high[0] == pytest.approx(float(np.max(exact)), abs=1e-7)
    # Its own report measures the compensated cam against the designed motion: no deviation.
    assert cam.vibration_check.max_output_deviation <= ODE_TOLERANCE * STROKE


@pytest.mark.parametrize(('laws', 'words'), [
    (['cycloidal', 'dwell', 'polynomial_9', 'dwell'], ['motion.laws[0] is cycloidal']),
    (['polynomial_345', 'dwell', 'polynomial_9', 'dwell'],
     ['3rd derivative jumps', 'at 0 deg', 'motion.laws[3] (dwell) and motion.laws[0] '
      '(polynomial_345)', 'polynomial_9']),
    (['polynomial_9', 'dwell', 'polynomial_4567', 'dwell'],
     ['4th derivative jumps', '180 deg', 'motion.laws[2] (polynomial_4567)']),
])
def test_compensation_over_a_motion_not_smooth_to_the_4th_derivative_is_refused(laws, words):
    with pytest.raises(InvalidParameter) as caught:
        design(**{'motion.laws': laws})
    assert caught.value.parameter == 'dynamics.compensate'
    assert all(word in str(caught.value) for word in words), str(caught.value)


def test_compensation_needs_a_train():
    values = {key: value for key, value in DESIGN.items()
              if key != 'dynamics.train_natural_frequency'}
    with pytest.raises(InvalidParameter, match='dynamics.train_natural_frequency') as caught:
        parse_parameters(values)
    assert caught.value.parameter == 'dynamics.compensate'


def test_the_base_radius_is_sized_for_the_compensated_cam():
    cam = design()
    theta = np.linspace(0.0, 2.0 * math.pi, 7200, endpoint=False)
    y = cam.surface.evaluate(theta)
    limits = dict(clockwise=False, max_pressure_angle=cam.config.pressure_angle_limit,
                  min_radius=cam.config.min_radius_of_curvature)
    expected = size_base_radius(cam.follower, theta, y.s, y.ds, y.d2s, program=cam.surface,
                                **limits).base_radius
    assert design_report(cam).min_base_radius == pytest.approx(expected, rel=1e-12)
    s = cam.program.evaluate(theta)
    rigid = size_base_radius(cam.follower, theta, s.s, s.ds, s.d2s, program=cam.program,
                             **limits).base_radius
    assert abs(expected - rigid) > 1e-4  # m: sizing the designed motion would be another cam
