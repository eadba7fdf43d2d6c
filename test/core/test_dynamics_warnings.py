"""A design's own verdict with dynamics: warnings, ok, the cached dynamics figures, cam angles."""
from __future__ import annotations

import math

import pytest
from test_dynamics import build, cosine_cam, H, K, M, P

from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.dynamics.report import dynamics_report
from cam_ros.core.report import design_report

TWO_PI = 2.0 * math.pi
UNDAMPED = {'dynamics.damping_ratio': 0.0, 'dynamics.external_force': 0.0}


def jumping(**updates: object) -> dict:
    """Return the undamped cosine cam at 1.2 x its jump speed."""
    omega = 1.2 * math.sqrt((2 * K + 2 * P / H) / M)
    return cosine_cam(cam_speed=omega, **UNDAMPED, **updates)


def test_cam_angles_read_in_0_360_and_span_ends_in_0_360_inclusive():
    short = TWO_PI - 1e-4  # 359.9943 deg
    assert cam_degrees(short) == pytest.approx(360.0 - math.degrees(1e-4), abs=1e-9)
    assert cam_degrees(short, 1) == 0.0 and cam_degrees(TWO_PI) == 0.0
    assert f'{cam_degrees(-1e-12, 1):.1f}' == '0.0'
    assert cam_degrees(short, 1, end=True) == 360.0 == cam_degrees(TWO_PI, end=True)
    assert cam_degrees(math.pi / 2, 1, end=True) == 90.0
    assert cam_degrees(math.radians(359.94), 1) == 359.9


def test_a_jumping_design_adds_its_jump_after_the_geometry_warnings():
    omega = 1.2 * math.sqrt((2 * K + 2 * P / H) / M)
    limit = {'limits.min_radius_of_curvature': 0.1}  # the flat face's radius is RB + H/2
    design = build(jumping(**limit))
    kinematic = build(jumping(**limit, **{'dynamics.mass': 0.0, 'dynamics.spring_rate': 0.0,
                                          'dynamics.spring_preload': 0.0}))  # no train
    assert kinematic.dynamics_check is None and kinematic.warnings()  # the radius warning
    # Q = (M w^2 - K) H/2 cos(theta) + K H/2 + P is negative around 180 deg
    start = math.degrees(math.acos(-(K * H / 2 + P) / ((M * omega ** 2 - K) * H / 2)))
    assert design.warnings() == kinematic.warnings() + [
        f'the follower leaves the cam between {start:.1f} and {360.0 - start:.1f} deg at '
        f'{omega:.6g} rad/s']


def test_the_design_fails_on_a_jump_alone_as_the_report_does():
    design = build(jumping())
    assert design.check.ok and not design.ok
    assert design_report(design).ok is False
    steady = build(cosine_cam(**UNDAMPED))
    assert steady.ok and steady.warnings() == []


def test_the_dynamics_figures_are_computed_once_and_are_the_reports():
    design = build(cosine_cam())
    figures = design.dynamics_check
    assert figures is not None and design.dynamics_check is figures
    assert figures == dynamics_report(design.dynamics, design.program, design.evaluate)
    assert design_report(design).dynamics is figures
