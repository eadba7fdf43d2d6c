"""Cam tables: knot values, interpolation errors against closed forms and dense brute force.

Interpolants are SciPy's: np.interp, CubicHermiteSpline, and for quintic Hermite pieces
BPoly.from_derivatives through (s, ds, d2s) at every knot (degree 5 on each interval).
"""
import math

import numpy as np
import pytest
from cam_motions import seed_000
from scipy.interpolate import BPoly, CubicHermiteSpline

from cam_ros.core.ecam.cam_table import (equidistant_table, interpolate, MAX_POINTS, stroke,
                                         tolerance_table)
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

deg = math.radians
RISE = 0.02  # m, seed 000
#: Dense brute-force grid over one revolution for the independent error checks.
DENSE = np.linspace(0.0, 2.0 * math.pi, 1_000_001)
MICRON = 1e-6


def program(*rows):
    """Build a program from rows (law, start_deg, end_deg, s_start, s_end)."""
    return MotionProgram([Segment(make_law(law), deg(start), deg(end), s0, s1)
                          for law, start, end, s0, s1 in rows])


SEED_000 = program(('dwell', 0, 90, 0, 0), ('cycloidal', 90, 180, 0, RISE),
                   ('dwell', 180, 240, RISE, RISE), ('simple_harmonic', 240, 360, RISE, 0))
#: Parabolic rise over 0-180 deg and parabolic return: |s''| = 4 h / pi^2 everywhere.
PARABOLIC = program(('constant_acceleration', 0, 180, 0, RISE),
                    ('constant_acceleration', 180, 360, RISE, 0))


def scipy_interpolant(table, theta):
    """Return the table's interpolant at theta as NumPy/SciPy build it."""
    if table.interpolation == 'linear':
        return np.interp(theta, table.angle, table.position)
    if table.interpolation == 'cubic':
        return CubicHermiteSpline(table.angle, table.position, table.slope)(theta)
    ends = np.column_stack((table.position, table.slope, table.curvature))
    return BPoly.from_derivatives(table.angle, ends.tolist())(theta)


def dense_error(table, exact):
    """Return the largest |interpolant - exact| on DENSE, the interpolant built by SciPy/NumPy."""
    return np.abs(scipy_interpolant(table, DENSE) - exact).max()


def test_equidistant_knots_hold_the_exact_values():
    table = equidistant_table(SEED_000, 7)
    np.testing.assert_array_equal(table.master_deg, 360.0 * np.arange(8) / 7)
    s, ds, d2s = seed_000(table.angle % (2 * math.pi))
    np.testing.assert_allclose(table.position, s, rtol=0, atol=1e-12 * RISE)
    np.testing.assert_allclose(table.slope, ds, rtol=0, atol=1e-12 * RISE)
    np.testing.assert_allclose(table.curvature, d2s, rtol=0, atol=1e-10 * RISE)
    assert table.position[-1] == table.position[0] and table.slope[-1] == table.slope[0]


@pytest.mark.parametrize('points', [4, 8, 36, 360])
def test_linear_error_of_a_parabola_is_h_squared_over_8_times_curvature(points):
    # Knots on the halves of each parabolic segment: every chord error is step^2/8 |s''| with
    # |s''| = 4 h / pi^2, step = 2 pi / points, i.e. 2 h / points^2 exactly.
    table = equidistant_table(PARABOLIC, points)
    assert table.max_error == pytest.approx(2 * RISE / points ** 2, rel=1e-9)


def test_cubic_hermite_reproduces_a_parabola_exactly():
    table = equidistant_table(PARABOLIC, 8, 'cubic')
    assert table.max_error < 1e-14 * RISE


def test_quintic_hermite_reproduces_a_quintic_law_exactly():
    # 3-4-5 rise and return: one quintic per half, so 8 equidistant knots lose nothing.
    quintic = program(('polynomial_345', 0, 180, 0, RISE), ('polynomial_345', 180, 360, RISE, 0))
    assert equidistant_table(quintic, 8, 'quintic').max_error < 1e-14 * RISE
    assert equidistant_table(quintic, 8, 'cubic').max_error > 1e-4 * RISE


@pytest.mark.parametrize('interpolation', ['linear', 'cubic', 'quintic'])
def test_reported_error_matches_dense_brute_force(interpolation):
    exact = seed_000(DENSE % (2 * math.pi))[0]
    table = equidistant_table(SEED_000, 50, interpolation)
    measured = dense_error(table, exact)
    # The reported worst error is refined on each interval, so it is at least the sampled one
    # and above it by no more than the dense grid can miss.
    assert measured <= table.max_error * (1 + 1e-9)
    assert table.max_error <= measured * (1 + 1e-4)


@pytest.mark.parametrize('interpolation', ['linear', 'cubic', 'quintic'])
def test_interpolate_is_the_interpolant_scipy_builds(interpolation):
    table = tolerance_table(SEED_000, 1e-5, interpolation)
    theta = np.append(DENSE[::97], table.angle[-1])  # the table's last point too
    np.testing.assert_allclose(interpolate(table, theta), scipy_interpolant(table, theta),
                               rtol=0, atol=1e-15)


@pytest.mark.parametrize('interpolation, tolerance', [('linear', MICRON), ('linear', 1e-4),
                                                      ('cubic', MICRON), ('cubic', 1e-8),
                                                      ('quintic', MICRON), ('quintic', 2e-9)])
def test_tolerance_table_stays_within_tolerance(interpolation, tolerance):
    table = tolerance_table(SEED_000, tolerance, interpolation)
    exact = seed_000(DENSE % (2 * math.pi))[0]
    assert table.max_error <= tolerance
    assert dense_error(table, exact) <= tolerance
    assert table.tolerance == tolerance
    for boundary in (0.0, 90.0, 180.0, 240.0, 360.0):  # where derivatives jump
        assert np.isclose(table.master_deg, boundary, rtol=0, atol=1e-12).any(), boundary
    assert np.all(np.diff(table.master_deg) > 0)


def test_cubic_table_meets_the_tolerance_where_the_slope_jumps():
    # Constant velocity after a dwell: ds/dtheta jumps at 90 and 180 deg, and a point carries
    # one slope (the next segment's), so the interval before each joint must be tiny.
    jumps = program(('dwell', 0, 90, 0, 0), ('constant_velocity', 90, 180, 0, RISE),
                    ('dwell', 180, 240, RISE, RISE), ('cycloidal', 240, 360, RISE, 0))
    table = tolerance_table(jumps, MICRON, 'cubic')
    exact = jumps.evaluate(DENSE).s
    assert table.max_error <= MICRON and dense_error(table, exact) <= MICRON
    assert table.slope[np.isclose(table.master_deg, 90.0, rtol=0, atol=1e-12)] == RISE / deg(90)


@pytest.mark.parametrize('tolerance', [MICRON, 1e-8])
def test_quintic_table_keeps_both_sides_where_the_acceleration_jumps(tolerance):
    # Seed 000: d2s jumps at 240 deg (dwell -> simple harmonic, -pi^2 h / (2 beta^2)) and at 0
    # (simple harmonic -> dwell, from +pi^2 h / (2 beta^2)); ds jumps nowhere.  A knot carries
    # the segment's that starts there, so the one before keeps the other side: it lies within
    # the distance where the joint's jump alone would break the tolerance, and has the dwell's
    # values (0, 0) there, or the simple harmonic's close to its end value.
    table = tolerance_table(SEED_000, tolerance, 'quintic')
    jump = math.pi ** 2 * RISE / (2 * deg(120) ** 2)
    # A quintic Hermite piece's response to a unit end curvature: t^3 (1 - t)^2 / 2 span^2,
    # largest 0.01728 span^2 at t = 3/5, so a knot farther than this from the joint fails.
    reach = math.sqrt(tolerance / (0.01728 * jump))
    for joint, left, right in ((240.0, 0.0, -jump), (360.0, jump, 0.0)):
        at = np.flatnonzero(np.isclose(table.master_deg, joint, rtol=0, atol=1e-12))
        assert at.size == 1
        assert table.curvature[at[0]] == pytest.approx(right if joint < 360 else 0.0,
                                                       rel=1e-12, abs=1e-12)
        before = at[0] - 1
        assert 0 < deg(joint - table.master_deg[before]) < reach
        assert table.curvature[before] == pytest.approx(left, rel=1e-3, abs=1e-12)
    exact = SEED_000.evaluate(DENSE).s
    assert dense_error(table, exact) <= table.max_error * (1 + 1e-9) <= tolerance


def test_each_placed_interval_is_as_long_as_the_tolerance_allows():
    # Greedy placement: stretching any interval that does not end at a segment boundary by
    # 0.1 % of its length breaks the tolerance (checked by brute force on the stretched chord).
    table = tolerance_table(SEED_000, MICRON)
    boundaries = np.radians([90.0, 180.0, 240.0, 360.0])
    stretched = 0
    for start, end in zip(table.angle[:-1], table.angle[1:]):
        if np.isclose(end, boundaries, rtol=0, atol=1e-12).any():
            continue
        longer = end + 1e-3 * (end - start)
        theta = np.linspace(start, longer, 20001)
        s = seed_000(theta)[0]
        chord = s[0] + (s[-1] - s[0]) * (theta - start) / (longer - start)
        assert np.abs(s - chord).max() > MICRON, math.degrees(start)
        stretched += 1
    assert stretched > 100


def test_a_micrometre_needs_far_fewer_placed_points_than_equidistant_ones():
    exact = seed_000(DENSE % (2 * math.pi))[0]
    placed = tolerance_table(SEED_000, MICRON)
    count = len(placed.master_deg) - 1
    # Twice as many equidistant points still miss a micrometre.
    assert dense_error(equidistant_table(SEED_000, 2 * count), exact) > MICRON
    cubic = tolerance_table(SEED_000, MICRON, 'cubic')
    assert len(cubic.master_deg) < count / 4


def test_stroke_is_the_travel_between_the_extreme_positions():
    assert stroke(SEED_000) == pytest.approx(RISE)
    shifted = program(('cycloidal', 0, 180, -0.01, 0.03), ('cycloidal', 180, 360, 0.03, -0.01))
    assert stroke(shifted) == pytest.approx(0.04)


@pytest.mark.parametrize('points', [0, 1, -5, 2.0, True, MAX_POINTS + 1])
def test_bad_point_counts_are_refused(points):
    with pytest.raises(InvalidParameter, match=r'^points = .*: must be an integer in \[2, '):
        equidistant_table(SEED_000, points)


@pytest.mark.parametrize('tolerance', [0.0, -1e-6, 0.021, math.nan, math.inf, 1e-12, '1e-6'])
def test_bad_tolerances_are_refused(tolerance):
    with pytest.raises(InvalidParameter, match=r'^tolerance = .*: must be in \[2e-09, 0.02\]'):
        tolerance_table(SEED_000, tolerance)


def test_unknown_interpolation_is_refused():
    with pytest.raises(InvalidParameter, match='interpolation = .spline.: must be one of linear'):
        equidistant_table(SEED_000, 10, 'spline')


@pytest.mark.parametrize('interpolation', ['linear', 'cubic', 'quintic'])
@pytest.mark.parametrize('points', [7, 11, 13])
def test_stated_error_is_never_below_the_truth_where_a_slope_jump_is_inside_an_interval(
        interpolation, points):
    # A dwell next to constant velocity: s has kinks at 90 and 180 deg; with 7, 11 or 13
    # equidistant points neither is a knot, so the worst error sits at a kink inside an interval.
    # Truth: the exact law and SciPy's interpolant on a dense grid plus the kinks themselves.
    kinks = np.radians([90.0, 180.0])
    jumps = program(('dwell', 0, 90, 0, 0), ('constant_velocity', 90, 180, 0, RISE),
                    ('dwell', 180, 240, RISE, RISE), ('cycloidal', 240, 360, RISE, 0))
    table = equidistant_table(jumps, points, interpolation)
    assert not np.isclose(table.angle[:, None], kinks, rtol=0, atol=1e-9).any()
    grid = np.sort(np.concatenate((DENSE, kinks)))
    approximation = scipy_interpolant(table, grid)
    truth = np.abs(approximation - jumps.evaluate(grid).s).max()
    assert truth * (1.0 - 1e-12) <= table.max_error <= truth * (1.0 + 1e-6)
