"""Tests of cam_ros.core.geometry.sizing: exact base-radius sizing and seed 002's quick estimate.

References: closed-form minimum radii on the samples (translating followers), the limit checked
on both sides of the returned radius, monotonicity in the limit, seed 000's flat-face example and
the mid-rise identity behind seed 002's estimate.
"""
import dataclasses
import math

from cam_motions import cycloidal, rise_return, seed_000
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment
from cam_ros.core.geometry.followers import (OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                             TranslatingRoller)
from cam_ros.core.geometry.cam_geometry import cam_geometry
from cam_ros.core.geometry.check import check_geometry
from cam_ros.core.geometry.sizing import (BIG_CAM_SIZE_INDEX, DENSE_SAMPLES, estimate_base_radius,
                                          SIZING_TOLERANCE, size_base_radius)
import numpy as np
import pytest
from scipy.optimize import minimize_scalar

BELOW = 1e-6  # relative step below the returned radius at which the limit must fail
CLOSED_FORM_TOL = 4 * SIZING_TOLERANCE  # m, sized radius vs closed form on the same samples
CM = 0.01
DEG = math.pi / 180

THETA = np.linspace(0.0, 2 * np.pi, DENSE_SAMPLES + 1)
LINEAR = seed_000(THETA, 2 * CM)  # m
ANGULAR = rise_return(THETA, 0.3)  # rad of arm swing
ROTATIONS = {'ccw': False, 'cw': True}

CASES = {  # name: (follower template, motion, limits); base_radius of the template is ignored
    'translating_roller_angle': (TranslatingRoller(0.03, 0.01, 0.005), LINEAR,
                                 {'max_pressure_angle': 30 * DEG}),
    'translating_roller_radius': (TranslatingRoller(0.03, 0.006, 0.0), LINEAR,
                                  {'min_radius': 0.004}),
    'translating_flat_radius': (TranslatingFlat(0.03), LINEAR, {'min_radius': 0.005}),
    'oscillating_roller_with_angle': (OscillatingRoller(0.03, 0.01, 0.09, 0.07, True), ANGULAR,
                                      {'max_pressure_angle': 20 * DEG}),
    'oscillating_roller_against_angle': (OscillatingRoller(0.03, 0.01, 0.09, 0.07, False),
                                         ANGULAR, {'max_pressure_angle': 25 * DEG}),
    'oscillating_flat_radius': (OscillatingFlat(0.03, 0.09, 0.0, False), ANGULAR,
                                {'min_radius': 0.005}),
}


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def verdict(follower, motion, clockwise, limits):
    """Return check_geometry's verdict on the limits given."""
    check = check_geometry(cam_geometry(follower, THETA, *motion, clockwise=clockwise), **limits)
    key = 'pressure_angle_ok' if 'max_pressure_angle' in limits else 'radius_ok'
    return getattr(check, key)


@pytest.mark.parametrize('name', CASES)
def test_limit_is_met_at_the_radius_and_fails_just_below(name, clockwise):
    template, motion, limits = CASES[name]
    sizing = size_base_radius(template, THETA, *motion, clockwise=clockwise, **limits)
    assert sizing.feasible
    assert sizing.governing == ('pressure_angle' if 'max_pressure_angle' in limits else 'radius')
    assert sizing.follower == dataclasses.replace(template, base_radius=sizing.base_radius)
    assert verdict(sizing.follower, motion, clockwise, limits) is True
    below = dataclasses.replace(template, base_radius=sizing.base_radius * (1 - BELOW))
    assert verdict(below, motion, clockwise, limits) is False


@pytest.mark.parametrize('offset', [0.0, 0.005, -0.005])
def test_translating_roller_angle_sizing_matches_closed_form(offset, clockwise):
    """tan phi = (v - sigma e)/(d + s) <= tan phi_max  <=>  d >= |v - sigma e|/tan phi_max - s."""
    sigma = -1 if clockwise else 1
    s, ds, _ = LINEAR
    limit = 25 * DEG
    height = np.max(np.abs(ds - sigma * offset) / math.tan(limit) - s)
    expected = math.hypot(height, offset) - 0.01
    sizing = size_base_radius(TranslatingRoller(0.03, 0.01, offset), THETA, *LINEAR,
                              clockwise=clockwise, max_pressure_angle=limit)
    assert sizing.base_radius == pytest.approx(expected, abs=CLOSED_FORM_TOL)


@pytest.mark.parametrize('limit', [0.0, 0.004, 0.01])
def test_translating_flat_radius_sizing_matches_closed_form(limit):
    """rho = Rb + s + d2s >= limit  <=>  Rb >= limit - min(s + d2s)."""
    s, _, d2s = LINEAR
    sizing = size_base_radius(TranslatingFlat(0.03), THETA, *LINEAR, min_radius=limit)
    assert sizing.base_radius == pytest.approx(limit - np.min(s + d2s), abs=CLOSED_FORM_TOL)


def test_seed_000_flat_face_needs_3_285_cm_not_3_2():
    """Size seed 000's flat-face cam for rho >= 0: 3.2853 cm, more than the lecture's 3.2 cm.

    The lecture read 3.2 cm off a 10-degree table whose worst row (160 deg) says 3.147 cm; the
    continuous worst case lies at 156.5 deg.
    """
    theta = np.linspace(0.0, 2 * np.pi, 36001)
    sizing = size_base_radius(TranslatingFlat(0.03), theta, *seed_000(theta, 2 * CM),
                              clockwise=True, min_radius=0.0)
    assert sizing.base_radius == pytest.approx(3.2852626 * CM, abs=1e-8)  # sampling error
    assert sizing.base_radius > 3.2 * CM


@pytest.mark.parametrize('name', ['translating_roller_angle', 'oscillating_roller_with_angle',
                                  'oscillating_roller_against_angle'])
def test_radius_grows_as_the_pressure_angle_limit_tightens(name):
    template, motion, _ = CASES[name]
    radii = [size_base_radius(template, THETA, *motion, max_pressure_angle=limit * DEG).base_radius
             for limit in (40, 30, 25, 20, 18)]
    assert all(b > a for a, b in zip(radii, radii[1:]))


def test_radius_grows_with_the_curvature_limit():
    template, motion, _ = CASES['translating_roller_radius']
    radii = [size_base_radius(template, THETA, *motion, min_radius=limit).base_radius
             for limit in (0.004, 0.006, 0.01, 0.02)]
    assert all(b > a for a, b in zip(radii, radii[1:]))


def test_two_limits_give_the_larger_radius(clockwise):
    template, motion = TranslatingRoller(0.03, 0.01, 0.004), LINEAR
    limits = {'max_pressure_angle': 30 * DEG, 'min_radius': 0.03}
    each = {key: size_base_radius(template, THETA, *motion, clockwise=clockwise,
                                  **{key: value}) for key, value in limits.items()}
    both = size_base_radius(template, THETA, *motion, clockwise=clockwise, **limits)
    winner = max(each, key=lambda key: each[key].base_radius)
    assert both.base_radius == pytest.approx(each[winner].base_radius, abs=CLOSED_FORM_TOL)
    assert both.governing == {'max_pressure_angle': 'pressure_angle',
                              'min_radius': 'radius'}[winner]


def test_unreachable_limit_is_reported_infeasible():
    template, motion, _ = CASES['oscillating_roller_with_angle']
    sizing = size_base_radius(template, THETA, *motion, max_pressure_angle=1 * DEG)
    assert not sizing.feasible and sizing.governing == 'infeasible'
    assert sizing.base_radius is None and sizing.follower is None


@pytest.mark.parametrize('follower, motion', [
    (TranslatingFlat(0.03), LINEAR),  # phi = 0: any radius meets the limit
    (OscillatingFlat(0.03, 0.09, 0.01, True), ANGULAR),  # phi = atan(f/t) falls with Rb
])
def test_limit_that_never_binds_stops_at_the_search_bound(follower, motion):
    """The smallest radius scanned: 2**-40 of the stroke above 0 (unbounded), or the first of
    256 radii spread evenly inside (face offset, pivot distance - face offset) (bounded)."""
    sizing = size_base_radius(follower, THETA, *motion, max_pressure_angle=12 * DEG)
    assert sizing.governing == 'search_bound'
    low = max(0.0, -getattr(follower, 'face_offset', 0.0))
    assert low < sizing.base_radius < low + 1e-3
    if isinstance(follower, OscillatingFlat):
        high = follower.pivot_distance - follower.face_offset
        smallest = low + (high - low) / 257
    else:
        smallest = np.ptp(motion[0]) * 2.0 ** -40
    assert sizing.base_radius == pytest.approx(smallest, rel=1e-12)
    assert sizing.tolerance == SIZING_TOLERANCE  # the result states the tolerance it meets


def test_geometry_can_govern():
    """With s down to -1 cm the face needs Rb > 1 cm just to stay above the cam centre."""
    s, ds, d2s = LINEAR
    sizing = size_base_radius(TranslatingFlat(0.03), THETA, s - CM, ds, d2s,
                              max_pressure_angle=0.1)
    assert sizing.governing == 'geometry'
    assert sizing.base_radius == pytest.approx(CM, abs=CLOSED_FORM_TOL)
    assert sizing.base_radius > CM


@pytest.mark.parametrize('kwargs, parameter', [
    ({}, 'max_pressure_angle'),
    ({'max_pressure_angle': math.pi / 2}, 'max_pressure_angle'),
    ({'min_radius': -1.0}, 'min_radius'),
    ({'min_radius': 0.0, 'tolerance': 0.0}, 'tolerance'),
])
def test_invalid_sizing_input_names_the_parameter(kwargs, parameter):
    with pytest.raises(InvalidParameter) as error:
        size_base_radius(TranslatingFlat(0.03), THETA, *LINEAR, **kwargs)
    assert error.value.parameter == parameter


# ---------------------------------------------------------------- sizing on the exact motion

def program(*segments):
    """Return a MotionProgram of (law, start deg, end deg, s_start, s_end) segments."""
    return MotionProgram(tuple(Segment(make_law(law), a * DEG, b * DEG, s0, s1)
                               for law, a, b, s0, s1 in segments))


SEED_PROGRAM = [('dwell', 0, 90, 0.0, 0.0), ('cycloidal', 90, 180, 0.0, 2 * CM),
                ('dwell', 180, 240, 2 * CM, 2 * CM)]
ISSUE_ROLLER = program(*SEED_PROGRAM, ('modified_sine', 240, 360, 2 * CM, 0.0))
ISSUE_FLAT = program(*SEED_PROGRAM, ('simple_harmonic', 240, 360, 2 * CM, 0.0))
OSCILLATION = program(('cycloidal', 0, 150, 0.0, 0.3), ('cycloidal', 150, 360, 0.3, 0.0))
GRID = np.linspace(0.0, 2 * np.pi, 7200, endpoint=False)


def exact_sizing(follower, motion, **kwargs):
    """Size on the 7200-sample grid of the design checks, refined on the exact motion."""
    values = motion.evaluate(GRID)
    return size_base_radius(follower, GRID, values.s, values.ds, values.d2s, program=motion,
                            **kwargs)


def fine_extreme(func, kind):
    """Return the extreme of a scalar-vectorised func: 2e6-sample scan, then minimize_scalar."""
    sign = 1.0 if kind == 'min' else -1.0
    fine = np.linspace(0.0, 2 * np.pi, 2_000_001)
    index = int(np.argmin(sign * func(fine)))
    found = minimize_scalar(lambda x: sign * func(np.array([x]))[0], method='bounded',
                            bounds=(fine[max(index - 1, 0)], fine[min(index + 1, fine.size - 1)]),
                            options={'xatol': 1e-14})
    return sign * min(found.fun, sign * func(fine[index:index + 1])[0])


def roller_peak_deg(base_radius, offset, roller_radius, motion):
    """Return max |pressure angle| (deg) of a ccw translating roller by an independent search.

    tan phi = (ds - e) / (d + s), d = sqrt(Rp^2 - e^2).
    """
    height = math.sqrt((base_radius + roller_radius) ** 2 - offset ** 2)

    def angle(x):
        values = motion.evaluate(x)
        return np.abs(np.degrees(np.arctan((values.ds - offset) / (height + values.s))))
    return fine_extreme(angle, 'max')


def test_issue_roller_radius_meets_30_deg_exactly():
    """Offset -0.8 cm, ccw, cycloidal rise, modified-sine return: the grid sizing was lenient."""
    template = TranslatingRoller(0.04, CM, -0.8 * CM)
    sizing = exact_sizing(template, ISSUE_ROLLER, max_pressure_angle=30 * DEG)
    radius = sizing.base_radius
    assert sizing.governing == 'pressure_angle'
    assert roller_peak_deg(radius, -0.8 * CM, CM, ISSUE_ROLLER) <= 30.0
    assert roller_peak_deg(radius * (1 - 1e-12), -0.8 * CM, CM, ISSUE_ROLLER) > 30.0


def test_issue_flat_face_radius_leaves_no_undercut():
    """rho = Rb + s + s'' >= 0 at the sized radius, by an independent fine search."""
    sizing = exact_sizing(TranslatingFlat(0.04), ISSUE_FLAT, clockwise=True, min_radius=0.0)

    def rho_minus_rb(x):
        values = ISSUE_FLAT.evaluate(x)
        return values.s + values.d2s
    lowest = fine_extreme(rho_minus_rb, 'min')
    assert sizing.governing == 'radius'
    assert sizing.base_radius + lowest >= 0.0
    assert sizing.base_radius * (1 - 1e-12) + lowest < 0.0
    assert sizing.max_base_radius is None  # translating followers: not bounded above


@pytest.mark.parametrize('with_cam, limit', [(True, 20), (False, 25)])
def test_oscillating_roller_reports_both_ends_of_the_feasible_range(with_cam, limit):
    """Both ends hold the limit and it fails just outside (independent fine search)."""
    template = OscillatingRoller(0.03, CM, 0.09, 0.07, with_cam)
    sizing = exact_sizing(template, OSCILLATION, max_pressure_angle=limit * DEG)
    low, high = sizing.base_radius, sizing.max_base_radius
    assert sizing.governing == sizing.max_governing == 'pressure_angle'
    assert low < high

    def peak(base_radius):
        follower = dataclasses.replace(template, base_radius=base_radius)

        def angle(x):
            values = OSCILLATION.evaluate(x)
            return np.abs(cam_geometry(follower, x, values.s, values.ds,
                                       values.d2s).pressure_angle)
        return fine_extreme(angle, 'max')
    assert peak(low) <= limit * DEG and peak(high) <= limit * DEG
    assert peak(low * (1 - 1e-9)) > limit * DEG and peak(high * (1 + 1e-9)) > limit * DEG


def test_oscillating_flat_feasible_to_the_search_bound():
    template = OscillatingFlat(0.03, 0.09, 0.0, False)
    sizing = exact_sizing(template, OSCILLATION, min_radius=0.005)
    assert sizing.governing == 'radius' and sizing.max_governing == 'search_bound'
    assert sizing.base_radius < sizing.max_base_radius < 0.09


def test_program_must_be_a_motion_program():
    with pytest.raises(InvalidParameter) as error:
        size_base_radius(TranslatingFlat(0.03), THETA, *LINEAR, min_radius=0.0, program='x')
    assert error.value.parameter == 'program'


# ---------------------------------------------------------------- seed 002's quick estimate

def test_estimate_formula():
    """R = Cv h / (beta cos eps (tan phi + tan eps)), Rb0 = R - h/2, e = R sin eps, index R/h."""
    h, beta, cv, phi, eps = 0.18, 130 * DEG, 2.0, 30 * DEG, 10 * DEG
    estimate = estimate_base_radius(h, beta, cv, phi, eccentricity_angle=eps)
    mean = cv * h / (beta * math.cos(eps) * (math.tan(phi) + math.tan(eps)))
    assert estimate.mean_radius == pytest.approx(mean, rel=1e-15)
    assert estimate.prime_radius == pytest.approx(mean - h / 2, rel=1e-15)
    assert estimate.offset == pytest.approx(mean * math.sin(eps), rel=1e-15)
    assert estimate.size_index == pytest.approx(mean / h, rel=1e-15)
    assert estimate.big_cam == (mean / h > BIG_CAM_SIZE_INDEX)
    clockwise = estimate_base_radius(h, beta, cv, phi, eccentricity_angle=eps, clockwise=True)
    assert clockwise.offset == -estimate.offset


def test_big_cam_index():
    assert estimate_base_radius(0.01, 30 * DEG, 2.0, 20 * DEG).big_cam
    assert not estimate_base_radius(0.05, 180 * DEG, 1.5, 40 * DEG).big_cam


@pytest.mark.parametrize('eps', [0.0, 8 * DEG, 15 * DEG])
def test_estimate_puts_the_limit_exactly_at_mid_rise(eps, clockwise):
    """Reach the limit exactly at mid-rise with the estimated R and offset R sin eps.

    A cycloidal rise peaks (Cv = 2) at mid-rise; with the roller centre at distance R there, the
    pressure angle equals the limit.
    """
    h, beta, phi = 0.02, 100 * DEG, 30 * DEG
    estimate = estimate_base_radius(h, beta, 2.0, phi, eccentricity_angle=eps,
                                    clockwise=clockwise)
    height = estimate.mean_radius * math.cos(eps) - h / 2  # d, with d + h/2 = R cos eps
    prime = math.hypot(height, estimate.offset)
    theta = np.array([beta / 2])
    follower = TranslatingRoller(prime - 0.005, 0.005, estimate.offset)
    geometry = cam_geometry(follower, theta, *cycloidal(theta, 0.0, beta, h), clockwise=clockwise)
    assert geometry.pressure_angle[0] == pytest.approx(phi, rel=1e-12)
    if eps == 0.0:  # seed 002's Rb0 = R - h/2 is exact without eccentricity only
        assert estimate.prime_radius == pytest.approx(prime, rel=1e-12)


def test_estimate_is_a_lower_bound_for_a_symmetric_rise():
    """ds/(Rp + s) peaks before mid-rise (s still small), so the exact radius is larger."""
    h, beta, phi = 0.02, 100 * DEG, 30 * DEG
    theta = np.linspace(0.0, beta, DENSE_SAMPLES + 1)
    estimate = estimate_base_radius(h, beta, 2.0, phi)
    sizing = size_base_radius(TranslatingRoller(0.03, 0.005), theta, *cycloidal(theta, 0, beta, h),
                              max_pressure_angle=phi)
    assert sizing.base_radius + 0.005 > estimate.prime_radius


@pytest.mark.parametrize('args, parameter', [
    ((0.0, 1.0, 2.0, 0.5), 'rise'),
    ((0.02, 7.0, 2.0, 0.5), 'rise_angle'),
    ((0.02, 1.0, -2.0, 0.5), 'velocity_coefficient'),
    ((0.02, 1.0, 2.0, 0.0), 'max_pressure_angle'),
])
def test_invalid_estimate_input_names_the_parameter(args, parameter):
    with pytest.raises(InvalidParameter) as error:
        estimate_base_radius(*args)
    assert error.value.parameter == parameter


def test_invalid_eccentricity_names_the_parameter():
    with pytest.raises(InvalidParameter) as error:
        estimate_base_radius(0.02, 1.0, 2.0, 0.5, eccentricity_angle=math.pi / 2)
    assert error.value.parameter == 'eccentricity_angle'


@pytest.mark.parametrize('rise_limit, return_limit', [(20 * DEG, 40 * DEG), (40 * DEG, 20 * DEG)],
                         ids=['rise binds', 'return binds'])
def test_separate_rise_and_return_limits_size_each_side_in_closed_form(
        rise_limit, return_limit, clockwise):
    """d >= |v - sigma e| / tan(phi_side) - s on each side (rise: ds >= 0, return: ds <= 0)."""
    sigma, offset = (-1 if clockwise else 1), 0.004
    s, ds, _ = LINEAR
    limit = np.where(ds >= 0.0, math.tan(rise_limit), math.tan(return_limit))
    height = np.max(np.abs(ds - sigma * offset) / limit - s)
    sizing = size_base_radius(TranslatingRoller(0.03, 0.01, offset), THETA, *LINEAR,
                              clockwise=clockwise, max_pressure_angle=rise_limit,
                              max_pressure_angle_return=return_limit)
    assert sizing.base_radius == pytest.approx(math.hypot(height, offset) - 0.01,
                                               abs=CLOSED_FORM_TOL)


@pytest.mark.parametrize('limit, candidate', [(0.0863416, 256), (0.0865170, 255)],
                         ids=['the last scanned', 'the last before a sampled failure'])
def test_a_range_failing_only_between_the_samples_ends_at_the_exact_boundary(limit, candidate):
    """On 360 samples the oscillating flat's smallest convex radius meets the limit at a radius
    the search scans (candidate/257 of the 90 mm bound: the last one, or the last before one
    that fails on the samples too); refined on the exact motion it fails there. The range's
    upper end is where the exact check (check_geometry, refined on the motion, 7200 samples)
    stops holding, below that radius, not the search bound."""
    template = OscillatingFlat(0.03, 0.09, 0.0, False)
    theta = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    values = OSCILLATION.evaluate(theta)
    sizing = size_base_radius(template, theta, values.s, values.ds, values.d2s,
                              program=OSCILLATION, min_radius=limit)

    def holds(base_radius, samples=None):
        follower = dataclasses.replace(template, base_radius=base_radius)
        if samples is not None:
            return check_geometry(cam_geometry(follower, samples[0], *samples[1:]),
                                  min_radius=limit).radius_ok
        motion = OSCILLATION.evaluate(GRID)
        return check_geometry(cam_geometry(follower, GRID, motion.s, motion.ds, motion.d2s),
                              program=OSCILLATION, min_radius=limit).radius_ok
    scanned = 0.09 * candidate / 257
    assert holds(scanned, (theta, values.s, values.ds, values.d2s)) and not holds(scanned)
    low, high = sizing.base_radius, sizing.max_base_radius
    assert sizing.max_governing == 'radius' and low < high < scanned
    assert holds(low) and holds(high)
    assert not holds(low * (1 - 1e-9)) and not holds(high * (1 + 1e-9))
