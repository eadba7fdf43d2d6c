"""Tests of cam_ros.core.geometry.cam_geometry against independent references.

References: finite differences and three-point circles of the computed curves, a direct
geometric pressure angle, hand-derived circle cases, the mirror rule, the reference note's
oscillating-roller formula and seed 000's flat-face lecture (formulas and table).
"""
import dataclasses
import math

from cam_motions import rise_return, seed_000
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry.followers import (OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                             TranslatingRoller)
from cam_ros.core.arrays import BLOCK
from cam_ros.core.geometry.cam_geometry import cam_geometry, contact_measures
from cam_ros.core.geometry.closure import ConjugateRoller
from cam_ros.core.geometry.check import check_geometry
import numpy as np
import pytest

FINE = 20001  # samples per turn for finite-difference references
CURVATURE_RTOL = 1e-5  # finite-difference curvature error / largest |curvature|
ANGLE_TOL = 1e-5  # rad, finite-difference pressure angle
CIRCLE_RTOL = 1e-4  # three-point circle radius (step 0.002 rad) vs exact radius
EXACT = 1e-12  # identities that hold to rounding
TABLE_TOL = 1e-5  # m (0.001 cm): seed 000's table is printed to 0.001 cm
CM = 0.01

FOLLOWERS = {  # name: (follower, rise of rise_return: m or rad)
    'translating_roller+e': (TranslatingRoller(0.04, 0.01, 0.005), 0.02),
    'translating_roller-e': (TranslatingRoller(0.04, 0.01, -0.008), 0.02),
    'translating_roller_concave': (TranslatingRoller(0.012, 0.004, 0.003), 0.03),
    'translating_flat': (TranslatingFlat(0.04), 0.02),
    'oscillating_roller_with': (OscillatingRoller(0.04, 0.01, 0.09, 0.07, True), 0.3),
    'oscillating_roller_against': (OscillatingRoller(0.04, 0.01, 0.09, 0.07, False), 0.3),
    'oscillating_flat_with': (OscillatingFlat(0.04, 0.09, 0.01, True), 0.3),
    'oscillating_flat_against': (OscillatingFlat(0.04, 0.09, -0.01, False), 0.3),
    'oscillating_flat_pivot_face': (OscillatingFlat(0.03, 0.09, 0.0, False), 0.3),
}
ROTATIONS = {'ccw': False, 'cw': True}


@pytest.fixture(params=FOLLOWERS)
def follower_case(request):
    return FOLLOWERS[request.param]


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def sigma_of(clockwise):
    return -1 if clockwise else 1


def is_roller(follower):
    return isinstance(follower, (TranslatingRoller, OscillatingRoller))


def fine_geometry(follower, rise, clockwise, samples=FINE):
    theta = np.linspace(0.0, 2 * np.pi, samples)
    return cam_geometry(follower, theta, *rise_return(theta, rise), clockwise=clockwise)


def to_fixed(theta, sigma, x, y):
    """Turn cam-frame points at cam angle theta into the fixed frame: Rot(sigma theta)."""
    c, s = np.cos(theta), np.sin(sigma * theta)
    return c * x - s * y, s * x + c * y


def fd_curvature(theta, x, y, sigma):
    """Return the convex-positive curvature of a cam-frame curve by finite differences."""
    x1, y1 = np.gradient(x, theta), np.gradient(y, theta)
    x2, y2 = np.gradient(x1, theta), np.gradient(y1, theta)
    return -sigma * (x1 * y2 - y1 * x2) / np.hypot(x1, y1) ** 3


def smooth(theta):
    """Mask away the ends (one-sided differences) and the rise/return junction (jerk jumps)."""
    step = theta[1] - theta[0]
    inner = np.zeros(theta.size, bool)
    inner[3:-3] = True
    return inner & (np.abs(theta - 5 * np.pi / 6) > 4 * step)


# ---------------------------------------------------------------- curvature

def test_pitch_curvature_matches_finite_differences(follower_case, clockwise):
    follower, rise = follower_case
    geometry = fine_geometry(follower, rise, clockwise)
    sigma = sigma_of(clockwise)
    reference = fd_curvature(geometry.theta, geometry.pitch_x, geometry.pitch_y, sigma)
    computed = 1.0 / geometry.pitch_radius
    scale = np.abs(computed).max()
    assert np.abs(reference - computed)[smooth(geometry.theta)].max() < CURVATURE_RTOL * scale


def test_surface_curvature_matches_finite_differences(follower_case, clockwise):
    follower, rise = follower_case
    geometry = fine_geometry(follower, rise, clockwise)
    assert not check_geometry(geometry).undercut
    sigma = sigma_of(clockwise)
    reference = fd_curvature(geometry.theta, geometry.surface_x, geometry.surface_y, sigma)
    computed = 1.0 / geometry.surface_radius
    scale = np.abs(computed).max()
    assert np.abs(reference - computed)[smooth(geometry.theta)].max() < CURVATURE_RTOL * scale


def circumradius(p1, p2, p3):
    """Return the radius of the circle through three points (arrays of shape (2, n))."""
    a = np.hypot(*(p2 - p3))
    b = np.hypot(*(p1 - p3))
    c = np.hypot(*(p1 - p2))
    cross = (p2 - p1)[0] * (p3 - p1)[1] - (p2 - p1)[1] * (p3 - p1)[0]
    return a * b * c / (2 * np.abs(cross))


@pytest.mark.parametrize('name', [name for name, (f, _) in FOLLOWERS.items() if is_roller(f)])
def test_roller_pitch_radius_matches_three_point_circle(name, clockwise):
    """Seed 000's method: the circle through three neighbouring pitch points."""
    follower, rise = FOLLOWERS[name]
    step = 0.002
    theta = np.linspace(0.1, 2 * np.pi - 0.1, 400)
    points = []
    for shift in (-step, 0.0, step):
        g = cam_geometry(follower, theta + shift, *rise_return(theta + shift, rise),
                         clockwise=clockwise)
        points.append(np.stack((g.pitch_x, g.pitch_y)))
    middle = cam_geometry(follower, theta, *rise_return(theta, rise), clockwise=clockwise)
    radius = circumradius(*points)
    exact = np.abs(middle.pitch_radius)
    # near an inflection the circle is ill-posed; across the junction the jerk jumps
    modest = (exact < 5 * follower.prime_radius) & (np.abs(theta - 5 * np.pi / 6) > 2 * step)
    assert modest.sum() > 300
    assert np.all(np.abs(radius - exact)[modest] < CIRCLE_RTOL * exact[modest])
    turn = points[1] - points[0], points[2] - points[1]
    cross = turn[0][0] * turn[1][1] - turn[0][1] * turn[1][0]
    assert np.all(np.sign(middle.pitch_radius) == -sigma_of(clockwise) * np.sign(cross))


def test_concave_case_has_concave_parts_and_inflections():
    follower, rise = FOLLOWERS['translating_roller_concave']
    geometry = fine_geometry(follower, rise, False)
    assert geometry.pitch_radius.min() < 0.0 < geometry.pitch_radius.max()
    assert np.all(np.isfinite(geometry.pitch_curvature))


# ---------------------------------------------------------------- pressure angle

def test_contact_measures_equal_the_geometry_in_blocks(follower_case, clockwise):
    """The per-request path (closed forms for translating followers, blocks) is cam_geometry."""
    follower, rise = follower_case
    theta = np.linspace(0.0, 2 * np.pi, 2 * BLOCK + 5)
    motion = rise_return(theta, rise)
    angle, radius = contact_measures(follower, theta, *motion, clockwise=clockwise)
    geometry = cam_geometry(follower, theta, *motion, clockwise=clockwise)
    np.testing.assert_allclose(angle, geometry.pressure_angle, rtol=EXACT, atol=EXACT)
    roller = follower.roller_radius if is_roller(follower) else 0.0
    curvature, expected = 1.0 / (radius + roller), 1.0 / (geometry.surface_radius + roller)
    np.testing.assert_allclose(curvature, expected, rtol=0.0,
                               atol=EXACT * np.abs(expected).max())


def test_contact_without_outputs_computes_what_contact_measures_writes(follower_case, clockwise):
    """A follower's _contact without out= (fresh arrays) gives the numbers of the blocks."""
    follower, rise = follower_case
    theta = np.linspace(0.0, 2 * np.pi, 1001)
    motion = rise_return(theta, rise)
    fresh = follower._contact(theta, -1 if clockwise else 1, *motion)
    for value, written in zip(fresh, contact_measures(follower, theta, *motion,
                                                      clockwise=clockwise)):
        np.testing.assert_array_equal(value, written)


def test_a_conjugate_second_roller_takes_its_own_geometry_not_roller_1s_closed_form(clockwise):
    """ConjugateRoller is a TranslatingRoller below the cam centre: its contact is its own."""
    first = TranslatingRoller(0.04, 0.01, 0.005)
    second = ConjugateRoller(0.04, 0.01, 0.005, spacing=2.0 * (first.prime_height + 0.02))
    theta = np.linspace(0.0, 2 * np.pi, 2 * BLOCK + 5)
    motion = rise_return(theta, 0.02)
    angle, radius = contact_measures(second, theta, *motion, clockwise=clockwise)
    geometry = cam_geometry(second, theta, *motion, clockwise=clockwise)
    np.testing.assert_array_equal(angle, geometry.pressure_angle)
    np.testing.assert_array_equal(radius, geometry.surface_radius)
    assert not np.allclose(angle, contact_measures(first, theta, *motion,
                                                   clockwise=clockwise)[0])


def test_pressure_angle_matches_direct_geometry(follower_case, clockwise):
    """Angle from the contact point's velocity to the normal found from finite differences."""
    follower, rise = follower_case
    geometry = fine_geometry(follower, rise, clockwise)
    theta, sigma = geometry.theta, sigma_of(clockwise)
    if is_roller(follower):  # normal of the pitch curve at the roller centre
        px, py = to_fixed(theta, sigma, geometry.pitch_x, geometry.pitch_y)
        tx, ty = np.gradient(geometry.pitch_x, theta), np.gradient(geometry.pitch_y, theta)
        point = np.stack((px, py))
    else:  # the face itself is tangent to the surface at the contact
        cx, cy = to_fixed(theta, sigma, geometry.surface_x, geometry.surface_y)
        tx, ty = np.gradient(geometry.surface_x, theta), np.gradient(geometry.surface_y, theta)
        point = np.stack((cx, cy))
    tangent = np.stack(to_fixed(theta, sigma, tx, ty))
    normal = np.stack((-tangent[1], tangent[0]))
    if isinstance(follower, (TranslatingRoller, TranslatingFlat)):
        motion = np.stack((np.zeros_like(theta), np.ones_like(theta)))
    else:  # a point of the arm moves perpendicular to pivot -> point
        arm = point - np.array([[0.0], [follower.pivot_distance]])
        motion = np.stack((-arm[1], arm[0]))
        motion *= np.sign(np.sum(motion * point, axis=0))  # rising moves away from the cam
    if is_roller(follower):
        normal *= np.sign(np.sum(normal * point, axis=0))  # outward
    else:
        normal *= np.sign(np.sum(normal * motion, axis=0))  # a rising face moves along its normal
    cross = motion[0] * normal[1] - motion[1] * normal[0]
    reference = sigma * np.arctan2(cross, np.sum(motion * normal, axis=0))
    assert np.abs(reference - geometry.pressure_angle)[smooth(theta)].max() < ANGLE_TOL


@pytest.mark.parametrize('with_cam', [True, False])
def test_oscillating_roller_pressure_angle_matches_reference_note(with_cam, clockwise):
    """Note: tan phi = (L(1 - k) - C cos psi) / (C sin psi), k = +ds/dtheta with the cam.

    Our sign convention makes phi = -mu times the note's angle (mu = +1 with the cam, -1 against).
    """
    follower = OscillatingRoller(0.04, 0.01, 0.09, 0.07, with_cam)
    theta = np.linspace(0.0, 2 * np.pi, 721)
    s, ds, d2s = seed_000(theta, 0.3)
    geometry = cam_geometry(follower, theta, s, ds, d2s, clockwise=clockwise)
    mu = 1.0 if with_cam else -1.0
    c, arm = 0.09, 0.07
    psi = math.acos((c * c + arm * arm - 0.05 ** 2) / (2 * c * arm)) + s
    note = np.arctan((arm * (1 - mu * ds) - c * np.cos(psi)) / (c * np.sin(psi)))
    assert np.abs(geometry.pressure_angle + mu * note).max() < EXACT


def test_translating_roller_pressure_angle_formula(clockwise):
    """Note: tan phi = (ds/dtheta - sigma e) / (d + s)."""
    follower = TranslatingRoller(0.04, 0.01, 0.005)
    theta = np.linspace(0.0, 2 * np.pi, 721)
    s, ds, d2s = seed_000(theta)
    geometry = cam_geometry(follower, theta, s, ds, d2s, clockwise=clockwise)
    d = math.sqrt(0.05 ** 2 - 0.005 ** 2)
    note = np.arctan((ds - sigma_of(clockwise) * 0.005) / (d + s))
    assert np.abs(geometry.pressure_angle - note).max() < EXACT


# ---------------------------------------------------------------- mirror rule

def mirrored(follower):
    if isinstance(follower, TranslatingRoller):
        return dataclasses.replace(follower, offset=-follower.offset)
    return follower


def test_clockwise_is_mirrored_counter_clockwise_with_offset_negated(follower_case):
    follower, rise = follower_case
    theta = np.linspace(0.0, 2 * np.pi, 1441)
    motion = rise_return(theta, rise)
    cw = cam_geometry(follower, theta, *motion, clockwise=True)
    ccw = cam_geometry(mirrored(follower), theta, *motion, clockwise=False)
    for name in ('pitch', 'surface'):
        np.testing.assert_allclose(getattr(cw, name + '_x'), -getattr(ccw, name + '_x'),
                                   atol=EXACT)
        np.testing.assert_allclose(getattr(cw, name + '_y'), getattr(ccw, name + '_y'),
                                   atol=EXACT)
    np.testing.assert_allclose(cw.pressure_angle, ccw.pressure_angle, atol=EXACT)
    np.testing.assert_allclose(cw.pitch_radius, ccw.pitch_radius, rtol=1e-10)
    np.testing.assert_allclose(cw.surface_radius, ccw.surface_radius, rtol=1e-10)
    if cw.contact_offset is not None:
        np.testing.assert_allclose(cw.contact_offset, ccw.contact_offset, atol=EXACT)


# ---------------------------------------------------------------- circle cases (dwell everywhere)

DWELL = 0.004  # m, or rad for the arm

THETA_DWELL = np.linspace(0.0, 2 * np.pi, 37)


def dwell_geometry(follower, clockwise, position=DWELL):
    s = np.full_like(THETA_DWELL, position)
    zero = np.zeros_like(THETA_DWELL)
    return cam_geometry(follower, THETA_DWELL, s, zero, zero, clockwise=clockwise)


def assert_circle(x, y, radius):
    np.testing.assert_allclose(np.hypot(x, y), radius, rtol=EXACT)


@pytest.mark.parametrize('offset', [0.0, 0.006, -0.006])
def test_translating_roller_dwell_is_circle(offset, clockwise):
    follower = TranslatingRoller(0.04, 0.01, offset)
    geometry = dwell_geometry(follower, clockwise)
    height = math.sqrt(0.05 ** 2 - offset ** 2) + DWELL
    pitch = math.hypot(offset, height)
    assert_circle(geometry.pitch_x, geometry.pitch_y, pitch)
    assert_circle(geometry.surface_x, geometry.surface_y, pitch - 0.01)
    np.testing.assert_allclose(geometry.pitch_radius, pitch, rtol=1e-12)
    np.testing.assert_allclose(geometry.surface_radius, pitch - 0.01, rtol=1e-12)
    # the normal is radial, tilted from +y by atan(e / height) toward +x
    expected = -sigma_of(clockwise) * math.atan(offset / height)
    np.testing.assert_allclose(geometry.pressure_angle, expected, atol=EXACT)


def test_translating_flat_dwell_is_circle(clockwise):
    geometry = dwell_geometry(TranslatingFlat(0.04), clockwise)
    assert_circle(geometry.surface_x, geometry.surface_y, 0.04 + DWELL)
    np.testing.assert_allclose(geometry.surface_radius, 0.04 + DWELL, rtol=EXACT)
    assert np.all(geometry.pressure_angle == 0.0)
    np.testing.assert_allclose(geometry.contact_offset, 0.0, atol=EXACT)


@pytest.mark.parametrize('with_cam', [True, False])
def test_oscillating_roller_dwell_is_circle(with_cam, clockwise):
    c, arm, prime = 0.09, 0.07, 0.05
    geometry = dwell_geometry(OscillatingRoller(0.04, 0.01, c, arm, with_cam), clockwise)
    psi = math.acos((c * c + arm * arm - prime ** 2) / (2 * c * arm)) + DWELL
    distance = math.sqrt(c * c + arm * arm - 2 * c * arm * math.cos(psi))
    assert_circle(geometry.pitch_x, geometry.pitch_y, distance)
    np.testing.assert_allclose(geometry.pitch_radius, distance, rtol=1e-12)
    # triangle pivot-roller-centre: the normal is radial, the roller moves perpendicular to the arm
    at_roller = math.acos((arm * arm + distance ** 2 - c * c) / (2 * arm * distance))
    np.testing.assert_allclose(np.abs(geometry.pressure_angle), abs(math.pi / 2 - at_roller),
                               atol=EXACT)


@pytest.mark.parametrize('with_cam', [True, False])
@pytest.mark.parametrize('face', [0.012, 0.0, -0.012])
def test_oscillating_flat_dwell_is_circle(face, with_cam, clockwise):
    c, base = 0.09, 0.04
    geometry = dwell_geometry(OscillatingFlat(base, c, face, with_cam), clockwise)
    psi = math.asin((base + face) / c) + DWELL
    assert_circle(geometry.surface_x, geometry.surface_y, c * math.sin(psi) - face)
    np.testing.assert_allclose(geometry.surface_radius, c * math.sin(psi) - face, rtol=1e-12)
    # the contact is the foot of the perpendicular from the cam centre to the face
    np.testing.assert_allclose(geometry.contact_offset, c * math.cos(psi), rtol=1e-12)
    # contact point seen from the pivot: along the face t, across it the face offset
    expected = math.atan(abs(face) / (c * math.cos(psi)))
    np.testing.assert_allclose(np.abs(geometry.pressure_angle), expected, atol=EXACT)


def test_oscillating_flat_face_through_pivot_has_zero_pressure_angle(clockwise):
    follower, rise = FOLLOWERS['oscillating_flat_pivot_face']
    geometry = fine_geometry(follower, rise, clockwise, samples=721)
    np.testing.assert_allclose(geometry.pressure_angle, 0.0, atol=EXACT)


# ---------------------------------------------------------------- flat faces: envelope

@pytest.mark.parametrize('name', [n for n, (f, _) in FOLLOWERS.items() if not is_roller(f)])
def test_flat_contact_is_where_neighbouring_faces_cross(name, clockwise):
    """The envelope point is the limit of the intersection of two neighbouring face lines."""
    follower, rise = FOLLOWERS[name]
    step = 1e-4
    theta = np.linspace(0.05, 2 * np.pi - 0.05, 300)
    sigma = sigma_of(clockwise)

    def face_line(angle):
        """Return unit normal (cam frame) and distance of the face line at cam angle angle."""
        s = rise_return(angle, rise)[0]
        if isinstance(follower, TranslatingFlat):
            normal, distance = np.stack((0 * s, 1 + 0 * s)), follower.base_radius + s
        else:
            c, f = follower.pivot_distance, follower.face_offset
            psi = math.asin((follower.base_radius + f) / c) + s
            lam = sigma if follower.arm_turns_with_cam else -sigma
            normal, distance = np.stack((lam * np.cos(psi), np.sin(psi))), c * np.sin(psi) - f
        x, y = to_fixed(angle, -sigma, normal[0], normal[1])
        return np.stack((x, y)), distance

    (n1, d1), (n2, d2) = face_line(theta - step), face_line(theta + step)
    det = n1[0] * n2[1] - n1[1] * n2[0]
    crossing = np.stack(((d1 * n2[1] - d2 * n1[1]) / det, (n1[0] * d2 - n2[0] * d1) / det))
    geometry = cam_geometry(follower, theta, *rise_return(theta, rise), clockwise=clockwise)
    error = np.hypot(crossing[0] - geometry.surface_x, crossing[1] - geometry.surface_y)
    assert error.max() < 1e-7  # O(step^2) times the profile scale
    # t is the distance from the reference point (pitch curve) to the contact along the face
    along = np.hypot(geometry.surface_x - geometry.pitch_x, geometry.surface_y - geometry.pitch_y)
    np.testing.assert_allclose(along, np.abs(geometry.contact_offset), atol=EXACT)


# ---------------------------------------------------------------- seed 000 (flat face lecture)

# Seed 000's table (cm): angle (deg), f, f', f'', its 4th column, t. OCR misreadings fixed by
# recomputing each row (the 4th column, printed from unrounded values, confirms the fixes):
# 110 deg f'' 5.018 -> 5.016; 120 deg f'' '4419' -> 4.411; 150 deg f'' '- 441' -> -4.411 and
# t 1.810 -> 1.910; 250 deg f 1.968 -> 1.966 and t -0.338 -> -0.388; 310 deg t -1.448 -> -1.449;
# 320 deg f' -1.289 -> -1.299; 350 deg t -0.338 -> -0.388.
SEED_000_TABLE = np.array([
    [100, 0.018, 0.298, 3.274, -3.291, 0.298],
    [110, 0.131, 1.052, 5.016, -5.147, 1.052],
    [120, 0.391, 1.910, 4.411, -4.802, 1.910],
    [130, 0.780, 2.470, 1.742, -2.522, 2.470],
    [140, 1.220, 2.470, -1.742, 0.522, 2.470],
    [150, 1.609, 1.910, -4.411, 2.802, 1.910],
    [160, 1.869, 1.052, -5.016, 3.147, 1.052],
    [170, 1.982, 0.298, -3.274, 1.291, 0.298],
    [180, 2.000, 0.000, 0.000, -2.000, 0.000],
    [240, 2.000, -0.000, -2.250, 0.250, -0.000],
    [250, 1.966, -0.388, -2.173, 0.207, -0.388],
    [260, 1.866, -0.750, -1.949, 0.083, -0.750],
    [270, 1.707, -1.061, -1.591, -0.116, -1.061],
    [280, 1.500, -1.299, -1.125, -0.375, -1.299],
    [290, 1.259, -1.449, -0.582, -0.676, -1.449],
    [300, 1.000, -1.500, 0.000, -1.000, -1.500],
    [310, 0.741, -1.449, 0.582, -1.324, -1.449],
    [320, 0.500, -1.299, 1.125, -1.625, -1.299],
    [330, 0.293, -1.061, 1.591, -1.884, -1.061],
    [340, 0.134, -0.750, 1.949, -2.083, -0.750],
    [350, 0.034, -0.388, 2.173, -2.207, -0.388],
])
SEED_000_BASE = 3.2 * CM  # the lecture's chosen base radius


def test_seed_000_table_matches_the_motion():
    """Our inline motion reproduces the table's f, f', f''."""
    theta = np.radians(SEED_000_TABLE[:, 0])
    for column, values in zip((1, 2, 3), seed_000(theta, 2 * CM)):
        np.testing.assert_allclose(values, SEED_000_TABLE[:, column] * CM, atol=TABLE_TOL)


@pytest.mark.parametrize('table_clockwise', [True, False])
def test_seed_000_table_fourth_column_is_base_radius_minus_rho(table_clockwise):
    """Match the table's 4th column, -(f + f'') = Rb - rho, and its t = f'.

    With the lecture's rho = Rb + f + f'', the 4th column is the base radius at which the surface
    would have a cusp at that angle; t = f' is the contact offset along the face.
    """
    theta = np.radians(SEED_000_TABLE[:, 0])
    geometry = cam_geometry(TranslatingFlat(SEED_000_BASE), theta, *seed_000(theta, 2 * CM),
                            clockwise=table_clockwise)
    np.testing.assert_allclose(SEED_000_BASE - geometry.surface_radius,
                               SEED_000_TABLE[:, 4] * CM, atol=TABLE_TOL)
    np.testing.assert_allclose(geometry.contact_offset, SEED_000_TABLE[:, 5] * CM, atol=TABLE_TOL)


def test_seed_000_clockwise_coordinates_match_the_lecture():
    """Lecture (follower along +x): x = (rb + f) cos - f' sin, y = (rb + f) sin + f' cos.

    Our frame is the lecture's turned by +90 degrees: (x, y)_ours = (-y, x)_lecture.
    """
    theta = np.linspace(0.0, 2 * np.pi, 361)
    f, f1, f2 = seed_000(theta, 2 * CM)
    geometry = cam_geometry(TranslatingFlat(SEED_000_BASE), theta, f, f1, f2, clockwise=True)
    x = (SEED_000_BASE + f) * np.cos(theta) - f1 * np.sin(theta)
    y = (SEED_000_BASE + f) * np.sin(theta) + f1 * np.cos(theta)
    np.testing.assert_allclose(geometry.surface_x, -y, atol=EXACT)
    np.testing.assert_allclose(geometry.surface_y, x, atol=EXACT)


# ---------------------------------------------------------------- motion checks and immutability

THETA = np.linspace(0.0, 2 * np.pi, 10)
ZERO = np.zeros(10)


@pytest.mark.parametrize('follower, args, parameter', [
    (TranslatingFlat(0.04), (THETA, ZERO[:5], ZERO, ZERO), 's'),
    (TranslatingFlat(0.04), ([[0.0]], [0.0], [0.0], [0.0]), 'theta'),
    (TranslatingFlat(0.04), (THETA, ZERO, ZERO, ['x'] * 10), 'd2s'),
    (TranslatingFlat(0.04), (THETA, ZERO, np.where(THETA > 3, np.nan, 0.0), ZERO), 'ds[5]'),
    (TranslatingFlat(0.04), (THETA, ZERO, ZERO, np.zeros((10, 1))), 'd2s'),
    (TranslatingFlat(0.04), (THETA, np.where(THETA > 1, -0.05, 0.0), ZERO, ZERO), 's[2]'),
    (TranslatingRoller(0.04, 0.01), (THETA, np.full(10, -0.06), ZERO, ZERO), 's[0]'),
    (OscillatingRoller(0.04, 0.01, 0.09, 0.07, True), (THETA, np.full(10, 3.0), ZERO, ZERO),
     's[0]'),
    (OscillatingFlat(0.04, 0.09, 0.0, True), (THETA, ZERO, np.full(10, 1.5), ZERO), 'ds[0]'),
    ('a follower', (THETA, ZERO, ZERO, ZERO), 'follower'),
])
def test_invalid_motion_names_the_parameter(follower, args, parameter):
    with pytest.raises(InvalidParameter) as error:
        cam_geometry(follower, *args)
    assert error.value.parameter == parameter


def test_results_are_immutable(follower_case):
    follower, rise = follower_case
    geometry = fine_geometry(follower, rise, False, samples=37)
    with pytest.raises(dataclasses.FrozenInstanceError):
        follower.base_radius = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        geometry.theta = None
    arrays = [geometry.theta, geometry.pitch_x, geometry.surface_y, geometry.pressure_angle,
              geometry.surface_radius]
    for array in arrays:
        with pytest.raises(ValueError):
            array[0] = 1.0
