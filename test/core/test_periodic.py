"""The exact periodic response of the elastic train (cam_ros/core/dynamics/periodic.py).

References independent of the code under test: SciPy's matrix exponential; the train's response
to a constant-velocity cam (velocity jumps at every joint) in closed form, piece by piece,
with its extremes at the stationary points of the damped sine; a fine FFT of the undamped
train away from resonance; SciPy's DOP853 integration of the ODE until the transient is gone.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from cam_ros.core import build_design, InvalidParameter, parse_parameters
from cam_ros.core.dynamics.periodic import periodic_response, transition
from cam_ros.core.dynamics.train import TrainConfig

#: The issue's case: the machine cam (25 mm over 100 deg out, 100 deg back, 450 rpm) with
#: constant-velocity rise and return, so its velocity jumps at all four joints, on a stiff
#: 2500 Hz train (333 times the cam frequency).
STROKE = 0.025
OMEGA = 47.1238898038469
JOINTS_DEG = (0.0, 100.0, 180.0, 280.0, 360.0)
POSITIONS = (0.0, STROKE, STROKE, 0.0, 0.0)
CV_DESIGN = {
    'length_unit': 'mm', 'rotation': 'counterclockwise', 'cam_speed': OMEGA,
    'follower.type': 'translating_roller', 'follower.base_radius': 60.0,
    'follower.roller_radius': 15.0, 'follower.offset': 0.0,
    'motion.laws': ['constant_velocity', 'dwell', 'constant_velocity', 'dwell'],
    'motion.start_deg': list(JOINTS_DEG[:4]), 'motion.end_deg': list(JOINTS_DEG[1:]),
    'motion.start_position': [1e3 * s for s in POSITIONS[:4]],
    'motion.end_position': [1e3 * s for s in POSITIONS[1:]],
    'limits.pressure_angle_deg': 60.0, 'limits.allow_velocity_jumps': True,
    'dynamics.train_natural_frequency': 2500.0, 'dynamics.train_damping_ratio': 0.05,
}
#: Seed 000 (cycloidal rise, harmonic return: acceleration jumps) on a 6 Hz train at 1 rev/s.
SEED = {
    'length_unit': 'cm', 'rotation': 'clockwise', 'cam_speed': 2.0 * math.pi,
    'follower.type': 'translating_roller', 'follower.base_radius': 4.0,
    'follower.roller_radius': 1.0, 'follower.offset': 0.5,
    'motion.laws': ['dwell', 'cycloidal', 'dwell', 'simple_harmonic'],
    'motion.start_deg': [0.0, 90.0, 180.0, 240.0], 'motion.end_deg': [90.0, 180.0, 240.0, 360.0],
    'motion.start_position': [0.0, 0.0, 2.0, 2.0], 'motion.end_position': [0.0, 2.0, 2.0, 0.0],
    'dynamics.train_natural_frequency': 6.0, 'dynamics.train_damping_ratio': 0.1,
}


@pytest.mark.parametrize('zeta', [0.0, 0.05, 0.999999, 1.0, 1.000001, 2.5])
def test_the_transition_matrix_is_the_matrix_exponential(zeta):
    train = TrainConfig(40.0, zeta)
    wn = train.omega_n
    a = np.array([[0.0, 1.0], [-wn * wn, -2.0 * zeta * wn]])
    times = np.array([0.0, 1e-6, 3e-4, 2e-3, 0.04])
    found = np.stack(transition(train, times), axis=-1).reshape(-1, 2, 2)
    for t, matrix in zip(times, found):
        expected = expm(a * t)
        scale = np.array([[1.0, 1.0 / wn], [wn, 1.0]])  # x and x' / wn are of one size
        np.testing.assert_allclose(matrix / scale, expected / scale, rtol=0.0, atol=1e-12)


def cv_train_reference(zeta: float, fn: float) -> tuple[float, float]:
    """Return max |x - s| and max |x''| of the train on the CV cam, in closed form.

    On a piece where y = y0 + v t the output is x = y - 2 zeta v / wn + exp(-a t) (A cos wd t
    + B sin wd t), a = zeta wn; the periodic state is reached by going round until the
    transient is below rounding (exp(-a T) per turn). Extremes of an offset damped sine
    C exp(-a t) cos(wd t - phi) + c lie where its derivative vanishes, or at the piece's ends.
    """
    wn = 2.0 * math.pi * fn
    a, wd = zeta * wn, wn * math.sqrt(1.0 - zeta * zeta)
    times = np.radians(JOINTS_DEG) / OMEGA
    velocities = np.diff(POSITIONS) / np.diff(times)
    turns = max(3, math.ceil(40.0 / (a * times[-1])))
    x, xd = 0.0, 0.0
    deviation = acceleration = 0.0
    for turn in range(turns):
        for k, v in enumerate(velocities):
            length = times[k + 1] - times[k]
            offset = -2.0 * zeta * v / wn
            big_a = x - POSITIONS[k] - offset
            big_b = (xd - v + a * big_a) / wd
            if turn == turns - 1:
                # e = offset + D, x'' = D'': extremes at the stationary points of D and D''
                for coefficients, shift in (((big_a, big_b), offset),
                                            (_derivative(*_derivative(big_a, big_b, a, wd),
                                                         a, wd), 0.0)):
                    slope = _derivative(*coefficients, a, wd)
                    base = math.atan2(-slope[0], slope[1])  # slope's cos and sin cancel
                    count = math.ceil(wd * length / math.pi) + 2
                    t = np.concatenate(((base + math.pi * np.arange(-2, count)) / wd,
                                        [0.0, length]))
                    t = t[(t >= 0.0) & (t <= length)]
                    value = shift + np.exp(-a * t) * (coefficients[0] * np.cos(wd * t)
                                                      + coefficients[1] * np.sin(wd * t))
                    peak = float(np.max(np.abs(value)))
                    if shift:
                        deviation = max(deviation, peak)
                    else:
                        acceleration = max(acceleration, peak)
            decay = math.exp(-a * length)
            c, s = math.cos(wd * length), math.sin(wd * length)
            x = POSITIONS[k + 1] + offset + decay * (big_a * c + big_b * s)
            d1 = _derivative(big_a, big_b, a, wd)
            xd = v + decay * (d1[0] * c + d1[1] * s)
    return deviation, acceleration


def _derivative(big_a: float, big_b: float, a: float, wd: float) -> tuple[float, float]:
    """Return the cos and sin coefficients of d/dt exp(-a t) (A cos wd t + B sin wd t)."""
    return -a * big_a + wd * big_b, -a * big_b - wd * big_a


@pytest.mark.parametrize('zeta, fn', [(0.05, 2500.0), (0.02, 2500.0), (0.05, 400.0)])
def test_a_stiff_train_after_velocity_jumps_is_exact_never_low(zeta, fn):
    # The case first: 4.39199e-5 m, where the Fourier series cut off at 8192
    # harmonics read 4.3974e-5 (and 4.3944e-5 on its grid).
    design = build_design(parse_parameters({**CV_DESIGN, 'dynamics.train_damping_ratio': zeta,
                                            'dynamics.train_natural_frequency': fn}))
    report = design.vibration_check
    deviation, acceleration = cv_train_reference(zeta, fn)
    assert report.max_output_deviation == pytest.approx(deviation, rel=1e-9)
    assert report.max_output_deviation >= deviation * (1.0 - 1e-12)
    assert report.peak_output_acceleration == pytest.approx(acceleration, rel=1e-9)
    assert report.peak_output_acceleration >= acceleration * (1.0 - 1e-12)


def test_an_undamped_train_off_resonance_is_the_fourier_series():
    # Seed 000's motion is continuous in s and s': its harmonics fall as 1/k^3, the output's as
    # 1/k^5 above fn: a 2^18-point FFT through the undamped frequency response is exact to
    # far below the tolerance.
    design = build_design(parse_parameters({**SEED, 'dynamics.train_damping_ratio': 0.0,
                                            'dynamics.train_natural_frequency': 6.5}))
    train, omega = design.config.train, design.config.cam_speed
    samples = 2 ** 18
    angle = 2.0 * math.pi * np.arange(samples) / samples
    spectrum = np.fft.rfft(design.program.evaluate(angle).s)
    k = np.arange(spectrum.size)
    x = np.fft.irfft(spectrum / (1.0 - (k * omega / train.omega_n) ** 2), samples)
    response = periodic_response(design.program, omega, train)
    check = np.linspace(0.0, 2.0 * math.pi, 997, endpoint=False)
    expected = np.interp(check, angle, x)  # the FFT grid is fine: linear between is 1e-10 off
    np.testing.assert_allclose(response.at(check), expected, rtol=0.0, atol=1e-9 * 0.02)


@pytest.mark.parametrize('zeta', [0.1, 1.0, 2.5])
def test_the_periodic_response_is_what_a_long_transient_settles_to(zeta):
    design = build_design(parse_parameters({**SEED, 'dynamics.train_damping_ratio': zeta}))
    train, omega = design.config.train, design.config.cam_speed
    wn = train.omega_n
    slowest = wn * (zeta - math.sqrt(zeta * zeta - 1.0)) if zeta > 1.0 else zeta * wn
    period = 2.0 * math.pi / omega
    cycles = math.ceil(45.0 / (slowest * period)) + 1  # the transient decays below 1e-19

    def rhs(t, z):
        s = float(design.program.evaluate(omega * t).s)
        return [z[1], wn * wn * (s - z[0]) - 2.0 * zeta * wn * z[1]]

    breaks = np.sort(np.asarray(design.program.breaks) % (2.0 * math.pi)) / omega
    times = np.unique(np.concatenate([breaks + k * period for k in range(cycles)]
                                     + [[cycles * period]]))
    state, last = np.zeros(2), []
    check = np.linspace(0.0, period, 50, endpoint=False) + 1e-3
    for a, b in zip(np.concatenate([[0.0], times[:-1]]), times):
        inside = [t for t in (cycles - 1) * period + check if a <= t < b]
        solved = solve_ivp(rhs, (a, b), state, method='DOP853', rtol=1e-12, atol=1e-15,
                           dense_output=bool(inside))
        if inside:
            last += list(zip(inside, *solved.sol(inside)))
        state = solved.y[:, -1]
    t, x, v = np.array(last).T
    response = periodic_response(design.program, omega, train)
    theta = omega * (t - (cycles - 1) * period)
    np.testing.assert_allclose(response.at(theta), x, rtol=0.0, atol=1e-9 * 0.02)
    np.testing.assert_allclose(response.at(theta, 1), v, rtol=0.0, atol=1e-8 * 0.02 * omega)
    # x'' from the ODE itself
    s = design.program.evaluate(theta).s
    np.testing.assert_allclose(response.at(theta, 2), wn * wn * (s - x) - 2 * zeta * wn * v,
                               rtol=0.0, atol=1e-7 * 0.02 * omega ** 2)


def test_the_grid_is_the_exact_response_at_its_angles_and_between():
    design = build_design(parse_parameters(CV_DESIGN))
    response = periodic_response(design.program, OMEGA, design.config.train)
    # 2094 rad of the train's phase per turn: 2^13 stretches of at most 0.5 rad
    assert response.angle.size >= 2 ** 13 and np.all(np.diff(response.angle) > 0.0)
    assert set(np.radians(JOINTS_DEG[:4])) <= set(response.angle)  # every break a knot
    # Between knots at() integrates from the knot before: half-way it must agree with the
    # stretch integrated from the knot (a different split of the same integral).
    middle = 0.5 * (response.angle[:-1] + response.angle[1:])[::101]
    halves = periodic_response(design.program, OMEGA, design.config.train, samples=2 ** 14)
    np.testing.assert_allclose(response.at(middle), halves.at(middle), rtol=0.0,
                               atol=1e-12 * STROKE)
    np.testing.assert_allclose(response.at(middle, 2), halves.at(middle, 2), rtol=0.0,
                               atol=1e-12 * np.max(np.abs(response.output_acceleration)))
    every = slice(None, None, 97)
    for order, grid in enumerate((response.output, response.output_velocity,
                                  response.output_acceleration)):
        np.testing.assert_allclose(response.at(response.angle[every] - 4.0 * math.pi, order),
                                   grid[every], rtol=0.0, atol=1e-12 * np.max(np.abs(grid)))


def test_an_undamped_train_at_resonance_has_no_periodic_response():
    design = build_design(parse_parameters({**SEED, 'dynamics.train_damping_ratio': 0.0}))
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        with pytest.raises(InvalidParameter, match='resonates'):
            periodic_response(design.program, design.config.cam_speed, design.config.train)


def test_a_train_too_stiff_to_integrate_is_refused_naming_its_frequency():
    design = build_design(parse_parameters({**SEED, 'dynamics.train_natural_frequency': 1e6}))
    with pytest.raises(InvalidParameter, match='dynamics.train_natural_frequency = 1000000.0: '
                                               'is 1e\\+06 times the cam frequency'):
        periodic_response(design.program, design.config.cam_speed, design.config.train)
