"""Cutter paths (core/geometry/machining.py) against closed forms.

References: a translating flat face driven by a simple harmonic rise and return over the whole
turn rides an eccentric circle (the Scotch yoke: face height Rb + h/2 (1 - cos theta)), so the
cam surface is the circle of radius Rb + h/2 about (0, -h/2) and every offset of it a circle;
the chord of a circle of radius R over an angle a deviates from it by R (1 - cos(a/2)); the
translating roller's pitch-curve radius of curvature in closed form (the kinematics notes) for
the smallest concave radius; finite differences for the normals.
"""
import math

import numpy as np
import pytest

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry import machining
from cam_ros.core.geometry.followers import (OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                             TranslatingRoller)
from cam_ros.core.geometry.machining import (cam_contour, check_cutter, cutter_contours,
                                             GROOVE_FIT, place_points,
                                             smallest_concave_radius)
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

DEG = math.pi / 180
MM = 1e-3
RISE = 20 * MM
BASE = 40 * MM
ECCENTRIC = MotionProgram((Segment(make_law('simple_harmonic'), 0.0, math.pi, 0.0, RISE),
                           Segment(make_law('simple_harmonic'), math.pi, 2 * math.pi, RISE, 0.0)))
SEED = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * DEG, 0.0, 0.0),
                      Segment(make_law('cycloidal'), 90 * DEG, 180 * DEG, 0.0, RISE),
                      Segment(make_law('dwell'), 180 * DEG, 240 * DEG, RISE, RISE),
                      Segment(make_law('simple_harmonic'), 240 * DEG, 2 * math.pi, RISE, 0.0)))
#: The seed's laws with the rise first: its most curved concave part lies before 1 rad.
EARLY = MotionProgram((Segment(make_law('cycloidal'), 0.0, 90 * DEG, 0.0, RISE),
                       Segment(make_law('dwell'), 90 * DEG, 150 * DEG, RISE, RISE),
                       Segment(make_law('simple_harmonic'), 150 * DEG, 270 * DEG, RISE, 0.0),
                       Segment(make_law('dwell'), 270 * DEG, 2 * math.pi, 0.0, 0.0)))
CENTRE = np.array([0.0, -RISE / 2])  # of the eccentric cam, in the cam frame
RADIUS = BASE + RISE / 2
ROTATIONS = {'ccw': False, 'cw': True}


@pytest.fixture(params=ROTATIONS)
def clockwise(request):
    return ROTATIONS[request.param]


def test_the_eccentric_cam_is_a_circle_with_radial_normals(clockwise):
    contour = cam_contour(TranslatingFlat(BASE), ECCENTRIC, clockwise)
    theta = np.linspace(0.0, 2 * math.pi, 1001)
    points, normals, curvature = contour.evaluate(theta)
    radial = points - CENTRE[:, np.newaxis]
    assert np.hypot(*radial) == pytest.approx(RADIUS, rel=1e-12)
    assert normals == pytest.approx(radial / RADIUS, abs=1e-12)
    assert curvature == pytest.approx(1 / RADIUS, rel=1e-9)
    offset = contour.offset(5 * MM).evaluate(theta)
    distance = np.hypot(*(offset[0] - CENTRE[:, np.newaxis]))
    assert distance == pytest.approx(RADIUS + 5 * MM, rel=1e-12)
    assert offset[2] == pytest.approx(1 / (RADIUS + 5 * MM), rel=1e-9)


@pytest.mark.parametrize('tolerance', [1e-3 * MM, 1e-2 * MM, 0.1 * MM])
def test_the_worst_deviation_on_a_circle_is_the_largest_chord_sagitta(tolerance, clockwise):
    cutter = 6 * MM
    path = place_points(cam_contour(TranslatingFlat(BASE), ECCENTRIC, clockwise).offset(cutter),
                        tolerance)
    radius = RADIUS + cutter
    radial = path.points - CENTRE
    assert np.hypot(*radial.T) == pytest.approx(radius, rel=1e-12)  # points on the circle
    angles = np.unwrap(np.arctan2(radial[:, 1], radial[:, 0]))
    span = np.abs(np.diff(np.append(angles, angles[0] + np.sign(angles[-1] - angles[0])
                                    * 2 * math.pi)))
    sagitta = radius * (1 - np.cos(span / 2))
    assert path.worst_deviation == pytest.approx(sagitta.max(), rel=1e-9)
    assert sagitta.max() <= tolerance
    assert sagitta.max() > 0.3 * tolerance  # not wastefully many points (whole splits)
    assert len(path.points) <= 2 * math.pi / (2 * math.acos(1 - tolerance / radius)) * 2 + 4


def concave_seed_radius(theta, base, roller, offset, sigma, program=SEED):
    """Return the surface radius of seed 000's roller cam in closed form (the notes)."""
    values = program.evaluate(theta)
    s, v, a = values.s, values.ds, values.d2s
    d = math.sqrt((base + roller) ** 2 - offset ** 2)
    along, across = d + s, v - sigma * offset
    pitch = np.hypot(along, across) ** 3 / (
        along ** 2 + across * (2 * v - sigma * offset) - a * along)
    return pitch - roller


@pytest.mark.parametrize('program', [SEED, EARLY], ids=['seed', 'rise first'])
def test_the_smallest_concave_radius_is_the_closed_form_and_bounds_the_cutter(clockwise,
                                                                              program):
    follower = TranslatingRoller(15 * MM, 10 * MM, 5 * MM)
    contour = cam_contour(follower, program, clockwise)
    radius, at = smallest_concave_radius(contour)
    theta = np.linspace(0.0, 2 * math.pi, 720_000, endpoint=False)
    rho = concave_seed_radius(theta, 15 * MM, 10 * MM, 5 * MM, -1 if clockwise else 1, program)
    concave = rho < 0
    assert radius == pytest.approx(-rho[concave].max(), rel=1e-9)
    assert radius <= -rho[concave].max()  # refined: never above the dense minimum
    assert at == pytest.approx(theta[concave][np.argmax(rho[concave])], abs=1e-4)
    check_cutter(contour, radius * (1 - 1e-9))
    with pytest.raises(InvalidParameter, match=r'cutter_radius = .*smallest concave radius of '
                                               r'the cam surface, .* m at cam angle .* rad'):
        check_cutter(contour, radius * (1 + 1e-9))


def test_a_convex_cam_takes_any_cutter():
    contour = cam_contour(TranslatingFlat(BASE), ECCENTRIC, False)
    assert smallest_concave_radius(contour)[0] == math.inf
    check_cutter(contour, 1.0)


FOLLOWERS = [TranslatingRoller(30 * MM, 10 * MM, 5 * MM), TranslatingFlat(BASE),
             OscillatingRoller(30 * MM, 10 * MM, 90 * MM, 70 * MM, True),
             OscillatingFlat(30 * MM, 90 * MM, 0.0, False)]


@pytest.mark.parametrize('follower', FOLLOWERS, ids=lambda f: type(f).__name__)
def test_normals_are_unit_outward_and_square_to_the_surface(follower, clockwise):
    motion = SEED if not isinstance(follower, (OscillatingRoller, OscillatingFlat)) else \
        MotionProgram((Segment(make_law('cycloidal'), 0.0, math.pi, 0.0, 0.3),
                       Segment(make_law('cycloidal'), math.pi, 2 * math.pi, 0.3, 0.0)))
    contour = cam_contour(follower, motion, clockwise)
    theta = np.linspace(0.01, 2 * math.pi - 0.01, 997)
    step = 1e-6
    points, normals, _ = contour.evaluate(theta)
    tangent = (contour.evaluate(theta + step)[0] - contour.evaluate(theta - step)[0]) / (2 * step)
    assert np.hypot(*normals) == pytest.approx(1.0, rel=1e-12)
    assert np.all(np.abs(np.sum(tangent * normals, axis=0)) / np.hypot(*tangent) < 1e-6)
    assert np.all(np.sum(points * normals, axis=0) > 0)  # pointing away from the cam centre


def test_rounded_points_are_counted_in_the_deviation():
    contour = cam_contour(TranslatingRoller(30 * MM, 10 * MM, 5 * MM), SEED, False).offset(
        4 * MM)
    resolution = 1e-4 * MM
    path = place_points(contour, 2e-3 * MM, resolution)
    assert np.all(np.abs(path.points / resolution - np.round(path.points / resolution)) < 1e-6)
    # every chord, densely: the exact curve never strays further than the stated worst
    knots = np.append(path.theta, path.theta[0] + 2 * math.pi)
    share = np.linspace(0.0, 1.0, 201)
    angles = knots[:-1, np.newaxis] + share * np.diff(knots)[:, np.newaxis]
    curve = contour.evaluate(angles.reshape(-1))[0].reshape(2, *angles.shape)
    start, end = path.points.T, np.roll(path.points, -1, axis=0).T
    chord = end - start
    rel = curve - start[:, :, np.newaxis]
    along = np.clip(np.sum(rel * chord[:, :, np.newaxis], axis=0)
                    / np.sum(chord ** 2, axis=0)[:, np.newaxis], 0, 1)
    gap = np.hypot(*(rel - along * chord[:, :, np.newaxis]))
    assert gap.max() <= path.worst_deviation <= path.tolerance
    assert path.worst_deviation == pytest.approx(gap.max(), rel=1e-3)


@pytest.mark.parametrize('tolerance, rule', [(0.0, 'must be a finite length > 10 x'),
                                             (math.nan, 'must be a finite length'),
                                             (5e-7, r'> 10 x the output resolution 1e-07 m')])
def test_bad_tolerances_are_refused_with_the_rule(tolerance, rule):
    contour = cam_contour(TranslatingFlat(BASE), ECCENTRIC, False)
    with pytest.raises(InvalidParameter, match=rf'tolerance = .*{rule}'):
        place_points(contour, tolerance, 1e-7)


def test_a_tolerance_needing_too_many_points_is_refused():
    contour = cam_contour(TranslatingFlat(BASE), ECCENTRIC, False)
    with pytest.raises(InvalidParameter, match=r'tolerance = 1e-15: needs more than'):
        place_points(contour, 1e-15)


def test_cutter_contours_and_lead_in_of_a_cam_and_of_a_groove():
    """The eccentric cam (a circle of RADIUS about CENTRE) and a groove of half width w about it:
    every path is a circle whose radius says which offset was taken."""
    cam = cam_contour(TranslatingFlat(BASE), ECCENTRIC, False)
    theta = np.linspace(0.0, 2 * math.pi, 361)

    def radii(contours):
        return {key: np.hypot(*(contour.evaluate(theta)[0] - CENTRE[:, np.newaxis]))
                for key, contour in contours.items()}

    cutter, half = 3 * MM, 5 * MM
    contours, lead_in = cutter_contours({'cam': cam}, cutter, nominal=True)
    assert contours['cam'] is cam and lead_in == 2 * cutter  # compensation: 2 Rc clear
    contours, lead_in = cutter_contours({'cam': cam}, cutter, nominal=False)
    assert radii(contours)['cam'] == pytest.approx(RADIUS + cutter, rel=1e-12)
    assert lead_in == cutter
    groove = {'inner': cam.offset(-half), 'outer': cam.offset(half).flipped()}
    assert cutter_contours(groove, cutter, True, half)[1] == half  # from the groove's middle
    contours, lead_in = cutter_contours(groove, cutter, False, half)  # each flank in turn
    assert radii(contours)['inner'] == pytest.approx(RADIUS - half + cutter, rel=1e-12)
    assert radii(contours)['outer'] == pytest.approx(RADIUS + half - cutter, rel=1e-12)
    assert lead_in == pytest.approx(half - cutter, rel=1e-12)
    for fits in (half, half * (1 + 0.5 * GROOVE_FIT)):  # one pass on the pitch curve
        contours, lead_in = cutter_contours(groove, fits, False, half)
        assert list(contours) == ['pitch'] and lead_in == 0.0
        assert radii(contours)['pitch'] == pytest.approx(RADIUS, rel=1e-12)
    narrower = half * (1 - 1e-6)  # 5 nm narrower: two passes, 5 nm apart
    contours, lead_in = cutter_contours(groove, narrower, False, half)
    assert list(contours) == ['inner', 'outer'] and lead_in == pytest.approx(half - narrower)
    with pytest.raises(InvalidParameter, match=r'^cutter_radius = .*is wider than the groove: '
                                               r'at most half its width, 0\.005 m'):
        cutter_contours(groove, half * (1 + 2 * GROOVE_FIT), False, half)


def chord_distances(contour, path, per_chord=4000):
    """Return the largest distance of the exact contour from each chord of a path (brute force)."""
    ends = np.append(path.theta[1:], path.theta[0] + 2 * math.pi)
    share = np.linspace(0.0, 1.0, per_chord)
    angles = path.theta[:, np.newaxis] + (ends - path.theta)[:, np.newaxis] * share
    exact = contour.evaluate(angles.reshape(-1))[0].reshape(2, *angles.shape)
    start, end = path.points.T[:, :, np.newaxis], np.roll(path.points, -1, axis=0).T
    chord = end[:, :, np.newaxis] - start
    along = np.clip(((exact - start) * chord).sum(axis=0) / (chord ** 2).sum(axis=0), 0.0, 1.0)
    return np.hypot(*(exact - start - along * chord)).max(axis=1)


def test_a_chord_found_beyond_the_tolerance_after_refinement_is_split(monkeypatch):
    """With chords placed up to 1.2 x the tolerance, only the refined check keeps the promise:
    it halves the worst chord until the true worst deviation is within the tolerance."""
    monkeypatch.setattr(machining, 'PLACEMENT_MARGIN', 1.2)
    halved = []

    def split(knots, chords, pieces):
        halved.extend(chords for piece in pieces if len(pieces) == 1 and piece == 2)
        return unsplit(knots, chords, pieces)
    unsplit = machining._split
    monkeypatch.setattr(machining, '_split', split)
    contour = cam_contour(TranslatingRoller(30 * MM, 10 * MM, 5 * MM), SEED, False)
    tolerance = 1e-2 * MM
    path = place_points(contour, tolerance)
    assert halved  # the refined check found chords beyond the tolerance and split them
    worst = chord_distances(contour, path)
    assert worst.max() <= path.worst_deviation <= tolerance
    assert path.worst_deviation == pytest.approx(worst.max(), rel=1e-6)
    chord = np.searchsorted(path.theta, path.worst_at, side='right') - 1
    assert worst[chord] == pytest.approx(worst.max(), rel=1e-6)
