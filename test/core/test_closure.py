"""Form-closed cams (geometry/closure.py, dynamics/flanks.py) against closed forms.

References: the translating roller's pitch-curve radius (the kinematics notes) evaluated on
720 000 angles, so a groove's flank radii are rho_p - w and |rho_p| - w; offsets of a circle
(the Scotch yoke's eccentric cam) are circles; roller 2 of a conjugate yoke at (e, d + s - B)
rotated into the cam frame; the crossovers of a groove without spring are the zeros of
m w^2 d2s/dtheta2 + F, in closed form for cycloidal and simple harmonic segments; a motion with
s(theta) + s(theta + pi) constant is of constant breadth.
"""
import math

import numpy as np
import pytest

from cam_ros.core import build_design, InvalidParameter
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.geometry.cam_geometry import cam_geometry
from cam_ros.core.geometry.closure import (conjugate_follower, ConjugateRoller, constant_breadth,
                                           groove_contours, groove_flanks, second_roller_problem)
from cam_ros.core.geometry.followers import (OscillatingRoller, TranslatingFlat,
                                             TranslatingRoller)
from cam_ros.core.geometry.machining import cam_contour
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

DEG = math.pi / 180
MM = 1e-3
RISE = 20 * MM
DENSE = np.linspace(0.0, 2 * math.pi, 720_000, endpoint=False)
SEED = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * DEG, 0.0, 0.0),
                      Segment(make_law('cycloidal'), 90 * DEG, 180 * DEG, 0.0, RISE),
                      Segment(make_law('dwell'), 180 * DEG, 240 * DEG, RISE, RISE),
                      Segment(make_law('simple_harmonic'), 240 * DEG, 2 * math.pi, RISE, 0.0)))
STEEP = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * DEG, 0.0, 0.0),
                       Segment(make_law('cycloidal'), 90 * DEG, 120 * DEG, 0.0, RISE),
                       Segment(make_law('dwell'), 120 * DEG, 240 * DEG, RISE, RISE),
                       Segment(make_law('simple_harmonic'), 240 * DEG, 2 * math.pi, RISE, 0.0)))
#: The seed's laws with the rise first: the extremes of its flanks lie before 1 rad.
EARLY = MotionProgram((Segment(make_law('cycloidal'), 0.0, 90 * DEG, 0.0, RISE),
                       Segment(make_law('dwell'), 90 * DEG, 150 * DEG, RISE, RISE),
                       Segment(make_law('simple_harmonic'), 150 * DEG, 270 * DEG, RISE, 0.0),
                       Segment(make_law('dwell'), 270 * DEG, 2 * math.pi, 0.0, 0.0)))
YOKE = MotionProgram((Segment(make_law('simple_harmonic'), 0.0, math.pi, 0.0, RISE),
                      Segment(make_law('simple_harmonic'), math.pi, 2 * math.pi, RISE, 0.0)))
ROTATIONS = {'ccw': False, 'cw': True}


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def pitch_radius(theta, motion, base, roller, offset, sigma):
    """Return the translating roller's signed pitch-curve radius (the notes' closed form)."""
    values = motion.evaluate(theta)
    s, v, a = values.s, values.ds, values.d2s
    d = math.sqrt((base + roller) ** 2 - offset ** 2)
    along, across = d + s, v - sigma * offset
    return np.hypot(along, across) ** 3 / (
        along ** 2 + across * (2 * v - sigma * offset) - a * along)


CAMS = {'seed': (15 * MM, SEED), 'rise first': (15 * MM, EARLY),
        'pitch radii over 1 m': (1500 * MM, SEED)}


@pytest.mark.parametrize('clearance', [0.0, 1 * MM])
@pytest.mark.parametrize('cam', CAMS)
def test_flank_radii_are_the_pitch_radius_less_the_half_width(cam, clearance, clockwise):
    base, program = CAMS[cam]
    follower = TranslatingRoller(base, 8 * MM, 4 * MM)
    flanks = groove_flanks(follower, program, clockwise, clearance)
    rho = pitch_radius(DENSE, program, base, 8 * MM, 4 * MM, -1 if clockwise else 1)
    half = 8 * MM + clearance / 2
    convex = rho[rho > 0].min()
    concave = -rho[rho < 0].max() if (rho < 0).any() else math.inf  # inf: no concave part
    assert flanks['inner'].radius_of_curvature_min == pytest.approx(convex - half, rel=1e-9)
    assert flanks['outer'].radius_of_curvature_min == pytest.approx(concave - half, rel=1e-9)
    assert flanks['inner'].radius_of_curvature_min <= convex - half  # refined: never above
    assert flanks['outer'].radius_of_curvature_min <= concave - half
    assert not flanks['inner'].undercut and not flanks['outer'].undercut


def test_an_outer_flank_tighter_than_the_roller_is_undercut():
    rho = pitch_radius(DENSE, STEEP, 15 * MM, 8 * MM, 4 * MM, 1)
    concave = -rho[rho < 0].max()
    roller = concave * 1.01
    flanks = groove_flanks(TranslatingRoller(23 * MM - roller, roller, 4 * MM), STEEP, False)
    assert flanks['outer'].undercut and flanks['outer'].radius_of_curvature_min < 0
    assert not flanks['inner'].undercut


def test_groove_flanks_are_offsets_of_the_pitch_curve(clockwise):
    follower = TranslatingRoller(30 * MM, 8 * MM, 4 * MM)
    sigma = -1 if clockwise else 1
    flanks = groove_contours(follower, SEED, clockwise, 2 * MM)
    theta = np.linspace(0.0, 2 * math.pi, 2001)
    inner, inner_normal, _ = flanks['inner'].evaluate(theta)
    outer, outer_normal, _ = flanks['outer'].evaluate(theta)
    values = SEED.evaluate(theta)
    d = math.sqrt((38 * MM) ** 2 - (4 * MM) ** 2)
    c, n = np.cos(theta), np.sin(sigma * theta)
    pitch = np.array((c * 4 * MM + n * (d + values.s), -n * 4 * MM + c * (d + values.s)))
    assert 0.5 * (inner + outer) == pytest.approx(pitch, abs=1e-15)
    assert np.hypot(*(outer - inner)) == pytest.approx(2 * 9 * MM, rel=1e-12)
    assert inner_normal == pytest.approx(-outer_normal)  # both into the groove
    assert np.sum((outer - inner) * inner_normal, axis=0) == pytest.approx(18 * MM, rel=1e-12)


def test_a_groove_about_a_convex_pitch_curve_has_no_convex_outer_flank():
    flanks = groove_flanks(TranslatingRoller(30 * MM, 8 * MM, 0.0), YOKE, False, 1 * MM)
    rho = pitch_radius(DENSE, YOKE, 30 * MM, 8 * MM, 0.0, 1)
    assert (rho > 0).all()  # a convex pitch curve: the outer flank bends away everywhere
    assert flanks['inner'].radius_of_curvature_min == pytest.approx(rho.min() - 8.5 * MM,
                                                                    rel=1e-9)
    assert flanks['outer'].radius_of_curvature_min == math.inf
    assert not flanks['outer'].undercut


def test_the_flanks_of_a_circle_are_circles():
    """Offsets of a circle: the Scotch yoke's eccentric cam of radius R about (0, -h/2)."""
    circle = cam_contour(TranslatingFlat(40 * MM), YOKE, False)
    radius, centre, half = 50 * MM, np.array([[0.0], [-10 * MM]]), 6 * MM
    theta = np.linspace(0.0, 2 * math.pi, 999)
    inner = circle.offset(-half).evaluate(theta)
    outer = circle.offset(half).flipped().evaluate(theta)
    assert np.hypot(*(inner[0] - centre)) == pytest.approx(radius - half, rel=1e-12)
    assert np.hypot(*(outer[0] - centre)) == pytest.approx(radius + half, rel=1e-12)
    assert inner[2] == pytest.approx(1 / (radius - half), rel=1e-9)  # rho + ... convex
    assert outer[2] == pytest.approx(-1 / (radius + half), rel=1e-9)  # concave from inside


def test_conjugate_roller_two_traces_its_closed_form(clockwise):
    follower = TranslatingRoller(30 * MM, 8 * MM, 4 * MM)
    second = conjugate_follower(follower, SEED)
    d = follower.prime_height
    assert second.spacing == pytest.approx(2 * d + RISE, rel=1e-12)  # s_min 0, s_max 20 mm
    sigma = -1 if clockwise else 1
    theta = np.linspace(0.0, 2 * math.pi, 997)
    values = SEED.evaluate(theta)
    profile = second._geometry(theta, sigma, values.s, values.ds, values.d2s)
    y = d + values.s - second.spacing
    c, n = np.cos(theta), np.sin(sigma * theta)
    assert profile.pitch == pytest.approx(np.array((c * 4 * MM + n * y, -n * 4 * MM + c * y)),
                                          abs=1e-15)
    # the mirror image of a roller at B - d - s: |tan phi| = |v - sigma e| / (B - d - s)
    expected = np.arctan(np.abs(values.ds - sigma * 4 * MM) / (second.spacing - d - values.s))
    assert np.abs(profile.pressure_angle) == pytest.approx(expected, abs=1e-12)


def test_constant_breadth_holds_for_a_harmonic_turn_and_not_for_the_seed():
    yoke = constant_breadth(YOKE)
    assert yoke.holds and yoke.spread < 1e-15
    seed = constant_breadth(SEED)
    values = SEED.evaluate(DENSE[DENSE < math.pi]).s + SEED.evaluate(
        DENSE[DENSE < math.pi] + math.pi).s
    assert not seed.holds
    assert seed.spread == pytest.approx(np.ptp(values), rel=1e-9)
    assert seed.spread >= np.ptp(values)


def config(**changes):
    flat = {'length_unit': 'mm', 'rotation': 'counterclockwise',
            'follower.type': 'translating_roller', 'follower.base_radius': 30.0,
            'follower.roller_radius': 8.0, 'follower.closure': 'groove',
            'motion.laws': ['dwell', 'cycloidal', 'dwell', 'simple_harmonic'],
            'motion.start_deg': [0.0, 90.0, 180.0, 240.0],
            'motion.end_deg': [90.0, 180.0, 240.0, 360.0],
            'motion.start_position': [0.0, 0.0, 20.0, 20.0],
            'motion.end_position': [0.0, 20.0, 20.0, 0.0],
            'dynamics.mass': 2.0, 'contact.face_width': 10.0, 'cam_speed': 30.0}
    flat.update(changes)
    return parse_parameters(flat)


def test_crossovers_are_the_sign_changes_of_the_required_force():
    """Q = m w^2 d2s/dtheta2 (no spring, no load): zero mid-rise and mid-return."""
    loads = build_design(config()).side_loads
    assert np.array(loads.crossovers) == pytest.approx([135 * DEG, 300 * DEG], abs=1e-12)
    inner, outer = loads.sides
    assert np.array(inner.spans) == pytest.approx(np.array([[300 * DEG, 135 * DEG]]), abs=1e-12)
    assert np.array(outer.spans) == pytest.approx(np.array([[135 * DEG, 300 * DEG]]), abs=1e-12)


def test_a_constant_load_moves_the_crossovers_and_adds_one_at_a_jump():
    load, mass, omega = 20.0, 2.0, 30.0
    design = build_design(config(**{'dynamics.external_force': load}))
    loads = design.side_loads
    # cycloidal rise over 90-180 deg: d2s = 2 pi h / b^2 sin(2 pi u), Q = m w^2 d2s + F = 0
    # twice; the SHM return over 240-360 deg starts at d2s = -h/2 (pi/b)^2 (a jump of Q
    # through 0 at 240 deg) and reaches Q = 0 where cos(pi u) = F / (m w^2 h/2 (pi/b)^2).
    beta = math.pi / 2
    shift = math.asin(load / (2 * math.pi * RISE / beta ** 2 * mass * omega ** 2))
    rise = [90 * DEG + beta * (0.5 + shift / (2 * math.pi)),
            90 * DEG + beta * (1 - shift / (2 * math.pi))]
    beta = 2 * math.pi / 3
    peak = RISE / 2 * (math.pi / beta) ** 2 * mass * omega ** 2
    back = 240 * DEG + beta * math.acos(load / peak) / math.pi
    expected = rise + [240 * DEG, back]
    assert np.array(loads.crossovers) == pytest.approx(expected, abs=1e-12)
    inner, outer = loads.sides
    assert np.array(outer.spans) == pytest.approx(np.array([expected[:2], expected[2:]]),
                                                  abs=1e-12)
    assert np.array(inner.spans) == pytest.approx(np.array([expected[1:3], expected[3::-3]]),
                                                  abs=1e-12)
    # the largest contact force on each flank: |Q| / cos(phi), densely
    values = design.program.evaluate(DENSE)
    q = mass * omega ** 2 * values.d2s + load
    cosine = np.cos(np.arctan(values.ds / (38 * MM + values.s)))
    assert inner.contact_force_max == pytest.approx((q / cosine).max(), rel=1e-9)
    assert outer.contact_force_max == pytest.approx((-q / cosine).max(), rel=1e-9)


def test_a_groove_never_jumps_but_an_undercut_flank_fails_the_verdict():
    fine = build_design(config(**{'cam_speed': 300.0}))  # a spring cam would leave at this speed
    assert fine.dynamics_check.jump and fine.ok
    steep = {'motion.end_deg': [90.0, 120.0, 240.0, 360.0],
             'motion.start_deg': [0.0, 90.0, 120.0, 240.0]}
    rho = pitch_radius(DENSE, STEEP, 30 * MM, 8 * MM, 0.0, 1)
    concave = -rho[rho < 0].max() / MM  # mm
    sizes = {'follower.roller_radius': concave * 1.01,
             'follower.base_radius': 38.0 - concave * 1.01}
    tight = build_design(config(**steep, **sizes))
    assert tight.closure.sides['outer'].undercut and not tight.ok
    assert any('outer flank is undercut' in note for note in tight.warnings())
    spring = build_design(config(**steep, **sizes, **{'follower.closure': 'force'}))
    assert not spring.check.undercut  # force closure never touches the concave side


@pytest.mark.parametrize('changes, parameter, rule', [
    ({'follower.type': 'translating_flat'}, 'follower.closure', 'needs a roller follower'),
    ({'dynamics.spring_rate': 1000.0}, 'dynamics.spring_rate', 'needs no return spring'),
    ({'follower.closure': 'force', 'follower.groove_clearance': 0.1},
     'follower.groove_clearance', 'closure: groove only'),
    ({'follower.conjugate_angle_deg': 90.0}, 'follower.conjugate_angle_deg',
     'oscillating_roller with follower.closure: conjugate only'),
    ({'follower.closure': 'spring'}, 'follower.closure', 'must be one of force, groove, '
                                                         'conjugate'),
])
def test_closure_config_errors_name_the_parameter(changes, parameter, rule):
    with pytest.raises(InvalidParameter) as raised:
        build_design(config(**changes))
    assert raised.value.parameter == parameter and rule in str(raised.value)


def test_an_oscillating_conjugate_arm_needs_an_angle_clear_of_the_swing():
    arm = {'follower.type': 'oscillating_roller', 'follower.closure': 'conjugate',
           'follower.pivot_distance': 90.0, 'follower.arm_length': 70.0,
           'dynamics.mass': 0.0, 'dynamics.arm_inertia': 0.01,
           'motion.start_position': [0.0, 0.0, 15.0, 15.0],
           'motion.end_position': [0.0, 15.0, 15.0, 0.0]}
    with pytest.raises(InvalidParameter) as raised:
        build_design(config(**arm))
    assert raised.value.parameter == 'follower.conjugate_angle_deg'
    design = build_design(config(**arm, **{'follower.conjugate_angle_deg': 100.0}))
    second = design.closure.second
    assert second is not None and design.closure.sides['second'].radius_of_curvature_min > 0
    assert design.side_loads.crossovers  # the load changes cams


def test_per_angle_stress_is_the_carrying_flanks_hertz_pressure():
    """p0 = sqrt(w E* K / pi), w = |N| / face width, K = 1/rho_flank + 1/Rr; the outer flank is
    seen from the roller as concave, rho = -(rho_p + Rr)."""
    design = build_design(config())
    theta = np.linspace(0.0, 2 * math.pi, 3601, endpoint=False)
    state = design.evaluate(theta)
    values = SEED.evaluate(theta)
    q = 2.0 * 30.0 ** 2 * values.d2s
    rho = pitch_radius(theta, SEED, 30 * MM, 8 * MM, 0.0, 1)
    contact = q / np.cos(np.arctan(values.ds / (38 * MM + values.s)))
    flank = np.where(q >= 0, rho - 8 * MM, -(rho + 8 * MM))
    modulus = 1 / (2 * (1 - 0.3 ** 2) / 207e9)
    expected = np.sqrt(np.abs(contact) / (10 * MM) * modulus * (1 / flank + 1 / (8 * MM))
                       / math.pi)
    assert state.dynamics.contact_force == pytest.approx(contact, rel=1e-9, abs=1e-9)
    assert state.dynamics.contact_stress == pytest.approx(expected, rel=1e-9, abs=1e-3)
    loads = design.side_loads
    assert max(side.contact_stress_max for side in loads.sides) == pytest.approx(
        design.dynamics_check.contact_stress_max, rel=1e-9)


def to_cam_frame(theta, sigma, point):
    """Turn a fixed-frame point (or vector) at cam angle theta into the cam frame."""
    c, n = np.cos(theta), np.sin(sigma * theta)
    return np.array((c * point[0] + n * point[1], -n * point[0] + c * point[1]))


def test_conjugate_arm_two_traces_its_closed_form(clockwise):
    """Arm 2 at psi0 + s - gamma: its roller centre written out, and the pitch curve's
    curvature and pressure angle from central differences of that centre (not from the code's
    derivatives)."""
    swing = 15 * DEG
    program = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * DEG, 0.0, 0.0),
                             Segment(make_law('cycloidal'), 90 * DEG, 200 * DEG, 0.0, swing),
                             Segment(make_law('dwell'), 200 * DEG, 240 * DEG, swing, swing),
                             Segment(make_law('cycloidal'), 240 * DEG, 2 * math.pi, swing, 0.0)))
    first = OscillatingRoller(30 * MM, 8 * MM, 90 * MM, 70 * MM, True)
    second = conjugate_follower(first, program, 100 * DEG)
    sigma = -1 if clockwise else 1
    lam, arm, pivot = sigma, 70 * MM, 90 * MM  # the arm turns with the cam

    def centre(theta):
        psi = first.initial_arm_angle + program.evaluate(theta).s - 100 * DEG
        return to_cam_frame(theta, sigma, (lam * arm * np.sin(psi), pivot - arm * np.cos(psi)))

    h = 1e-4
    theta = np.linspace(0.0, 2 * math.pi, 2001, endpoint=False)
    theta = theta[np.abs(theta[:, np.newaxis] - np.array(program.breaks)).min(axis=1) > 3 * h]
    values = program.evaluate(theta)
    profile = second._geometry(theta, sigma, values.s, values.ds, values.d2s)
    np.testing.assert_allclose(profile.pitch, centre(theta), rtol=0.0, atol=1e-15)
    before, here, after = centre(theta - h), centre(theta), centre(theta + h)
    tangent, bend = (after - before) / (2 * h), (after - 2 * here + before) / h ** 2
    curvature = (tangent[0] * bend[1] - tangent[1] * bend[0]) / np.hypot(*tangent) ** 3
    sign = np.sign(np.median(curvature * profile.pitch_curvature))
    np.testing.assert_allclose(profile.pitch_curvature, sign * curvature, rtol=1e-5)
    # sin(pressure angle) = the unit tangent (fixed frame) along the roller's motion, w.
    c, n = np.cos(theta), np.sin(sigma * theta)
    fixed = np.array((c * tangent[0] - n * tangent[1], n * tangent[0] + c * tangent[1]))
    psi = first.initial_arm_angle + values.s - 100 * DEG
    along = (fixed[0] * lam * np.cos(psi) + fixed[1] * np.sin(psi)) / np.hypot(*fixed)
    np.testing.assert_allclose(np.abs(np.sin(profile.pressure_angle)), np.abs(along),
                               rtol=0.0, atol=1e-8)
    assert np.abs(along).max() > 0.1  # the arm moves: the check is not of zeros


def test_a_conjugate_yokes_cam_two_is_checked_with_the_limits_swapped(clockwise):
    """Cam 2 drives the return: its rise is checked against the return's limit and the other
    way round; its largest pressure angle is roller 2's closed form, refined."""
    design = build_design(config(**{
        'follower.closure': 'conjugate', 'follower.offset': 4.0,
        'rotation': 'clockwise' if clockwise else 'counterclockwise',
        'limits.pressure_angle_deg': 35.0, 'limits.pressure_angle_return_deg': 25.0}))
    closure = design.closure
    assert closure.closure == 'conjugate' and closure.breadth is None  # offset: no breadth test
    second = closure.second
    assert second.pressure_angle_limit == pytest.approx(25 * DEG, rel=1e-15)
    assert second.pressure_angle_return_limit == pytest.approx(35 * DEG, rel=1e-15)
    sigma, offset = (-1 if clockwise else 1), 4 * MM
    d = math.sqrt(38 ** 2 - 4 ** 2) * MM
    values = SEED.evaluate(DENSE)
    worst = np.arctan(np.abs(values.ds - sigma * offset) / (d + RISE - values.s)).max()
    assert second.max_pressure_angle == pytest.approx(worst, rel=1e-9)
    assert second.max_pressure_angle >= worst
    assert closure.sides['second'].radius_of_curvature_min == second.min_radius


def test_a_conjugate_yoke_without_offset_reports_its_constant_breadth_spread():
    design = build_design(config(**{'follower.closure': 'conjugate'}))
    breadth = design.closure.breadth
    half = DENSE[DENSE < math.pi]
    spread = np.ptp(SEED.evaluate(half).s + SEED.evaluate(half + math.pi).s)
    assert not breadth.holds
    assert breadth.spread == pytest.approx(spread, rel=1e-9) and breadth.spread >= spread
    assert build_design(config(**{'follower.closure': 'force'})).closure is None


def test_a_yokes_roller_two_is_refused_once_it_reaches_the_cam_centre():
    """Roller 2's centre is at height d + s - B: refused as soon as d + max(s) >= B on the
    samples, the tie included; conjugate_follower's B = 2 d + min s + max s always clears it."""
    follower = TranslatingRoller(30 * MM, 8 * MM, 4 * MM)
    theta = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    values = SEED.evaluate(theta)
    d = follower.prime_height
    reach = d + values.s.max()
    for spacing, refused in ((0.5 * reach, True), (reach, True),
                             (reach * (1 + 1e-12), False), (2 * d + RISE, False)):
        second = ConjugateRoller(30 * MM, 8 * MM, 4 * MM, spacing)
        if refused:
            with pytest.raises(InvalidParameter, match='roller 2 must stay below the cam centre'):
                cam_geometry(second, theta, values.s, values.ds, values.d2s)
        else:
            cam_geometry(second, theta, values.s, values.ds, values.d2s)
    assert second_roller_problem(follower, SEED, 0.0) is None


def test_arm_two_is_refused_exactly_where_its_angle_leaves_zero_to_pi():
    """Arm 2 stands at psi0 + s - gamma + pi (the arm turned back by gamma): the pair is refused
    for a conjugate angle gamma exactly when that leaves (0, pi) over the swing (dense)."""
    swing = 15 * DEG
    program = MotionProgram((Segment(make_law('cycloidal'), 0.0, math.pi, 0.0, swing),
                             Segment(make_law('cycloidal'), math.pi, 2 * math.pi, swing, 0.0)))
    first = OscillatingRoller(30 * MM, 8 * MM, 90 * MM, 70 * MM, True)
    s = program.evaluate(DENSE).s
    low, high = first.initial_arm_angle + s.min() + math.pi, first.initial_arm_angle + s.max()
    verdicts = []
    for gamma in np.linspace(1 * DEG, 359 * DEG, 359):
        ends = (low - gamma, high + math.pi - gamma)
        if min(abs(end - edge) for end in ends for edge in (0.0, math.pi)) < 1e-6:
            continue  # a tie with the edge: the samples decide
        problem = second_roller_problem(first, program, gamma)
        verdicts.append(problem is None)
        assert verdicts[-1] == (ends[0] > 0.0 and ends[1] < math.pi), gamma
        if problem is not None:
            assert 'the second roller cannot follow' in problem and 'arm angle' in problem
    assert any(verdicts) and not all(verdicts)
