"""Engage blend: a quintic smoothstep in master position, p/v/a continuous at both ends."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.engage import Blend, Held, smoothstep
from cam_ros.core.ecam.master import CamMapping, chain_rule, ElectronicCam

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
CAM = ElectronicCam(build_design(parse_parameters(read_parameters_file(DEFAULT))).program,
                    CamMapping(0.2, 1.5, 0.003, -2.0))
H = 1e-5  # rad of master: central-difference step


def test_smoothstep_derivatives_are_those_of_its_polynomial():
    u = np.linspace(0.0, 1.0, 101)[1:-1]
    values = smoothstep(u)
    poly = np.polynomial.Polynomial([0, 0, 0, 10, -15, 6])
    for order, value in enumerate(values):
        np.testing.assert_allclose(value, poly.deriv(order)(u) if order else poly(u), atol=1e-9)
    ends = np.array(smoothstep(np.array([0.0, 1.0])))
    np.testing.assert_array_equal(ends[:3, 0], [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(ends[:3, 1], [1.0, 0.0, 0.0])


@pytest.mark.parametrize('q0, sign', [(2.0, 1.0), (2.0, -1.0), (7.3, 1.0)])
def test_blend_starts_on_the_held_path_ends_on_the_cam_and_is_smooth(q0, sign):
    distance = math.radians(30.0)
    blend = Blend(Held(0.004), CAM, q0, distance)
    start, end = blend.derivatives(q0), blend.derivatives(q0 + sign * distance)
    assert float(start.y) == 0.004 and float(start.dy) == 0.0 and float(start.d2y) == 0.0
    cam = CAM.derivatives(q0 + sign * distance)
    for got, want in zip(end[:3], cam[:3]):
        assert float(got) == pytest.approx(float(want), rel=1e-12, abs=1e-15)
    inside = q0 + sign * distance * np.linspace(0.05, 0.95, 19)
    for order in range(3):  # each derivative is the central difference of the one before
        low, high = blend.derivatives(inside - H), blend.derivatives(inside + H)
        np.testing.assert_allclose(blend.derivatives(inside)[order + 1],
                                   (high[order] - low[order]) / (2 * H), rtol=1e-5, atol=1e-7)


def test_setpoints_at_600_rpm_have_no_step_where_the_blend_begins_and_ends():
    omega, distance, q0 = 20 * math.pi, math.radians(30.0), 1.0  # 600 rpm, 2 rad/s^2
    held = Held(-0.01)
    blend = Blend(held, CAM, q0, distance)

    def steps(dt):  # across each end: path before at -dt, path after at +dt (seconds)
        ends = ((held, blend, q0), (blend, CAM, q0 + distance))
        return np.array([[abs(float(a) - float(b)) for a, b in zip(
            chain_rule(0.0, after.derivatives(q + omega * dt), omega, 2.0)[1:4],
            chain_rule(0.0, before.derivatives(q - omega * dt), omega, 2.0)[1:4])]
            for before, after, q in ends])

    coarse, fine = steps(1e-5), steps(1e-6)
    # Continuous: the difference across the end shrinks with the time apart (a step would not).
    assert np.all(fine <= coarse / 5 + 1e-15), (coarse, fine)
