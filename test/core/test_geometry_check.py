"""Tests of cam_ros.core.geometry.check: undercut, cusps, limits and face width.

References: closed-form extremes and roots of the motion (by brentq or bisection to adjacent
doubles), the samples' own extremes for the grid-only checks and seed 000's flat-face lecture.
"""
import dataclasses
import math

from cam_motions import cycloidal, rise_return, seed_000
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry.followers import TranslatingFlat, TranslatingRoller
from cam_ros.core.geometry.cam_geometry import cam_geometry
from cam_ros.core.geometry.check import check_geometry
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment
import numpy as np
import pytest

CUSP_TOL = 1e-6  # rad, interpolated cusp angle vs root of the closed form
CM = 0.01
SEED_000_BASE = 3.2 * CM  # the lecture's chosen base radius
SEED_000_FACE = (-1.6 * CM, 2.6 * CM)  # 'the face 2.6 cm above centerline and 1.6 cm below'
SEED_000_TABLE_T_MAX = 2.470 * CM  # the largest contact offset t in the lecture's table


# ---------------------------------------------------------------- seed 000 (flat face lecture)

def test_seed_000_face_extents_cover_the_true_extremes_only_narrowly():
    """t runs from -1.5 cm to 8/pi = 2.546 cm; the table's 2.47 cm misses the peak at 135 deg.

    The lecture's face (2.6 cm above, 1.6 cm below) still covers the contact.
    """
    theta = np.linspace(0.0, 2 * np.pi, 7201)
    geometry = cam_geometry(TranslatingFlat(SEED_000_BASE), theta, *seed_000(theta, 2 * CM),
                            clockwise=True)
    check = check_geometry(geometry)
    assert check.face_max == pytest.approx(8 / math.pi * CM, rel=1e-12)
    assert check.face_min == pytest.approx(-1.5 * CM, rel=1e-9)
    assert check.face_width == pytest.approx((8 / math.pi + 1.5) * CM, rel=1e-9)
    assert SEED_000_FACE[0] <= check.face_min and check.face_max <= SEED_000_FACE[1]
    assert check.face_max > SEED_000_TABLE_T_MAX + 0.07 * CM


def seed_000_rho(theta):
    """Closed-form flat-face radius on seed 000's cycloidal rise with the lecture's base radius."""
    u = (theta - math.pi / 2) / (math.pi / 2)
    f = 2 * CM * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    f2 = 2 * np.pi * 2 * CM / (math.pi / 2) ** 2 * np.sin(2 * np.pi * u)
    return SEED_000_BASE + f + f2


def test_seed_000_base_radius_3_2_cm_has_a_cusp_the_table_hides():
    """Between the 150 and 160 deg rows -(f + f'') peaks at 3.285 cm > 3.2 cm: undercut."""
    from scipy.optimize import brentq
    theta = np.linspace(0.0, 2 * np.pi, 36001)
    geometry = cam_geometry(TranslatingFlat(SEED_000_BASE), theta, *seed_000(theta, 2 * CM))
    check = check_geometry(geometry, min_radius=0.0)
    assert check.undercut and check.radius_ok is False
    edges = [brentq(seed_000_rho, math.radians(a), math.radians(b)) for a, b in
             ((150, 156.5), (156.5, 165))]
    np.testing.assert_allclose(check.cusp_angles, edges, atol=CUSP_TOL)
    inside = (theta > edges[0]) & (theta < edges[1])
    np.testing.assert_array_equal(check.undercut_angles, theta[inside])
    assert check.min_radius == pytest.approx(SEED_000_BASE - 3.2852625 * CM, abs=1e-8)


# ---------------------------------------------------------------- checks on the samples

def test_check_reports_roller_undercut_where_pitch_radius_below_roller_radius():
    follower = TranslatingRoller(0.02, 0.015, 0.0)
    theta = np.linspace(0.0, 2 * np.pi, 7201)
    geometry = cam_geometry(follower, theta, *rise_return(theta, 0.03, np.pi / 4))
    check = check_geometry(geometry)
    rho = geometry.pitch_radius
    undercut = (rho > 0) & (rho <= 0.015)
    assert undercut.any()
    np.testing.assert_array_equal(check.undercut_angles, theta[undercut])
    assert check.cusp_angles.size >= 2 and not check.ok
    assert check.min_radius < 0.0  # the convex surface radius rho_pitch - Rr went negative
    assert check.face_min is None and check.face_width is None


@pytest.mark.parametrize('clockwise', [False, True], ids=['ccw', 'cw'])
def test_check_pressure_angle_and_radius_limits(clockwise):
    follower = TranslatingRoller(0.04, 0.01, 0.005)
    theta = np.linspace(0.0, 2 * np.pi, 3601)
    geometry = cam_geometry(follower, theta, *seed_000(theta, 0.02), clockwise=clockwise)
    peak = np.abs(geometry.pressure_angle).max()
    convex = geometry.pitch_radius > 0
    smallest = geometry.surface_radius[convex].min()
    check = check_geometry(geometry)
    assert check.pressure_angle_ok is None and check.radius_ok is None and check.ok
    assert check.max_pressure_angle == peak
    assert abs(geometry.pressure_angle[theta == check.max_pressure_angle_at][0]) == peak
    assert check.min_radius == pytest.approx(smallest, rel=1e-12)
    assert check_geometry(geometry, max_pressure_angle=peak * (1 + 1e-9)).pressure_angle_ok
    below = check_geometry(geometry, max_pressure_angle=peak * (1 - 1e-9))
    assert below.pressure_angle_ok is False and not below.ok
    assert check_geometry(geometry, min_radius=smallest * (1 - 1e-9)).radius_ok
    assert check_geometry(geometry, min_radius=smallest * (1 + 1e-9)).radius_ok is False


# ---------------------------------------------------------------- checks on the exact motion

DEG = math.pi / 180
GRID = np.linspace(0.0, 2 * np.pi, 7200, endpoint=False)  # the design checks' sampling
RISE = 2 * CM


def program(*segments):
    """Return a MotionProgram of (law, start deg, end deg, s_start, s_end) segments."""
    return MotionProgram(tuple(Segment(make_law(law), a * DEG, b * DEG, s0, s1)
                               for law, a, b, s0, s1 in segments))


SEED = program(('dwell', 0, 90, 0.0, 0.0), ('cycloidal', 90, 180, 0.0, RISE),
               ('dwell', 180, 240, RISE, RISE), ('simple_harmonic', 240, 360, RISE, 0.0))


def exact_check(follower, motion, clockwise=False, **limits):
    """Return check_geometry on the design grid, refined on the exact motion."""
    values = motion.evaluate(GRID)
    geometry = cam_geometry(follower, GRID, values.s, values.ds, values.d2s, clockwise=clockwise)
    return check_geometry(geometry, program=motion, **limits)


def seed_rho_minimum():
    """Return (min of s + s'', angle) on seed 000's cycloidal rise (beta = 90 deg) in closed form.

    d/du (s + s'') = 0  <=>  cos(2 pi u) (4 pi^2 / beta^2 - 1) = -1, with sin(2 pi u) < 0.
    """
    beta = math.pi / 2
    turn = 2 * math.pi - math.acos(-1.0 / (4 * math.pi ** 2 / beta ** 2 - 1.0))
    u = turn / (2 * math.pi)
    value = RISE * (u - math.sin(turn) / (2 * math.pi)) + 2 * math.pi * RISE / beta ** 2 * \
        math.sin(turn)
    return value, beta + u * beta


@pytest.mark.parametrize('clockwise', [False, True], ids=['ccw', 'cw'])
def test_flat_face_minimum_radius_is_the_closed_form(clockwise):
    value, angle = seed_rho_minimum()
    check = exact_check(TranslatingFlat(0.04), SEED, clockwise)
    assert check.min_radius == pytest.approx(0.04 + value, rel=1e-14)
    assert check.min_radius_at == pytest.approx(angle, abs=1e-8)


def test_flat_face_minimum_at_a_joint_is_the_one_sided_limit():
    """Harmonic rise then dwell: rho = Rb + h - h/2 (pi/beta)^2 just before the joint (u -> 1).

    The sample on the joint belongs to the dwell (rho = Rb + h), so the grid misses it.
    """
    motion = program(('simple_harmonic', 0, 120, 0.0, RISE), ('dwell', 120, 180, RISE, RISE),
                     ('simple_harmonic', 180, 300, RISE, 0.0), ('dwell', 300, 360, 0.0, 0.0))
    check = exact_check(TranslatingFlat(0.04), motion)
    expected = 0.04 + RISE - RISE / 2 * (math.pi / (120 * DEG)) ** 2
    assert check.min_radius == pytest.approx(expected, abs=1e-16)
    assert min(abs(check.min_radius_at - 120 * DEG), abs(check.min_radius_at - 180 * DEG)) < 1e-13


def test_zero_offset_roller_pressure_angle_peak_is_a_root_of_the_derivative():
    """tan phi = s' / (Rp + s) peaks where s'' (Rp + s) = s'^2 on the cycloidal rise."""
    from scipy.optimize import brentq
    prime = 0.05
    beta, start = math.pi / 2, math.pi / 2

    def motion(x):
        return cycloidal(np.array([x]), start, beta, RISE)

    def slope(x):
        s, ds, d2s = (value[0] for value in motion(x))
        return d2s * (prime + s) - ds ** 2
    peak_at = brentq(slope, start + 0.01, start + beta / 2, xtol=1e-15, rtol=1e-15)
    s, ds, _ = (value[0] for value in motion(peak_at))
    check = exact_check(TranslatingRoller(prime - CM, CM), SEED)
    assert check.max_pressure_angle == pytest.approx(math.atan(ds / (prime + s)), rel=1e-14)
    assert check.pressure_angle_high == (check.max_pressure_angle, check.max_pressure_angle_at)
    assert check.max_pressure_angle_at == pytest.approx(peak_at, abs=1e-8)
    values = SEED.evaluate(GRID)
    grid = cam_geometry(TranslatingRoller(prime - CM, CM), GRID, values.s, values.ds, values.d2s)
    assert check.max_pressure_angle > np.abs(grid.pressure_angle).max()


def test_face_extents_are_the_peaks_of_ds():
    """t = ds: from -h pi / (2 beta_return) to 2 h / beta_rise (mid-rise of the cycloid)."""
    check = exact_check(TranslatingFlat(0.04), SEED, True)
    assert check.face_max == pytest.approx(2 * RISE / (math.pi / 2), rel=1e-15)
    assert check.face_min == pytest.approx(-RISE * math.pi / (2 * 120 * DEG), rel=1e-15)


def bisect(func, low, high):
    """Return the root of func in [low, high] by bisection down to adjacent doubles."""
    f_low = func(low)
    while True:
        middle = 0.5 * (low + high)
        if middle in (low, high):
            return middle
        if (func(middle) > 0) == (f_low > 0):
            low, f_low = middle, func(middle)
        else:
            high = middle


def test_cusp_angles_are_roots():
    """Seed 000 with Rb = 3.2 cm: rho = Rb + s + s'' changes sign twice near 156.5 deg."""
    check = exact_check(TranslatingFlat(SEED_000_BASE), SEED, True)
    edges = [bisect(seed_000_rho, a * DEG, b * DEG) for a, b in ((150, 156.5), (156.5, 165))]
    np.testing.assert_allclose(check.cusp_angles, edges, rtol=0.0, atol=2e-15)
    assert check.undercut and not check.ok


def test_undercut_between_samples_is_found():
    """A base radius 1e-10 m short of the closed-form need: undercut that no sample shows."""
    value, angle = seed_rho_minimum()
    follower = TranslatingFlat(-value - 1e-10)
    values = SEED.evaluate(GRID)
    geometry = cam_geometry(follower, GRID, values.s, values.ds, values.d2s)
    assert not check_geometry(geometry).undercut  # the grid alone misses it
    check = exact_check(follower, SEED)
    assert check.undercut and check.radius_ok is None
    assert check.min_radius == pytest.approx(-1e-10, abs=1e-16)
    np.testing.assert_array_equal(check.undercut_angles, [check.min_radius_at])
    assert check.min_radius_at == pytest.approx(angle, abs=1e-8)
    low, high = check.cusp_angles  # the dip's two ends, roots of rho on either side of it
    assert low < check.min_radius_at < high and high - low < 1e-4

    def rho(x):
        return follower.base_radius + seed_000_rho(x) - SEED_000_BASE
    for edge, outside in ((low, angle - 1e-3), (high, angle + 1e-3)):
        assert edge == pytest.approx(bisect(rho, outside, angle), abs=1e-11)


# ---------------------------------------------------------------- validation and immutability

@pytest.mark.parametrize('limits, parameter', [
    ({'max_pressure_angle': 0.0}, 'max_pressure_angle'),
    ({'max_pressure_angle': math.pi / 2}, 'max_pressure_angle'),
    ({'min_radius': -0.001}, 'min_radius'),
    ({'min_radius': float('inf')}, 'min_radius'),
])
def test_invalid_limits_name_the_parameter(limits, parameter):
    theta = np.linspace(0.0, 2 * np.pi, 37)
    geometry = cam_geometry(TranslatingFlat(0.04), theta, *seed_000(theta))
    with pytest.raises(InvalidParameter) as error:
        check_geometry(geometry, **limits)
    assert error.value.parameter == parameter


def test_results_are_immutable():
    theta = np.linspace(0.0, 2 * np.pi, 3601)
    geometry = cam_geometry(TranslatingFlat(SEED_000_BASE), theta, *seed_000(theta, 2 * CM))
    check = check_geometry(geometry)
    with pytest.raises(dataclasses.FrozenInstanceError):
        check.min_radius = 1.0
    for array in (check.undercut_angles, check.cusp_angles):
        assert array.size
        with pytest.raises(ValueError):
            array[0] = 1.0
