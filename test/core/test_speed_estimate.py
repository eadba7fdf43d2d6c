"""Master speed from a least-squares quadratic over a window: exact, jitter-removing, delay."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core.ecam.cycle_clock import CycleClock, SETTLED
from cam_ros.core.ecam.speed_estimate import fit_speed, SpeedEstimator
from cam_ros.core.rounding import ceil_sig

RPM = 2 * math.pi / 60


def run(window_s, stamps, positions):
    """Feed samples to an estimator of window window_s; return the estimated omegas and alphas."""
    estimator, estimates = SpeedEstimator(int(window_s * 1e9)), []
    for t, q in zip(stamps.tolist(), positions.tolist()):
        estimator.add(t, q)
        estimates.append(estimator.estimate())
    return np.array(estimates).T


@pytest.mark.parametrize('window_s', [0.0, 0.02, 0.05])
def test_exact_for_constant_acceleration_at_irregular_stamps(window_s):
    rng = np.random.default_rng(7)
    stamps = np.cumsum(rng.integers(2_000_000, 6_000_000, 200))
    t = stamps * 1e-9
    q, omega, alpha = 3.0 + 40.0 * t - 7.5 * t ** 2, 40.0 - 15.0 * t, -15.0
    got_omega, got_alpha = run(window_s, stamps, q)
    np.testing.assert_allclose(got_omega[2:], omega[2:], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(got_alpha[2:], alpha, rtol=1e-6)


def test_three_samples_give_the_interpolating_quadratic():
    t = np.array([0, 3_000_000, 7_000_000])
    q = np.array([1.0, 1.2, 1.9])
    h1, h2 = 4e-3, 3e-3
    alpha = 2 * ((q[2] - q[1]) / h1 - (q[1] - q[0]) / h2) / (h1 + h2)
    omega, got_alpha, misfit = fit_speed(t.tolist(), q.tolist())
    assert got_alpha == pytest.approx(alpha, rel=1e-10)
    assert omega == pytest.approx((q[2] - q[1]) / h1 + alpha * h1 / 2, rel=1e-10)
    assert misfit == pytest.approx(0.0, abs=1e-24)


def test_the_delay_under_jerk_is_as_documented():
    jerk, window = 500.0, 0.05
    stamps = np.arange(0, 2001) * 50_000  # dense and even: the continuous-window figures
    t = stamps * 1e-9
    omega, alpha = run(window, stamps, jerk * t ** 3 / 6)
    now = t[-1]
    assert alpha[-1] == pytest.approx(jerk * (now - window / 2), rel=2e-3)
    assert omega[-1] - jerk * now ** 2 / 2 == pytest.approx(-jerk * window ** 2 / 10, rel=2e-2)


def percent(error):
    """Print a worst error as a percentage rounded up."""
    return f'{ceil_sig(100 * error, 3)} %'


SEEDS = range(200)  # a jitter bound needs many draws: one seed's worst is a median's


def jittered(count, seed, period_ns=4_000_000, jitter_ns=200_000):
    """Return nominal sample times (ns) on a cycle and their stamps, jittered by +-jitter_ns."""
    rng = np.random.default_rng(seed)
    nominal = np.arange(count) * period_ns
    return nominal, nominal + rng.integers(-jitter_ns, jitter_ns + 1, count)


def speed_errors(nominal, stamps, window_s):
    """Relative speed errors of an accelerating master sampled on nominal, stamped stamps."""
    t = nominal * 1e-9
    positions, speeds = 600 * RPM * t + 2.0 * t ** 2, 600 * RPM + 4.0 * t
    omega, _ = run(window_s, stamps, positions)
    return np.abs(omega / speeds - 1.0)


def test_a_window_averages_stamp_jitter_and_the_cycle_clock_removes_it(report):
    nominal, stamps = jittered(2 * SETTLED, seed=3)  # 250 Hz, +-0.2 ms, 600 rpm and speeding up
    three = speed_errors(nominal, stamps, 0.0)[20:]
    report('three-point speed error max', percent(three.max()))
    assert three.max() > 0.1  # the 21 %: three stamps cannot average
    window = np.array([speed_errors(*jittered(2 * SETTLED, seed), 0.05) for seed in SEEDS])
    full = 50_000_000 // 4_000_000  # the first full window: 12 cycles back, 13 samples
    start, before, after = window[:, 4:full], window[:, full:SETTLED], window[:, SETTLED:]
    report(f'0.05 s window, {len(SEEDS)} seeds, messages 4-{full - 1}: speed error max',
           percent(start.max()))
    report('0.05 s window, clock settling: speed error max', percent(before.max()))
    report('0.05 s window, clock settled: speed error max', percent(after.max()))
    assert start.max() <= 0.04
    assert before.max() <= 0.007  # the issue asks 2 % from the first full window on
    assert after.max() <= 0.0004


def test_exact_stamps_of_samples_off_the_cycle_stay_exact():
    nominal, stamps = jittered(1000, seed=4)  # sampled late or early, stamped truly
    t = stamps * 1e-9
    omega, alpha = run(0.05, stamps, 3.0 + 40.0 * t - 7.5 * t ** 2)
    np.testing.assert_allclose(omega[2:], 40.0 - 15.0 * t[2:], rtol=1e-9)
    np.testing.assert_allclose(alpha[2:], -15.0, rtol=1e-6)


def test_the_clock_follows_lost_messages_and_a_new_rate(report):
    nominal, stamps = jittered(3000, seed=5)
    kept = np.random.default_rng(6).random(nominal.size) > 0.1  # one message in ten lost
    lossy = speed_errors(nominal[kept], stamps[kept], 0.05)[SETTLED:]
    slow, fast = jittered(1000, 7), jittered(2000, 8, period_ns=1_000_000)
    faster = speed_errors(np.concatenate([slow[0], slow[0][-1] + 1_000_000 + fast[0]]),
                          np.concatenate([slow[1], slow[0][-1] + 1_000_000 + fast[1]]), 0.05)
    report('10 % of messages lost: speed error max', percent(lossy.max()))
    report('250 Hz then 1 kHz: speed error max', percent(faster[SETTLED:].max()))
    assert lossy.max() <= 0.0005
    assert faster[SETTLED:].max() <= 0.02 and faster[-500:].max() <= 0.005


def test_the_cycle_clock_returns_exact_cycles_as_they_are_and_smooths_jitter():
    clock = CycleClock()
    stamps = 1_700_000_000_000_000_000 + np.arange(300) * 4_000_000  # epoch-sized stamps
    assert [clock.time(stamp) for stamp in stamps.tolist()] == stamps.tolist()
    assert clock.exact and clock.period == 4_000_000 and clock.cycle == 299
    nominal, jittery = jittered(1000, seed=9)
    clock = CycleClock()
    times = np.array([clock.time(stamp) for stamp in jittery.tolist()])
    assert clock.samples == 1000 and not clock.exact  # followed throughout, no restart
    intervals = np.abs(np.diff(times) - 4_000_000)[SETTLED:]
    assert intervals.max() < 0.02 * np.abs(np.diff(jittery) - 4_000_000)[SETTLED:].max()
    deviation = np.abs(times - nominal)[4 * SETTLED:]  # the offset takes longer to settle
    assert deviation.max() < 0.25 * np.abs(jittery - nominal)[4 * SETTLED:].max()


def test_the_cycle_clock_starts_as_the_least_squares_line_and_counts_lost_cycles():
    _, stamps = jittered(SETTLED, seed=10)
    clock, offsets = CycleClock(), stamps - stamps[0]
    for count, stamp in enumerate(stamps.tolist(), 1):
        time = clock.time(stamp)
        if 2 <= count <= 90:  # the start-up gains (the loop's own from about 100 samples)
            slope, intercept = np.polyfit(np.arange(count), offsets[:count], 1)
            assert clock.period == pytest.approx(slope, abs=1e-5)
            assert time - stamps[0] == pytest.approx(intercept + slope * (count - 1), abs=1)
    nominal, stamps = jittered(3 * SETTLED, seed=11)
    kept = np.flatnonzero(np.random.default_rng(12).random(nominal.size) > 0.1)  # 10 % lost
    clock = CycleClock()
    assert [(clock.time(stamp), clock.cycle)[1] for stamp in stamps[kept].tolist()] == \
        (kept - kept[0]).tolist()


def test_samples_bunched_at_one_end_give_the_least_squares_line():
    times = [1, 2, 3, 1_000_000_003]  # probes a nanosecond apart, then a sample 1 s later
    positions = [0.0, 0.0, 0.0, 2.0]
    slope, _ = np.polyfit((np.array(times) - times[-1]) * 1e-9, positions, 1)
    omega, alpha, _ = fit_speed(times, positions)
    assert omega == pytest.approx(slope, rel=1e-9) and alpha == 0.0
    omegas, _ = run(0.05, np.array(times), np.array(positions))
    assert omegas[-1] == pytest.approx(slope, rel=1e-9)


def bunch_ratio(times):
    """Return det / (n s2 s4) of the quadratic's normal equations (u = (t - t_n) / span)."""
    t = np.array(times, dtype=float)
    u = (t - t[-1]) / (t[-1] - t[0])
    moments = np.vander(u, 3, increasing=True)
    normal = moments.T @ moments
    return np.linalg.det(normal) / (t.size * normal[1, 1] * normal[2, 2])


@pytest.mark.parametrize('width_ns, quadratic', [(3_000, False), (30_000, True)])
def test_the_line_takes_over_exactly_below_the_documented_determinant(width_ns, quadratic):
    """One sample, then 19 bunched within width_ns a second later, on q = 3 t + 5 t^2: below
    det = 1e-10 n s2 s4 (numpy's determinant here) the least-squares line, above it the
    quadratic, exact (omega 3 + 10 t, alpha 10); both against np.polyfit."""
    times = [0] + [1_000_000_000 - width_ns + k * width_ns // 18 for k in range(19)]
    assert times[-1] == 1_000_000_000
    ratio = bunch_ratio(times)
    assert bool(ratio > 1e-10) is quadratic and 1e-12 < ratio < 1e-8  # a decade off 1e-10
    seconds = np.array(times) * 1e-9
    positions = 3.0 * seconds + 5.0 * seconds ** 2
    omega, alpha, _ = fit_speed(times, positions.tolist())
    if quadratic:
        assert omega == pytest.approx(3.0 + 10.0 * seconds[-1], rel=1e-6)
        assert alpha == pytest.approx(10.0, rel=1e-4)
    else:
        slope, _ = np.polyfit(seconds - seconds[-1], positions, 1)
        assert omega == pytest.approx(slope, rel=1e-9) and alpha == 0.0
        assert abs(omega - 13.0) > 0.1  # not the quadratic's
