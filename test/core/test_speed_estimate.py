"""Master speed from a least-squares quadratic over a window: exact, jitter-averaging, delay."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core.ecam.master import MasterTracker
from cam_ros.core.ecam.speed_estimate import fit_speed

SECOND = 10 ** 9
RPM = 2 * math.pi / 60


def run(tracker, stamps, positions):
    """Feed samples; return the estimated omegas and alphas."""
    states = [tracker.accept(int(t), float(q), None, int(t)) for t, q in zip(stamps, positions)]
    return np.array([s.omega for s in states]), np.array([s.alpha for s in states])


@pytest.mark.parametrize('window_s', [0.0, 0.02, 0.05])
def test_exact_for_constant_acceleration_at_irregular_stamps(window_s):
    rng = np.random.default_rng(7)
    stamps = np.cumsum(rng.integers(2_000_000, 6_000_000, 200))
    t = stamps * 1e-9
    q, omega, alpha = 3.0 + 40.0 * t - 7.5 * t ** 2, 40.0 - 15.0 * t, -15.0
    got_omega, got_alpha = run(MasterTracker(SECOND, window_ns=int(window_s * 1e9)), stamps, q)
    np.testing.assert_allclose(got_omega[2:], omega[2:], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(got_alpha[2:], alpha, rtol=1e-6)


def test_three_samples_give_the_interpolating_quadratic():
    t = np.array([0, 3_000_000, 7_000_000])
    q = np.array([1.0, 1.2, 1.9])
    h1, h2 = 4e-3, 3e-3
    alpha = 2 * ((q[2] - q[1]) / h1 - (q[1] - q[0]) / h2) / (h1 + h2)
    omega, got_alpha = fit_speed(t, q)
    assert got_alpha == pytest.approx(alpha, rel=1e-10)
    assert omega == pytest.approx((q[2] - q[1]) / h1 + alpha * h1 / 2, rel=1e-10)


def test_the_delay_under_jerk_is_as_documented():
    jerk, window = 500.0, 0.05
    stamps = np.arange(0, 2001) * 50_000  # dense and even: the continuous-window figures
    t = stamps * 1e-9
    omega, alpha = run(MasterTracker(SECOND, window_ns=int(window * 1e9)), stamps,
                       jerk * t ** 3 / 6)
    now = t[-1]
    assert alpha[-1] == pytest.approx(jerk * (now - window / 2), rel=2e-3)
    assert omega[-1] - jerk * now ** 2 / 2 == pytest.approx(-jerk * window ** 2 / 10, rel=2e-2)


def test_a_window_averages_stamp_jitter(report):
    rng = np.random.default_rng(3)
    nominal = np.arange(2000) * 4_000_000  # 250 Hz
    stamps = nominal + rng.integers(-200_000, 200_001, nominal.size)  # +-0.2 ms
    speed = 600 * RPM
    positions = speed * nominal * 1e-9  # sampled on time, stamped with jitter
    errors = {}
    for window in (0.0, 0.05):
        omega, _ = run(MasterTracker(SECOND, window_ns=int(window * 1e9)), stamps, positions)
        errors[window] = np.abs(omega[20:] / speed - 1.0)
    report('three-point speed error max', f'{errors[0.0].max():.2%}')
    report('0.05 s window speed error max', f'{errors[0.05].max():.2%}')
    report('0.05 s window speed error rms', f'{np.sqrt(np.mean(errors[0.05] ** 2)):.2%}')
    assert errors[0.0].max() > 0.1  # the 21 %: three stamps cannot average
    assert np.sqrt(np.mean(errors[0.05] ** 2)) <= 0.01
    assert errors[0.05].max() <= 0.035 and errors[0.05].max() < errors[0.0].max() / 5
