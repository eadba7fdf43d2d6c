"""Tests of cam_ros.core.geometry.followers: construction checks name the parameter and the rule.

Their geometry (profiles, pressure angles, curvature) is tested through cam_geometry in
test_geometry.py.
"""
import math

import numpy as np

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.geometry.followers import (OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                             TranslatingRoller)
import pytest


@pytest.mark.parametrize('make, parameter', [
    (lambda: TranslatingRoller(0.0, 0.01), 'base_radius'),
    (lambda: TranslatingRoller(0.04, -0.01), 'roller_radius'),
    (lambda: TranslatingRoller(0.04, 0.01, 0.05), 'offset'),
    (lambda: TranslatingRoller(0.04, 0.01, float('nan')), 'offset'),
    (lambda: TranslatingRoller('4 cm', 0.01), 'base_radius'),
    (lambda: TranslatingFlat(-1.0), 'base_radius'),
    (lambda: TranslatingFlat(True), 'base_radius'),
    (lambda: OscillatingRoller(0.04, 0.01, 0.2, 0.07, True), 'base_radius'),
    (lambda: OscillatingRoller(0.04, 0.01, 0.09, 0.0, True), 'arm_length'),
    (lambda: OscillatingRoller(0.04, 0.01, 0.09, 0.07, 'yes'), 'arm_turns_with_cam'),
    (lambda: OscillatingFlat(0.04, 0.09, 0.06, True), 'face_offset'),
    (lambda: OscillatingFlat(0.04, 0.09, -0.05, True), 'face_offset'),
    (lambda: OscillatingFlat(0.04, -0.09, 0.0, True), 'pivot_distance'),
])
def test_invalid_followers_name_the_parameter(make, parameter):
    with pytest.raises(InvalidParameter) as error:
        make()
    assert error.value.parameter == parameter
    assert str(error.value).startswith(parameter + ' = ')


@pytest.mark.parametrize('offset', [0.0, 0.007, -0.03])
def test_translating_roller_centre_starts_on_the_prime_circle(offset):
    follower = TranslatingRoller(0.03, 0.01, offset)
    assert math.hypot(offset, follower.prime_height) == pytest.approx(0.04, rel=1e-15)


@pytest.mark.parametrize('pivot, arm', [(0.09, 0.07), (0.05, 0.08), (0.1, 0.1)])
def test_oscillating_roller_centre_starts_on_the_prime_circle(pivot, arm):
    psi0 = OscillatingRoller(0.03, 0.01, pivot, arm, True).initial_arm_angle
    centre = (arm * math.sin(psi0), pivot - arm * math.cos(psi0))  # (0, C) + L u, lam = +1
    assert math.hypot(*centre) == pytest.approx(0.04, rel=1e-14)


@pytest.mark.parametrize('face', [0.0, 0.02, -0.02])
def test_oscillating_flat_face_starts_tangent_to_the_base_circle(face):
    psi0 = OscillatingFlat(0.04, 0.09, face, False).initial_arm_angle
    normal = (math.cos(psi0), math.sin(psi0))  # of the face (and arm), away from the cam
    foot = (-face * normal[0], 0.09 - face * normal[1])  # face_offset from the pivot, cam side
    assert foot[0] * normal[0] + foot[1] * normal[1] == pytest.approx(0.04, rel=1e-14)
    assert 0.0 < psi0 < math.pi / 2


@pytest.mark.parametrize('with_cam', [True, False])
def test_an_oscillating_flat_arm_must_turn_slower_than_the_cam_and_keep_its_face_clear(with_cam):
    """1 - mu ds/dtheta > 0 (mu = +1 when the arm turns with the cam, -1 against it), and the
    face clear of the cam centre: pivot_distance sin(psi0 + s) > face_offset."""
    arm = OscillatingFlat(0.03, 0.09, 0.02, with_cam)
    mu = 1.0 if with_cam else -1.0
    s = np.zeros(3)
    assert arm._motion_problem(s, mu * np.array([0.0, 0.99, -5.0])) is None
    problem = arm._motion_problem(s, mu * np.array([0.0, 1.0, -5.0]))
    assert problem.parameter == 'ds[1]' and '1 - mu*ds/dtheta > 0' in problem.rule
    psi0 = math.asin(0.05 / 0.09)
    clear = math.asin(0.02 / 0.09) - psi0  # s where the face reaches the cam centre
    assert arm._motion_problem(np.array([0.0, clear + 1e-6]), np.zeros(2)) is None
    problem = arm._motion_problem(np.array([0.0, clear - 1e-6]), np.zeros(2))
    assert problem.parameter == 's[1]' and 'face must stay clear of the cam centre' in problem.rule
