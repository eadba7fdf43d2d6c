"""G2/G3 arcs fitted to a cutter path (core/geometry/arcs.py) against independent references.

References: the circle through three points solved here from the perpendicular bisectors (a 2 x 2
linear system); each arc's deviation from the exact contour measured by a dense scan (then a
finer scan about its largest value) plus the radius mismatch its rounded end points leave; the
arc's turn from the angles of its points about its centre; the eccentric cam (a translating flat
face on a simple harmonic rise and return over the whole turn) is a circle of radius
Rb + h / 2 about (0, -h / 2), so its offset is one too.
"""
import math

import numpy as np
import pytest

from cam_ros.core.geometry.arcs import fit_arcs, lines_only, MAX_SWEEP
from cam_ros.core.geometry.followers import TranslatingFlat, TranslatingRoller
from cam_ros.core.geometry.machining import cam_contour, place_points
from test_machining import BASE, ECCENTRIC, MM, RISE, SEED

CUTTER = 6 * MM
SCAN = 3000  # samples of a run's dense scan, and again about its largest value


def circle_through(a, b, c):
    """Return the centre of the circle through three points (perpendicular bisectors)."""
    matrix = 2.0 * np.array([b - a, c - a])
    return np.linalg.solve(matrix, [b @ b - a @ a, c @ c - a @ a])


def turn(points, centre):
    """Return the angle (rad) a run of points turns through about centre, one way or other."""
    angles = np.unwrap(np.arctan2(points[:, 1] - centre[1], points[:, 0] - centre[0]))
    return abs(angles[-1] - angles[0])


def dense_gap(contour, start, end, centre, radius):
    """Return the largest | |C(theta) - centre| - radius | over [start, end] by dense scans."""
    def gap(theta):
        curve = contour.evaluate(np.mod(theta, 2 * math.pi))[0]
        return np.abs(np.hypot(curve[0] - centre[0], curve[1] - centre[1]) - radius)
    theta = np.linspace(start, end, SCAN)
    peak = int(np.argmax(gap(theta)))
    step = theta[1] - theta[0]
    fine = np.clip(np.linspace(theta[peak] - step, theta[peak] + step, SCAN), start, end)
    return float(max(gap(theta).max(), gap(fine).max()))


class Run:
    """Points i..j of a path as the arc through its ends and middle point (the module doc)."""

    def __init__(self, contour, path, resolution, i, j):
        count = len(path.points)
        points = np.vstack((path.points, path.points[:1]))
        knots = np.append(path.theta, path.theta[0] + 2 * math.pi)
        exact = circle_through(points[i], points[(i + j) // 2], points[j])
        self.centre = (np.round(exact / resolution) * resolution if resolution else exact)
        self.sweep = turn(points[i:j + 1], exact)
        radius = math.hypot(*(points[i] - self.centre))
        self.mismatch = abs(math.hypot(*(points[j] - self.centre)) - radius)
        self.deviation = (dense_gap(contour, knots[i], knots[j], self.centre, radius)
                          + self.mismatch)
        self.closes = j == count


CASES = {
    'roller, no rounding': (TranslatingRoller(30 * MM, 10 * MM, 5 * MM), SEED, False,
                            0.01 * MM, 0.0),
    'roller, mm resolution': (TranslatingRoller(30 * MM, 10 * MM, 5 * MM), SEED, True,
                              0.01 * MM, 1e-6),
    'flat face, coarse': (TranslatingFlat(BASE), SEED, False, 0.05 * MM, 1e-6),
}


@pytest.fixture(scope='module', params=CASES)
def fitted(request):
    follower, program, clockwise, tolerance, resolution = CASES[request.param]
    contour = cam_contour(follower, program, clockwise).offset(CUTTER)
    path = place_points(contour, tolerance, resolution)
    return contour, path, resolution, fit_arcs(contour, path, resolution)


def test_the_moves_run_once_round_the_path(fitted):
    _, path, _, arcs = fitted
    count = len(path.points)
    assert arcs.path is path
    assert arcs.moves[0].start == 0 and arcs.moves[-1].end == 0
    assert [move.end for move in arcs.moves[:-1]] == [move.start for move in arcs.moves[1:]]
    assert all(move.start < move.end or move.end == 0 for move in arcs.moves)
    lines = [move for move in arcs.moves if move.centre is None]
    assert all((move.end - move.start) % count == 1 for move in lines)
    assert len(arcs.moves) < count / 3  # arcs replace most of the chords


def test_every_arc_is_the_circle_through_its_ends_and_middle_within_the_tolerance(fitted):
    contour, path, resolution, arcs = fitted
    count = len(path.points)
    deviations = []
    for move in arcs.moves:
        if move.centre is None:
            continue
        run = Run(contour, path, resolution, move.start, move.end or count)
        assert move.centre == pytest.approx(run.centre, abs=1e-12 + resolution * 1e-6)
        if resolution:  # the centre as the file writes it
            assert np.abs(np.array(move.centre) / resolution
                          - np.round(np.array(move.centre) / resolution)).max() < 1e-6
        assert run.sweep <= MAX_SWEEP * (1 + 1e-12)
        assert run.deviation <= path.tolerance * (1 + 1e-9)
        deviations.append(run.deviation)
    # the stated worst is the arcs' true one (never below it) or the chords' if larger
    worst = max(path.worst_deviation, max(deviations))
    assert arcs.worst_deviation >= worst * (1 - 1e-12)
    assert arcs.worst_deviation == pytest.approx(worst, rel=1e-6)
    assert max(deviations) > 0.5 * path.tolerance  # runs grown until the tolerance binds


def test_every_move_is_as_long_as_an_arc_fits(fitted):
    """The run one point longer than each move (two chords for a line) does not fit."""
    contour, path, resolution, arcs = fitted
    count = len(path.points)
    for move in arcs.moves:
        end = (move.end or count) + 1
        if end > count:
            continue
        longer = Run(contour, path, resolution, move.start, end)
        assert (longer.sweep > MAX_SWEEP * (1 - 1e-9)
                or longer.deviation > path.tolerance * (1 - 1e-6)), (move, longer.deviation)


@pytest.mark.parametrize('clockwise', [False, True])
def test_an_eccentric_circle_becomes_three_arcs_of_its_radius(clockwise):
    contour = cam_contour(TranslatingFlat(BASE), ECCENTRIC, clockwise).offset(CUTTER)
    path = place_points(contour, 0.01 * MM)
    arcs = fit_arcs(contour, path)
    count = len(path.points)
    centre, radius = np.array([0.0, -RISE / 2]), BASE + RISE / 2 + CUTTER
    chord = 2 * math.acos(1 - 0.01 * MM / radius)  # the widest chord's angle
    points = np.vstack((path.points, path.points[:1]))
    circles = [move for move in arcs.moves if move.centre is not None]
    assert len(circles) == 3
    assert all(move.centre == pytest.approx(centre, abs=1e-12) for move in circles)
    sweeps = [turn(points[move.start:(move.end or count) + 1], centre) for move in circles]
    assert max(sweeps) <= MAX_SWEEP and min(sweeps) > MAX_SWEEP - chord  # the longest runs
    assert len(arcs.moves) <= 4 and all(  # at most the last chord is left, a line
        (move.end - move.start) % count == 1 for move in arcs.moves if move.centre is None)
    # points on the circle: the arcs deviate by rounding only, the chords by their sagitta
    assert arcs.worst_deviation == path.worst_deviation


def test_lines_only_is_one_chord_per_point(fitted):
    _, path, _, _ = fitted
    lines = lines_only(path)
    count = len(path.points)
    assert [(move.start, move.end, move.centre) for move in lines.moves] == [
        (i, (i + 1) % count, None) for i in range(count)]
    assert lines.worst_deviation == path.worst_deviation and lines.path is path
