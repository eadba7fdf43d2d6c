"""Separate rise and return pressure-angle limits: the per-side check, the base-radius sizing
with two limits, and the smallest translating-roller cam (base radius and offset together).

References, all independent of the code under test: the translating roller's closed form
tan phi = (v - sigma e) / (d + s) evaluated on 400 000 angles with the sides taken from the sign
of v; a polar scan of the feasible cam centres (for each direction, the smallest radius meeting
every sampled constraint, minimised over the direction); the limits checked to hold at a result
and to fail just inside it.
"""
import dataclasses
import math

import numpy as np
import pytest

from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry.cam_geometry import cam_geometry
from cam_ros.core.geometry.check import check_geometry
from cam_ros.core.geometry.followers import OscillatingRoller, TranslatingRoller
from cam_ros.core.geometry.joint_sizing import smallest_cam
from cam_ros.core.geometry.sizing import size_base_radius
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

DEG = math.pi / 180
CM = 0.01
GRID = np.linspace(0.0, 2 * np.pi, 7200, endpoint=False)
DENSE = np.linspace(0.0, 2 * np.pi, 400_000, endpoint=False)
ROTATIONS = {'ccw': False, 'cw': True}


def program(*segments):
    """Return a MotionProgram of (law, start deg, end deg, s_start, s_end) segments."""
    return MotionProgram(tuple(Segment(make_law(law), a * DEG, b * DEG, s0, s1)
                               for law, a, b, s0, s1 in segments))


SEED = program(('dwell', 0, 90, 0.0, 0.0), ('cycloidal', 90, 180, 0.0, 2 * CM),
               ('dwell', 180, 240, 2 * CM, 2 * CM), ('simple_harmonic', 240, 360, 2 * CM, 0.0))
# a steep return with no dwells: the return's limit matters
STEEP = program(('cycloidal', 0, 200, 0.0, 3 * CM), ('modified_sine', 200, 300, 3 * CM, 0.0),
                ('dwell', 300, 360, 0.0, 0.0))


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def exact_check(follower, motion, clockwise, **limits):
    """Return check_geometry on the design grid, refined on the exact motion."""
    values = motion.evaluate(GRID)
    geometry = cam_geometry(follower, GRID, values.s, values.ds, values.d2s, clockwise=clockwise)
    return check_geometry(geometry, program=motion, **limits)


def closed_form_sides(motion, prime_radius, offset, clockwise):
    """Return the largest |phi| on the rise (v >= 0) and on the return (v <= 0), densely."""
    sigma = -1 if clockwise else 1
    values = motion.evaluate(DENSE)
    d = math.sqrt(prime_radius ** 2 - offset ** 2)
    phi = np.abs(np.arctan((values.ds - sigma * offset) / (d + values.s)))
    return phi[values.ds >= 0].max(), phi[values.ds <= 0].max()


@pytest.mark.parametrize('offset', [0.0, 0.6 * CM, -0.6 * CM])
def test_each_side_peak_is_the_closed_form_never_below_it(offset, clockwise):
    follower = TranslatingRoller(3 * CM, 1 * CM, offset)
    check = exact_check(follower, STEEP, clockwise, max_pressure_angle=30 * DEG)
    rise, ret = closed_form_sides(STEEP, 4 * CM, offset, clockwise)
    assert check.pressure_angle_rise[0] == pytest.approx(rise, rel=1e-9)
    assert check.pressure_angle_return[0] == pytest.approx(ret, rel=1e-9)
    assert check.pressure_angle_rise[0] >= rise - 1e-15
    assert check.pressure_angle_return[0] >= ret - 1e-15
    assert max(rise, ret) == pytest.approx(check.max_pressure_angle, rel=1e-9)


def test_each_side_is_judged_by_its_own_limit(clockwise):
    follower = TranslatingRoller(3 * CM, 1 * CM, 0.0)
    check = exact_check(follower, STEEP, clockwise, max_pressure_angle=30 * DEG)
    rise, ret = check.pressure_angle_rise[0], check.pressure_angle_return[0]
    assert ret > rise  # the steep return is the worse side here
    between = 0.5 * (rise + ret)
    assert exact_check(follower, STEEP, clockwise, max_pressure_angle=between,
                       max_pressure_angle_return=ret * (1 + 1e-9)).pressure_angle_ok is True
    assert exact_check(follower, STEEP, clockwise, max_pressure_angle=between,
                       max_pressure_angle_return=ret * (1 - 1e-9)).pressure_angle_ok is False
    assert exact_check(follower, STEEP, clockwise, max_pressure_angle=rise * (1 - 1e-9),
                       max_pressure_angle_return=ret * 2).pressure_angle_ok is False
    # one limit for both, as before: the overall peak decides
    assert exact_check(follower, STEEP, clockwise,
                       max_pressure_angle=between).pressure_angle_ok is False


def test_a_dwell_with_offset_counts_for_both_sides():
    """On a dwell the follower neither rises nor returns: the stricter limit applies."""
    motion = program(('dwell', 0, 360, 0.0, 0.0))
    follower = TranslatingRoller(3 * CM, 1 * CM, 2 * CM)  # |phi| = asin(e / Rp) = 30 deg
    check = exact_check(follower, motion, False, max_pressure_angle=31 * DEG,
                        max_pressure_angle_return=29 * DEG)
    assert check.pressure_angle_rise[0] == pytest.approx(30 * DEG, rel=1e-12)
    assert check.pressure_angle_return[0] == pytest.approx(30 * DEG, rel=1e-12)
    assert check.pressure_angle_ok is False


def test_sizing_with_two_limits_holds_at_the_radius_and_fails_below(clockwise):
    follower = OscillatingRoller(0.03, 0.01, 0.09, 0.07, False)
    arm = program(('cycloidal', 0, 150, 0.0, 0.3), ('cycloidal', 150, 250, 0.3, 0.0),
                  ('dwell', 250, 360, 0.0, 0.0))
    limits = dict(max_pressure_angle=20 * DEG, max_pressure_angle_return=35 * DEG)
    values = arm.evaluate(GRID)
    sizing = size_base_radius(follower, GRID, values.s, values.ds, values.d2s,
                              clockwise=clockwise, program=arm, **limits)
    assert sizing.governing in ('pressure_angle_rise', 'pressure_angle_return')
    at = exact_check(sizing.follower, arm, clockwise, **limits)
    assert at.pressure_angle_ok is True
    below = dataclasses.replace(follower, base_radius=sizing.base_radius * (1 - 1e-6))
    assert exact_check(below, arm, clockwise, **limits).pressure_angle_ok is False
    # the governing side is the one that fails just below
    failing = exact_check(below, arm, clockwise, **limits)
    side = sizing.governing.removeprefix('pressure_angle_')
    peak = failing.pressure_angle_rise if side == 'rise' else failing.pressure_angle_return
    assert peak[0] > limits['max_pressure_angle' if side == 'rise'
                            else 'max_pressure_angle_return']


def polar_scan(motion, rise_limit, return_limit, clockwise):
    """Return the smallest prime radius over cam centre directions, from sampled constraints.

    For the centre at r (sin a, cos a) in the (sigma e, d) plane, each sampled angle with its
    side's t = tan(limit) asks |v - r sin a| <= t (s + r cos a): linear in r, so the smallest r
    meeting all of them is a maximum of ratios; it is minimised over a by a fine scan then a
    bounded search.
    """
    from scipy.optimize import minimize_scalar

    values = motion.evaluate(DENSE)
    v, s = values.ds, values.s
    blocks = [(v >= 0, math.tan(rise_limit)), (v <= 0, math.tan(return_limit))]

    def radius(a):
        low, high = 0.0, math.inf
        for side, t in blocks:
            for sign in (1.0, -1.0):  # r (t cos a + sign sin a) >= sign v - t s
                slope = t * math.cos(a) + sign * math.sin(a)
                rhs = sign * v[side] - t * s[side]
                if slope > 0.0:
                    low = max(low, float(np.max(rhs / slope)))
                elif slope < 0.0:
                    high = min(high, float(np.min(rhs / slope)))
                elif np.any(rhs > 0.0):
                    return math.inf
        return low if low <= high else math.inf

    scan = np.linspace(-1.4, 1.4, 281)
    radii = [radius(a) for a in scan]
    best = scan[int(np.argmin(radii))]
    found = minimize_scalar(radius, bounds=(best - 0.01, best + 0.01), method='bounded',
                            options={'xatol': 1e-12})
    sigma = -1 if clockwise else 1
    return found.fun, sigma * found.fun * math.sin(found.x)


@pytest.mark.parametrize('limits', [(30, 30), (30, 45), (25, 60)])
@pytest.mark.parametrize('motion', [SEED, STEEP], ids=['seed', 'steep'])
def test_smallest_cam_matches_a_polar_scan_and_meets_both_limits(motion, limits, clockwise):
    rise, ret = limits[0] * DEG, limits[1] * DEG
    cam = smallest_cam(1 * CM, motion, max_pressure_angle=rise, max_pressure_angle_return=ret,
                       clockwise=clockwise)
    prime, offset = polar_scan(motion, rise, ret, clockwise)
    assert cam.prime_radius == pytest.approx(prime, rel=1e-6)
    assert cam.offset == pytest.approx(offset, rel=1e-4, abs=1e-8)
    assert cam.base_radius == pytest.approx(cam.prime_radius - 1 * CM, rel=1e-12)
    follower = TranslatingRoller(cam.base_radius, 1 * CM, cam.offset)
    check = exact_check(follower, motion, clockwise, max_pressure_angle=rise,
                        max_pressure_angle_return=ret)
    assert check.pressure_angle_ok is True
    assert check.pressure_angle_rise[0] <= rise and check.pressure_angle_return[0] <= ret
    # on the safe side, but by no more than a rounding: the limit is met with equality
    worst = max(check.pressure_angle_rise[0] / rise, check.pressure_angle_return[0] / ret)
    assert worst == pytest.approx(1.0, abs=1e-9)


def test_no_smaller_cam_meets_the_limits(clockwise):
    """Every cam centre inside the result's prime circle breaks a limit (the dense closed form)."""
    rise, ret = 30 * DEG, 45 * DEG
    cam = smallest_cam(1 * CM, SEED, max_pressure_angle=rise, max_pressure_angle_return=ret,
                       clockwise=clockwise)
    sigma = -1 if clockwise else 1
    inside = cam.prime_radius * (1 - 1e-6)
    centre = math.atan2(sigma * cam.offset, math.sqrt(cam.prime_radius ** 2 - cam.offset ** 2))
    for a in centre + np.linspace(-1.2, 1.2, 41):
        offset = sigma * inside * math.sin(a)
        peaks = closed_form_sides(SEED, inside, offset, clockwise)
        assert peaks[0] > rise or peaks[1] > ret, a


def test_governing_names_the_limits_met():
    one = smallest_cam(1 * CM, SEED, max_pressure_angle=30 * DEG)
    assert one.governing == 'pressure_angle'
    two = smallest_cam(1 * CM, SEED, max_pressure_angle=30 * DEG,
                       max_pressure_angle_return=45 * DEG)
    assert two.governing == 'pressure_angle_rise_and_return'
    lax = smallest_cam(1 * CM, SEED, max_pressure_angle=30 * DEG,
                       max_pressure_angle_return=89 * DEG)
    assert lax.governing == 'pressure_angle_rise'
    assert lax.prime_radius < two.prime_radius < one.prime_radius


def test_a_return_limit_needs_a_rise_limit_and_a_valid_angle():
    values = SEED.evaluate(GRID)
    geometry = cam_geometry(TranslatingRoller(0.03, 0.01), GRID, values.s, values.ds, values.d2s)
    with pytest.raises(InvalidParameter, match='max_pressure_angle'):
        check_geometry(geometry, max_pressure_angle_return=0.5)
    with pytest.raises(InvalidParameter, match=r'max_pressure_angle_return = 2\.0.*\(0, pi/2\)'):
        check_geometry(geometry, max_pressure_angle=0.5, max_pressure_angle_return=2.0)


def flat_config(**changes):
    flat = {'follower.type': 'translating_roller', 'follower.base_radius': 0.03,
            'follower.roller_radius': 0.01, 'motion.laws': ['cycloidal', 'cycloidal'],
            'motion.start_deg': [0.0, 180.0], 'motion.end_deg': [180.0, 360.0],
            'motion.start_position': [0.0, 0.02], 'motion.end_position': [0.02, 0.0]}
    flat.update(changes)
    return parse_parameters(flat)


def test_the_return_limit_defaults_to_the_rise_limit_and_is_range_checked():
    assert flat_config().pressure_angle_return_limit == pytest.approx(30 * DEG)
    assert flat_config(**{'limits.pressure_angle_deg': 25.0}).pressure_angle_return_limit \
        == pytest.approx(25 * DEG)
    given = flat_config(**{'limits.pressure_angle_return_deg': 45.0})
    assert (given.pressure_angle_limit, given.pressure_angle_return_limit) == pytest.approx(
        (30 * DEG, 45 * DEG))
    with pytest.raises(InvalidParameter, match=r'limits.pressure_angle_return_deg = 95.0: '
                                               r'must be <= 89'):
        flat_config(**{'limits.pressure_angle_return_deg': 95.0})


def test_the_optimum_is_the_apex_of_the_kinematics_notes_wedge(clockwise):
    """The notes' closed form: A = min(s - s' cot L_rise), B = min(s + s' cot L_return) over
    each side, apex x* = (B - A) / (cot L_rise + cot L_return), d* = -A - x* cot L_rise."""
    rise, ret = 30 * DEG, 45 * DEG
    values = SEED.evaluate(DENSE)
    s, v = values.s, values.ds
    a = np.min((s - v / math.tan(rise))[v >= 0])
    b = np.min((s + v / math.tan(ret))[v <= 0])
    x = (b - a) / (1 / math.tan(rise) + 1 / math.tan(ret))
    d = -a - x / math.tan(rise)
    cam = smallest_cam(1 * CM, SEED, max_pressure_angle=rise, max_pressure_angle_return=ret,
                       clockwise=clockwise)
    assert cam.governing == 'pressure_angle_rise_and_return'
    assert cam.prime_radius == pytest.approx(math.hypot(x, d), rel=1e-8)
    assert cam.offset == pytest.approx((-1 if clockwise else 1) * x, rel=1e-7)


@pytest.mark.parametrize('motion', [SEED, STEEP], ids=['seed', 'steep'])
def test_a_lax_return_limit_puts_the_optimum_at_the_foot_of_the_rise_line(motion, clockwise):
    """Rise at 60 deg, return at 89: one line binds, d >= -A - x cot L with
    A = min(s - s' cot L) over the rise; the smallest cam is the foot of the perpendicular from
    the origin on it (prime radius -A sin L), not a meeting of two lines (and the polar scan)."""
    rise, ret = 60 * DEG, 89 * DEG
    cam = smallest_cam(1 * CM, motion, max_pressure_angle=rise, max_pressure_angle_return=ret,
                       clockwise=clockwise)
    prime, offset = polar_scan(motion, rise, ret, clockwise)
    assert cam.governing == 'pressure_angle_rise'
    assert cam.prime_radius == pytest.approx(prime, rel=1e-6)
    assert cam.offset == pytest.approx(offset, rel=1e-4, abs=1e-8)
    # the foot's closed form: the line d = -A - x cot L at distance A sin L from the origin
    values = motion.evaluate(DENSE)
    a = np.min((values.s - values.ds / math.tan(rise))[values.ds >= 0])
    assert cam.prime_radius == pytest.approx(-a * math.sin(rise), rel=1e-7)
    peaks = closed_form_sides(motion, cam.prime_radius, cam.offset, clockwise)
    assert (cam.rise_peak, cam.return_peak) == pytest.approx(peaks, rel=1e-6)
    assert cam.rise_peak <= rise and cam.rise_peak == pytest.approx(rise, rel=1e-9)
