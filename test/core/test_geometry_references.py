"""Numbers of core/geometry a user sees (check.py, machining.py, the one-angle path of
cam_geometry.py) against independent references, for the mutation score (issue 49).

References (the kinematics notes, as test_geometry.py uses them on whole arrays): a translating
roller's pressure angle tan phi = (ds/dtheta - sigma e) / (d + s), d = sqrt(Rp^2 - e^2); an
oscillating roller's tan phi = (L (1 - mu ds) - C cos psi) / (C sin psi), phi = -mu times it;
an oscillating flat face in a dwell rides a circle of radius C sin psi - f about the cam centre
and leans by atan(|f| / (C cos psi)); seed 000's translating-roller pitch and surface radii in
closed form, scanned densely then minimised (scipy), their roots by brentq; a brute-force chord
distance for a cutter path's worst deviation; a refusal's whole line, its figures from those
references where it gives any.
"""
import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from cam_motions import seed_000
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry import machining
from cam_ros.core.geometry.cam_geometry import cam_geometry, contact_at
from cam_ros.core.geometry.check import check_geometry
from cam_ros.core.geometry.followers import OscillatingFlat, OscillatingRoller, TranslatingRoller
from cam_ros.core.geometry.machining import cam_contour, check_cutter, Contour, place_points
from test_machining import chord_distances, concave_seed_radius, SEED

EXACT = 1e-12
ANGLES = (0.3, 1.1, 2.0, 2.9, 4.4, 5.8)  # rad: the seed's rise, dwells and return
ROTATIONS = {'ccw': False, 'cw': True}


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def seed_at(theta, rise=0.02):
    """Return the seed's s, ds, d2s at one angle, as floats."""
    return [float(value[0]) for value in seed_000(np.array([theta]), rise)]


@pytest.mark.parametrize('offset', [0.005, -0.008])
def test_a_translating_roller_at_one_angle_takes_the_sense_of_rotation(offset, clockwise):
    follower = TranslatingRoller(0.04, 0.01, offset)
    sigma = -1 if clockwise else 1
    d = math.sqrt(0.05 ** 2 - offset ** 2)
    for theta in ANGLES:
        s, ds, d2s = seed_at(theta)
        angle, _ = contact_at(follower, theta, s, ds, d2s, clockwise=clockwise)
        assert angle == pytest.approx(math.atan((ds - sigma * offset) / (d + s)), abs=EXACT)


@pytest.mark.parametrize('with_cam', [True, False])
def test_an_oscillating_roller_at_one_angle_is_the_notes(with_cam, clockwise):
    c, arm = 0.09, 0.07
    follower = OscillatingRoller(0.04, 0.01, c, arm, with_cam)
    mu = 1.0 if with_cam else -1.0
    for theta in ANGLES:
        s, ds, d2s = seed_at(theta, 0.3)
        angle, radius = contact_at(follower, theta, s, ds, d2s, clockwise=clockwise)
        psi = math.acos((c * c + arm * arm - 0.05 ** 2) / (2 * c * arm)) + s
        note = math.atan((arm * (1 - mu * ds) - c * math.cos(psi)) / (c * math.sin(psi)))
        assert isinstance(angle, float) and isinstance(radius, float)
        assert angle == pytest.approx(-mu * note, abs=EXACT)


@pytest.mark.parametrize('face', [0.012, -0.012])
def test_an_oscillating_flat_face_in_a_dwell_at_one_angle_rides_its_circle(face, clockwise):
    c, base, dwell = 0.09, 0.04, 0.2
    follower = OscillatingFlat(base, c, face, False)
    psi = math.asin((base + face) / c) + dwell
    for theta in ANGLES:
        angle, radius = contact_at(follower, theta, dwell, 0.0, 0.0, clockwise=clockwise)
        assert radius == pytest.approx(c * math.sin(psi) - face, rel=EXACT)
        assert abs(angle) == pytest.approx(math.atan(abs(face) / (c * math.cos(psi))),
                                           abs=EXACT)


def test_a_first_chord_found_beyond_the_tolerance_after_refinement_is_split(monkeypatch):
    """The refined check's worst chord may be chord 0 (the contour turned so that it is): it is
    split until the true worst deviation, a brute-force chord distance, is within tolerance."""
    monkeypatch.setattr(machining, 'PLACEMENT_MARGIN', 1.2)  # chords up to 1.2 x tolerance
    halved = []

    def split(knots, chords, pieces):
        halved.extend(int(chord) for chord, piece in zip(chords, pieces)
                      if len(pieces) == 1 and piece == 2)
        return unsplit(knots, chords, pieces)
    unsplit = machining._split
    monkeypatch.setattr(machining, '_split', split)
    cam = cam_contour(TranslatingRoller(0.03, 0.01, 0.005), SEED, False)
    turn = 177 / 200 * 2 * math.pi

    def evaluate(theta):
        return cam.evaluate(np.mod(theta + turn, 2 * math.pi))
    contour = Contour(evaluate, np.mod(cam.breaks - turn, 2 * math.pi))
    tolerance = 1e-5
    path = place_points(contour, tolerance)
    assert 0 in halved
    worst = chord_distances(contour, path)
    assert worst.max() <= path.worst_deviation <= tolerance
    assert path.worst_deviation == pytest.approx(worst.max(), rel=1e-6)


def test_a_gouging_cutter_is_refused_with_the_radius_and_angle_of_the_dense_scan():
    """The refusal's figures (what the user reads) against seed 000's closed-form surface
    radius on a 720 000-point scan, the whole line as the user sees it."""
    contour = cam_contour(TranslatingRoller(0.015, 0.01, 0.005), SEED, False)
    theta = np.linspace(0.0, 2 * math.pi, 720_000, endpoint=False)
    rho = concave_seed_radius(theta, 0.015, 0.01, 0.005, 1)
    concave = rho < 0
    radius, at = -rho[concave].max(), theta[concave][np.argmax(rho[concave])]
    with pytest.raises(InvalidParameter) as refused:
        check_cutter(contour, 0.5, 'cutter')
    words = re.fullmatch(r'cutter = 0\.5: is larger than the smallest concave radius of the '
                         r'cam surface, (\S+) m at cam angle (\S+) rad: the cutter would gouge '
                         r'it there \(use a smaller cutter\)', str(refused.value))
    assert words is not None, str(refused.value)
    assert float(words[1]) == pytest.approx(radius, rel=1e-5)  # printed to 6 figures
    assert float(words[2]) == pytest.approx(at, abs=1e-4)


@pytest.mark.parametrize('cutter', [0.0, -0.001, math.inf, math.nan])
def test_a_cutter_that_is_no_length_is_refused_with_its_value(cutter):
    contour = cam_contour(TranslatingRoller(0.015, 0.01, 0.005), SEED, False)
    with pytest.raises(InvalidParameter) as refused:
        check_cutter(contour, cutter)
    assert str(refused.value) == f'cutter_radius = {cutter!r}: must be a finite length > 0 (m)'


def test_a_tolerance_needing_too_many_points_says_how_many():
    contour = cam_contour(TranslatingRoller(0.03, 0.01, 0.005), SEED, False)
    with pytest.raises(InvalidParameter) as refused:
        place_points(contour, 1e-15)
    assert str(refused.value) == ('tolerance = 1e-15: needs more than 1000000 points: give a '
                                  'larger one')


# ------------------------------------------------ a roller's undercut and radius (check.py)

GRID = np.linspace(0.0, 2 * np.pi, 7200, endpoint=False)  # the design checks' sampling
DENSE = np.linspace(0.0, 2 * np.pi, 720_000, endpoint=False)


def pitch_radius(theta, prime, offset):
    """Return seed 000's translating-roller pitch-curve radius in closed form (the notes)."""
    return concave_seed_radius(np.atleast_1d(theta), prime, 0.0, offset, 1)


def smallest_convex_pitch(prime, offset):
    """Return (radius, angle) of the most curved convex part of the pitch curve: a dense scan,
    then a bounded scalar minimisation of the closed form about it."""
    rho = pitch_radius(DENSE, prime, offset)
    index = int(np.argmin(np.where(rho > 0, rho, np.inf)))
    found = minimize_scalar(lambda angle: pitch_radius(angle, prime, offset)[0],
                            bounds=(DENSE[index - 2], DENSE[index + 2]), method='bounded',
                            options={'xatol': 1e-12})
    assert found.fun <= rho[index]
    return found.fun, found.x


def checked(follower):
    values = SEED.evaluate(GRID)
    geometry = cam_geometry(follower, GRID, values.s, values.ds, values.d2s)
    return check_geometry(geometry), check_geometry(geometry, program=SEED)


@pytest.mark.parametrize('prime, offset', [(0.03, 0.005), (0.04, 0.0)])
def test_a_roller_undercut_between_samples_is_found(prime, offset):
    """A roller 1e-10 m larger than the pitch curve's smallest convex radius: an undercut no
    sample shows, said at the refined angle, its cusps the closed form's roots about it."""
    radius, angle = smallest_convex_pitch(prime, offset)
    roller = radius + 1e-10
    grid_only, check = checked(TranslatingRoller(prime - roller, roller, offset))
    assert not grid_only.undercut
    assert check.undercut and not check.ok
    assert check.min_radius == pytest.approx(-1e-10, abs=1e-15)
    assert check.min_radius_at == pytest.approx(angle, abs=1e-6)
    np.testing.assert_array_equal(check.undercut_angles, [check.min_radius_at])
    low, high = check.cusp_angles

    def margin(at):
        return pitch_radius(at, prime, offset)[0] - roller
    assert low == pytest.approx(brentq(margin, angle - 1e-3, angle), abs=1e-9)
    assert high == pytest.approx(brentq(margin, angle, angle + 1e-3), abs=1e-9)


def test_a_cam_of_metres_reports_its_smallest_radius():
    """Every convex radius above 1 m (a curvature below 1 / m): the smallest is still said."""
    prime, offset, roller = 2.0, 0.01, 0.05
    radius, angle = smallest_convex_pitch(prime, offset)
    assert radius > 1.0
    _, check = checked(TranslatingRoller(prime - roller, roller, offset))
    assert check.min_radius == pytest.approx(radius - roller, rel=1e-9)
    assert check.pitch_convex_radius_min == pytest.approx(radius, rel=1e-9)
    assert check.min_radius_at == pytest.approx(angle, abs=1e-5)


def test_a_roller_cam_reports_its_smallest_concave_pitch_radius():
    """The pitch curve's most curved concave part against the closed form's dense scan (a
    concave radius: positive, the smallest in size)."""
    prime, offset, roller = 0.025, 0.005, 0.01
    rho = pitch_radius(DENSE, prime, offset)
    concave = rho < 0
    assert concave.any()
    index = int(np.argmax(np.where(concave, rho, -np.inf)))
    found = minimize_scalar(lambda angle: -pitch_radius(angle, prime, offset)[0],
                            bounds=(DENSE[index - 2], DENSE[index + 2]), method='bounded',
                            options={'xatol': 1e-12})
    _, check = checked(TranslatingRoller(prime - roller, roller, offset))
    assert check.pitch_concave_radius_min == pytest.approx(found.fun, rel=1e-9)
    assert check.pitch_concave_radius_min <= -rho[index]


def test_a_check_without_the_motion_takes_every_sample_the_first_too():
    """Grid only (no program): the reported peak is the samples' own, here the first sample's
    (the grid starts at the peak of the notes' closed form)."""
    prime, offset = 0.04, 0.005
    follower = TranslatingRoller(prime - 0.01, 0.01, offset)
    d = math.sqrt(prime ** 2 - offset ** 2)

    def closed_form(theta):
        values = SEED.evaluate(np.mod(theta, 2 * math.pi))
        return np.arctan((values.ds - offset) / (d + values.s))
    peak = DENSE[np.argmax(np.abs(closed_form(DENSE)))]
    theta = peak + np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    values = SEED.evaluate(np.mod(theta, 2 * math.pi))
    check = check_geometry(cam_geometry(follower, theta, values.s, values.ds, values.d2s))
    assert check.max_pressure_angle == pytest.approx(abs(closed_form(theta[:1])[0]), abs=EXACT)
    assert check.max_pressure_angle_at == peak
    assert check.max_pressure_angle > np.abs(closed_form(theta[1:])).max()


def seed_geometry(follower, s=None, ds=None):
    """Return cam_geometry of seed 000 on 8 samples, s or ds replaced when given."""
    theta = np.linspace(0.0, 2 * math.pi, 8, endpoint=False)
    values = SEED.evaluate(theta)
    return cam_geometry(follower, theta, values.s if s is None else s,
                        values.ds if ds is None else ds, values.d2s)


ROLLER = TranslatingRoller(0.04, 0.01, 0.005)
REFUSALS = {  # what is done: the whole line the user reads (name = value: rule)
    'not a geometry': (lambda: check_geometry('x'), "geometry = 'x': must be a CamGeometry"),
    'not a program': (lambda: check_geometry(seed_geometry(ROLLER), program='x'),
                      "program = 'x': must be a MotionProgram or None"),
    'a return limit alone': (
        lambda: check_geometry(seed_geometry(ROLLER), max_pressure_angle_return=0.5),
        'max_pressure_angle = None: give it with max_pressure_angle_return (the rise limit)'),
    'theta not 1-D': (lambda: cam_geometry(ROLLER, np.zeros((2, 2)), 0.0, 0.0, 0.0),
                      "theta = 'array of shape (2, 2)': must be 1-D with at least 1 sample"),
    'a shorter s': (lambda: cam_geometry(ROLLER, np.zeros(4), np.zeros(3), 0.0, 0.0),
                    "s = 'array of shape (3,)': must have the shape of theta (4,)"),
    'an offset past the prime circle': (
        lambda: TranslatingRoller(0.04, 0.01, 0.06),
        'offset = 0.06: needs |offset| < base_radius + roller_radius = 0.05 m'),
    'a roller below the cam centre': (
        lambda: seed_geometry(ROLLER, s=np.full(8, -0.1)),
        's[0] = -0.1: roller centre must stay above the cam centre (s > -0.0497494 m)'),
    'an arm that cannot reach': (
        lambda: OscillatingRoller(0.04, 0.01, 0.2, 0.07, True),
        'base_radius = 0.04: the prime radius base_radius + roller_radius = 0.05 m must lie in '
        '(|pivot_distance - arm_length|, pivot_distance + arm_length) = (0.13, 0.27) m so that '
        'the roller reaches the cam'),
    'a face arm outrunning the cam': (
        lambda: seed_geometry(OscillatingFlat(0.04, 0.09, 0.01, True), s=np.zeros(8),
                              ds=np.full(8, 2.0)),
        "ds[0] = 2.0: the arm must turn slower than the cam in the cam's sense "
        '(1 - mu*ds/dtheta > 0)'),
    'a face reaching the pivot': (  # lengths exact in binary: the bound's own value
        lambda: OscillatingFlat(0.5, 0.75, 0.25, False),
        'face_offset = 0.25: base_radius + face_offset = 0.75 m must lie in (0, pivot_distance '
        '= 0.75 m) so that the face touches the base circle'),
    'a negative length': (lambda: TranslatingRoller(-0.04, 0.01, 0.0),
                          'base_radius = -0.04: must be > 0 (m)'),
    'not a number': (lambda: TranslatingRoller('a', 0.01, 0.0),
                     "base_radius = 'a': must be a real number > 0 (m)"),
}


@pytest.mark.parametrize('case', REFUSALS)
def test_a_refusal_names_the_parameter_its_value_and_the_rule(case):
    do, line = REFUSALS[case]
    with pytest.raises(InvalidParameter) as refused:
        do()
    assert str(refused.value) == line


def test_a_placement_out_of_rounds_is_refused(monkeypatch):
    monkeypatch.setattr(machining, 'MAX_ROUNDS', 1)  # the first placement's chords: too long
    with pytest.raises(InvalidParameter) as refused:
        place_points(cam_contour(ROLLER, SEED, False), 1e-5)
    assert str(refused.value) == 'tolerance = 1e-05: could not be met by the point placement'
