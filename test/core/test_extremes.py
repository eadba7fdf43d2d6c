"""Tests of the extreme and root refinement against closed forms and scalar root finders."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from cam_ros.core.extremes import refine_extrema, refine_extremum, refine_roots

TWO_PI = 2.0 * math.pi
GRID = np.linspace(0.0, TWO_PI, 7200, endpoint=False)
STEP = GRID[1]
EPS = np.finfo(float).eps


def sampled(func, theta=GRID):
    """Return the grid and func on it (what a caller hands over)."""
    return theta, func(theta)


@pytest.mark.parametrize('phase', [0.1234, 1.0, -2.5, 1.5e-5])
def test_smooth_extremes_match_closed_form(phase):
    def func(x):
        return 2.0 + 3.0 * np.sin(3.0 * x + phase)

    value, angle = refine_extremum(func, *sampled(func), 'max')
    assert value == pytest.approx(5.0, rel=1e-15, abs=0.0)
    assert math.sin(3.0 * angle + phase) == pytest.approx(1.0, abs=1e-15)
    assert 0.0 <= angle < TWO_PI
    value, angle = refine_extremum(func, *sampled(func), 'min')
    assert value == pytest.approx(-1.0, rel=1e-14, abs=0.0)
    assert math.sin(3.0 * angle + phase) == pytest.approx(-1.0, abs=1e-15)


def test_grid_value_is_improved_beyond_the_grid():
    # A narrow peak half-way between samples: the grid misses it by ~ f'' h^2 / 8.
    centre = GRID[1000] + 0.5 * STEP

    def func(x):
        return np.cos(0.5 * (x - centre)) ** 1600

    theta, values = sampled(func)
    assert 1.0 - values.max() > 1e-5
    value, angle = refine_extremum(func, theta, values, 'max')
    assert value == pytest.approx(1.0, abs=1e-15)
    assert angle == pytest.approx(centre, abs=1e-7)


def test_second_near_equal_peak_between_samples_wins():
    # Peak A sits on a sample (value 1); peak B lies between samples, true value 1 + 1e-7, but
    # its samples stay below 1: the grid's argmax is A, the true maximum is B.
    at_a, at_b = GRID[500], GRID[3000] + 0.5 * STEP

    def func(x):
        return np.maximum(np.cos(0.5 * (x - at_a)) ** 400,
                          (1.0 + 1e-7) * np.cos(0.5 * (x - at_b)) ** 1600)

    theta, values = sampled(func)
    assert abs(theta[int(np.argmax(values))] - at_a) < 1e-12
    value, angle = refine_extremum(func, theta, values, 'max', breaks=[])
    assert value == pytest.approx(1.0 + 1e-7, rel=1e-15)
    assert angle == pytest.approx(at_b, abs=1e-7)


def test_one_sided_limit_at_a_jump():
    # Rising ramp up to c (off the grid), then a drop: sup is the left limit at c.
    c = 2.0 + 0.3 * STEP

    def func(x):
        x = np.mod(x, TWO_PI)
        return np.where(x < c, x, x - 5.0)

    value, angle = refine_extremum(func, *sampled(func), 'max', breaks=[c])
    assert value == pytest.approx(c, rel=2 * EPS, abs=0.0)  # the limit, not c - gap
    assert angle < c
    assert angle == pytest.approx(c, abs=1e-13)


@pytest.mark.parametrize('index', [0, 2400, 7199])
def test_one_sided_limit_at_a_break_on_a_sample(index):
    # The break is a sample (a joint at a round angle): the sample there is the right side's,
    # the maximum is the left limit, reached from the left up to the break.
    c = GRID[index] if index else TWO_PI

    def func(x):
        x = np.mod(x, TWO_PI)
        x = np.where(x == 0.0, TWO_PI, x) if index == 0 else x
        return np.where(x < c, np.exp(x - c), 0.5 - 0.1 * (x - c))

    theta, values = sampled(func)
    assert values.max() < 1.0 - 1e-4  # the grid misses the left limit by a whole step
    value, angle = refine_extremum(func, theta, values, 'max', breaks=[GRID[index]])
    assert value == pytest.approx(1.0, rel=4 * EPS, abs=0.0)  # exact, not exp(-gap)
    assert np.mod(angle - c + 1.0, TWO_PI) == pytest.approx(1.0, abs=1e-13)
    minimum, at = refine_extremum(lambda x: -func(x), theta, -values, 'min',
                                  breaks=[GRID[index]])
    assert minimum == -value


def test_one_sided_limit_from_the_right_at_a_sample_is_the_sample():
    c = GRID[3000]

    def func(x):
        return np.where(x < c, x - c, 2.0 - np.square(x - c))

    value, angle = refine_extremum(func, *sampled(func), 'max', breaks=[c])
    assert value == 2.0
    assert angle == pytest.approx(c, abs=1e-13)


def test_roots_at_jumps_on_samples_are_the_breaks():
    # +1 up to the first break, -1 up to the second, +1 again: both sign changes are jumps at
    # samples, each the end of its grid interval.
    first, second = GRID[1000], GRID[4000]

    def func(x):
        x = np.mod(x, TWO_PI)
        return np.where((x >= first) & (x < second), -1.0, 1.0) + 0.0 * x

    roots = refine_roots(func, *sampled(func), breaks=[first, second])
    np.testing.assert_array_equal(roots, [first, second])


def test_kink_minimum_at_a_break():
    c = 4.0 + 0.7 * STEP

    def func(x):
        return np.where(x < c, 3.0 * (c - x), 0.5 * (x - c)) + 1.0

    value, angle = refine_extremum(func, *sampled(func), 'min', breaks=[c])
    assert value == pytest.approx(1.0, abs=1e-13)
    assert angle == pytest.approx(c, abs=1e-13)


def test_extreme_across_the_wrap():
    def func(x):
        return np.cos(x + 0.25 * STEP)

    value, angle = refine_extremum(func, *sampled(func), 'max', breaks=[0.0])
    assert value == pytest.approx(1.0, abs=1e-15)
    assert math.cos(angle + 0.25 * STEP) == pytest.approx(1.0, abs=1e-15)
    assert 0.0 <= angle < TWO_PI


def test_plateau_costs_a_few_small_calls():
    sizes = []

    def func(x):
        sizes.append(x.size)
        return np.where(np.mod(x, TWO_PI) < 3.0, 1.0, np.cos(np.mod(x, TWO_PI) - 3.0))

    theta, values = sampled(func)
    sizes.clear()
    value, _ = refine_extremum(func, theta, values, 'max', breaks=[3.0])
    assert value == 1.0
    assert max(sizes) < 100


def test_open_range_without_period():
    theta = np.linspace(0.0, 1.0, 101)

    def func(x):
        return x * (1.0 - x) + 0.1 * x

    value, angle = refine_extremum(func, theta, func(theta), 'max', period=None)
    assert angle == pytest.approx(0.55, abs=1e-7)
    assert value == pytest.approx(0.55 ** 2 + 0.0, rel=1e-14)
    value, angle = refine_extremum(func, theta, func(theta), 'min', period=None)
    assert (value, angle) == (0.0, 0.0)


@pytest.mark.parametrize('phase', [0.1234, 1.0, 1e-3])
def test_roots_match_brentq(phase):
    def func(x):
        return np.sin(3.0 * x + phase) - 0.3 * np.cos(x)

    roots = refine_roots(func, *sampled(func))
    scalar = lambda x: float(func(np.array([x]))[0])  # noqa: E731
    values = func(GRID)
    change = np.flatnonzero(values * np.roll(values, -1) < 0.0)
    expected = np.sort([brentq(scalar, GRID[i], GRID[i] + STEP, xtol=1e-16, rtol=8.9e-16)
                        % TWO_PI for i in change])
    assert roots.size == expected.size == 6
    np.testing.assert_allclose(roots, expected, rtol=0.0, atol=4e-15)
    assert np.all(np.abs(func(roots)) < 1e-14)


def test_root_at_a_jump_is_the_break():
    c = 1.0 + 0.4 * STEP

    def func(x):
        x = np.mod(x, TWO_PI)
        return np.where(x < c, 1.0, -1.0) + 0.0 * x

    roots = refine_roots(func, *sampled(func), breaks=[c, 5.0])
    assert roots.size == 2  # the jump at c and the wrap at 2 pi (a jump between samples)
    assert roots[0] == pytest.approx(c, abs=1e-13)


def test_no_sign_change_no_roots():
    def func(x):
        return 2.0 + np.sin(x)

    assert refine_roots(func, *sampled(func)).size == 0


def test_bad_input():
    with pytest.raises(ValueError, match='kind'):
        refine_extremum(np.sin, GRID, np.sin(GRID), 'largest')
    with pytest.raises(ValueError, match='same size'):
        refine_extremum(np.sin, GRID, np.sin(GRID[:-1]))
    with pytest.raises(ValueError, match='increasing'):
        refine_roots(np.sin, GRID[::-1], np.sin(GRID[::-1]))


def test_several_functions_in_one_search_match_closed_forms():
    calls = []

    def rows(x):
        calls.append(x.size)
        return np.array([np.sin(x + 0.3), 2.0 * np.cos(2.0 * x) + x * 0.0])

    values = rows(GRID)
    calls.clear()
    (high, high_at), (low, low_at) = refine_extrema(rows, GRID, values, ['max', 'min'])
    assert high == pytest.approx(1.0, abs=1e-15)
    assert math.sin(high_at + 0.3) == pytest.approx(1.0, abs=1e-15)
    assert low == pytest.approx(-2.0, abs=1e-15)
    assert math.cos(2.0 * low_at) == pytest.approx(-1.0, abs=1e-15)
    single = len(calls)
    calls.clear()
    refine_extremum(lambda x: rows(x)[0], GRID, values[0], 'max')
    assert single == len(calls)  # one search serves both rows
