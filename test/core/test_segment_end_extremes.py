"""Extremes at a segment's end (issue 38): the one-sided limit before a joint counts.

Where a derivative jumps at a joint (a constant-velocity or harmonic law into a dwell) a
measure's extreme can be the limit from the left, owned by the segment that ends there, while
the joint's own angle belongs to the next segment. References: a translating roller's pressure
angle and pitch curvature in closed form (the pitch point e^(-i sigma theta) (e + i (d + s))
differentiated twice), with the left segment's law written out at u = 1; a dense scan of the
same closed form over the segment confirms the joint holds the extreme.
"""
import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, InvalidParameter
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.geometry.joint_sizing import smallest_cam
from cam_ros.core.geometry.machining import cutter_contours, smallest_concave_radius
from cam_ros.core.report import design_report

CONFIG = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
MM = 1e-3
DEG = math.pi / 180
REL = 1e-12
U = np.linspace(0.0, 1.0, 100_001)  # a segment's u, for the dense scans


def design(**updates):
    flat = read_parameters_file(CONFIG)
    flat.update({'length_unit': 'mm', 'rotation': 'counterclockwise',
                 'limits.min_radius_of_curvature': 0.0, **updates})
    return build_design(parse_parameters(flat))


def motion(laws, edges, positions):
    return {'motion.laws': laws, 'motion.start_deg': edges[:-1], 'motion.end_deg': edges[1:],
            'motion.start_position': positions[:-1], 'motion.end_position': positions[1:]}


def roller(s, v, a, prime, offset, sigma=1):
    """Return |pressure angle| and pitch curvature of a translating roller (closed form)."""
    along = math.sqrt(prime ** 2 - offset ** 2) + s
    across = v - sigma * offset
    curvature = ((along ** 2 + across * (2 * v - sigma * offset) - a * along)
                 / np.hypot(along, across) ** 3)
    return np.arctan(np.abs(across) / along), curvature


def harmonic(stroke, span, u, rising=True):
    """Return s, ds, d2s of a simple harmonic rise (or return) of stroke over span at u."""
    y, y1, y2 = ((1 - np.cos(np.pi * u)) / 2, np.pi / 2 * np.sin(np.pi * u),
                 np.pi ** 2 / 2 * np.cos(np.pi * u))
    sign = 1.0 if rising else -1.0
    return (stroke * (y if rising else 1 - y), sign * stroke * y1 / span,
            sign * stroke * y2 / span ** 2)


# ------------------------------------------- constant-velocity return of 30 mm into a dwell at 300

CV_STROKE, CV_SPAN = 30 * MM, 100 * DEG
CV = dict(**motion(['dwell', 'cycloidal', 'dwell', 'constant_velocity', 'dwell'],
                   [0.0, 90.0, 180.0, 200.0, 300.0, 360.0], [0.0, 0.0, 30.0, 30.0, 0.0, 0.0]),
          **{'follower.base_radius': 40.0, 'follower.roller_radius': 10.0,
             'follower.offset': 5.0, 'limits.pressure_angle_deg': 30.0,
             'limits.pressure_angle_return_deg': 24.0372, 'limits.allow_velocity_jumps': True})


def cv_return_limit(prime, offset):
    """Return |pressure angle| at 300 deg from the left: s = 0, ds = -h / beta."""
    return float(roller(0.0, -CV_STROKE / CV_SPAN, 0.0, prime, offset)[0])


def test_cv_return_pressure_angle_is_the_limit_at_the_joint_and_fails_its_limit():
    cam = design(**CV)
    peak, at = cam.check.pressure_angle_return
    exact = cv_return_limit(50 * MM, 5 * MM)
    assert math.degrees(exact) == pytest.approx(24.037365, abs=1e-6)
    s = CV_STROKE * (1 - U)  # the whole return: the peak is at its end
    assert np.all(roller(s, -CV_STROKE / CV_SPAN, 0.0, 50 * MM, 5 * MM)[0] <= exact)
    assert peak == pytest.approx(exact, rel=REL, abs=0.0)
    assert at == pytest.approx(300 * DEG, abs=1e-12)
    assert cam.check.pressure_angle_ok is False  # 24.037365 deg > 24.0372 (was 24.037092)


def test_cv_return_sizing_meets_the_limit_at_the_joint():
    report = design_report(design(**CV))
    limit = 24.0372 * DEG
    offset, roller_radius = 5 * MM, 10 * MM
    along = (CV_STROKE / CV_SPAN + offset) / math.tan(limit)
    exact = math.hypot(along, offset) - roller_radius
    assert report.min_base_radius_governing == 'pressure_angle_return'
    assert report.min_base_radius == pytest.approx(exact, rel=REL, abs=0.0)
    prime = report.min_base_radius + roller_radius
    assert cv_return_limit(prime, offset) <= limit * (1 + 4 * np.finfo(float).eps)


@pytest.mark.parametrize('limit_deg', [40.0, 30.0])
def test_cv_return_smallest_cam_stays_within_the_limit_at_the_joint(limit_deg):
    cam = design(**CV)
    found = smallest_cam(10 * MM, cam.program, max_pressure_angle=limit_deg * DEG)
    reached = cv_return_limit(found.prime_radius, found.offset)
    assert found.return_peak == pytest.approx(reached, rel=REL, abs=0.0)
    assert reached <= limit_deg * DEG * (1 + 4 * np.finfo(float).eps)  # was 40.00068 deg
    assert reached == pytest.approx(limit_deg * DEG, rel=REL, abs=0.0)


# ---------------------------------------------- harmonic rise of 30 mm over 40 deg into a dwell

RISE_SPAN = 40 * DEG
HARMONIC = {'follower.base_radius': 36.439, 'follower.roller_radius': 18.561,
            'follower.offset': -10.0, 'limits.pressure_angle_deg': 60.0}


def harmonic_rise_end_curvature(prime, offset):
    """Return the pitch curvature at the harmonic rise's end (the joint, from the left)."""
    curvature = roller(*harmonic(30 * MM, RISE_SPAN, 1.0), prime, offset)[1]
    scan = roller(*harmonic(30 * MM, RISE_SPAN, U), prime, offset)[1]
    assert np.all(scan <= curvature)  # the joint holds the largest curvature
    return float(curvature)


def test_harmonic_rise_into_a_dwell_is_undercut_at_the_joint():
    cam = design(**HARMONIC, **motion(['dwell', 'simple_harmonic', 'dwell', 'cycloidal'],
                                      [0.0, 90.0, 130.0, 200.0, 360.0],
                                      [0.0, 0.0, 30.0, 30.0, 0.0]))
    exact = harmonic_rise_end_curvature(55 * MM, -10 * MM)
    check = cam.check
    assert 1 / exact - 18.561 * MM == pytest.approx(-3.1e-7, rel=0.02)
    assert check.undercut  # was 'Undercut none'
    assert check.min_radius == pytest.approx(1 / exact - 18.561 * MM, rel=1e-9, abs=0.0)
    assert check.min_radius_at == pytest.approx(130 * DEG, abs=1e-12)
    assert check.pitch_convex_radius_min == pytest.approx(1 / exact, rel=REL, abs=0.0)
    assert check.cusp_angles[-1] == pytest.approx(130 * DEG, abs=1e-12)
    report = design_report(cam)
    assert report.max_roller_radius == pytest.approx(1 / exact, rel=REL, abs=0.0)
    assert report.max_roller_radius < 18.561 * MM  # 18.56069 mm (was 18.5614)


def test_groove_inner_flank_is_undercut_at_the_joint():
    cam = design(**HARMONIC, **{'follower.closure': 'groove', 'follower.groove_clearance': 0.0},
                 **motion(['dwell', 'simple_harmonic', 'dwell', 'cycloidal'],
                          [0.0, 130.0, 170.0, 240.0, 360.0], [0.0, 0.0, 30.0, 30.0, 0.0]))
    exact = harmonic_rise_end_curvature(55 * MM, -10 * MM)
    inner = cam.closure.sides['inner']
    assert inner.undercut and not cam.closure.ok
    assert inner.radius_of_curvature_min == pytest.approx(1 / exact - 18.561 * MM, rel=1e-9,
                                                          abs=0.0)
    assert inner.at == pytest.approx(170 * DEG, abs=1e-12)


# ------------------------------------------ harmonic return of 30 mm over 60 deg into a dwell

RETURN_SPAN = 60 * DEG
RETURN = {'follower.base_radius': 20.0, 'follower.roller_radius': 10.0, 'follower.offset': 5.0,
          'limits.pressure_angle_deg': 80.0,
          **motion(['dwell', 'cycloidal', 'dwell', 'simple_harmonic'],
                   [0.0, 20.0, 200.0, 300.0, 360.0], [0.0, 0.0, 30.0, 30.0, 0.0])}


def test_smallest_concave_radius_at_the_joint_refuses_a_cutter_just_above_it():
    cam = design(**RETURN)
    bend = roller(*harmonic(30 * MM, RETURN_SPAN, U, rising=False), 30 * MM, 5 * MM)[1]
    end = float(bend[-1])
    assert end < 0.0 and np.all(bend >= end)  # the most concave pitch point is the joint
    exact = -1 / end + 10 * MM  # the concave surface lies Rr further out than the pitch curve
    radius, at = smallest_concave_radius(cam.contours()['surface'])
    assert radius == pytest.approx(exact, rel=REL, abs=0.0)
    assert at == pytest.approx(2 * math.pi, abs=1e-12)
    cutter_contours(cam.contours(), exact * (1 - 1e-9), False)
    with pytest.raises(InvalidParameter, match='smallest concave radius'):
        cutter_contours(cam.contours(), exact * (1 + 1e-9), False)  # was accepted


def test_conjugate_cam_smallest_radius_at_the_joint():
    # Roller 2 rides the other side: turned by pi, offset -e, travel h - s, same prime distance.
    cam = design(**RETURN, **{'follower.closure': 'conjugate'})
    s, v, a = harmonic(30 * MM, RETURN_SPAN, U, rising=False)
    curvature = roller(30 * MM - s, -v, -a, 30 * MM, -5 * MM)[1]
    assert np.all(curvature <= curvature[-1])
    exact = 1 / curvature[-1] - 10 * MM
    second = cam.closure.sides['second']
    assert second.radius_of_curvature_min == pytest.approx(exact, rel=REL, abs=0.0)
    assert second.at == pytest.approx(2 * math.pi, abs=1e-12)
    # cam 1 at the return's start (300 deg from the right) is the mirror image: the same radius
    first = cam.closure.sides['first']
    assert first.radius_of_curvature_min == pytest.approx(exact, rel=REL, abs=0.0)
    assert first.at == pytest.approx(300 * DEG, abs=1e-12)
