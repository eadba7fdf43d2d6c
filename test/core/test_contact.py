"""Hertz line contact against published values and its own identities."""
from __future__ import annotations

import math

import numpy as np

from cam_ros.core.dynamics.contact import effective_modulus, half_width, peak_pressure

E, NU = 207e9, 0.3


def test_equal_steel_cylinders_match_roarks_coefficients():
    # Roark's Formulas for Stress and Strain, Table 14.1, cylinder on cylinder with E1 = E2 = E
    # and nu = 0.3: sigma_max = 0.591 sqrt(p E / K_D), contact band width 2b = 2.15
    # sqrt(p K_D / E), with K_D = D1 D2 / (D1 + D2) and p the load per unit length.
    d1, d2, load = 0.050, 0.030, 2.0e5  # m, m, N/m
    k_d = d1 * d2 / (d1 + d2)
    curvature = 2.0 / d1 + 2.0 / d2
    modulus = effective_modulus(E, NU, E, NU)
    assert math.isclose(peak_pressure(load, curvature, modulus),
                        0.591 * math.sqrt(load * E / k_d), rel_tol=1e-3)
    assert math.isclose(2.0 * half_width(load, curvature, modulus),
                        2.15 * math.sqrt(load * k_d / E), rel_tol=2e-3)


def test_pressure_and_width_carry_the_load_as_a_semi_ellipse():
    load = np.array([1e3, 5e4, 3e5])
    curvature = np.array([10.0, 80.0, 300.0])
    modulus = effective_modulus(207e9, 0.3, 72e9, 0.33)
    p0, b = peak_pressure(load, curvature, modulus), half_width(load, curvature, modulus)
    np.testing.assert_allclose(math.pi * b * p0 / 2.0, load, rtol=1e-14)
    # Hertz's half-width from the pressure: b^2 = 4 w R' / (pi E*)
    np.testing.assert_allclose(b ** 2, 4.0 * load / (curvature * math.pi * modulus), rtol=1e-14)


def test_effective_modulus_of_dissimilar_bodies():
    # steel on aluminium: 1/E* = 0.91/207e9 + (1 - 0.33^2)/72e9
    expected = 1.0 / (0.91 / 207e9 + (1.0 - 0.33 ** 2) / 72e9)
    assert math.isclose(effective_modulus(207e9, 0.3, 72e9, 0.33), expected, rel_tol=1e-15)
    assert math.isclose(effective_modulus(E, NU, E, NU), E / (2 * (1 - NU ** 2)), rel_tol=1e-15)


def test_concave_cam_lowers_the_stress_flat_face_and_no_contact():
    roller, modulus = 0.01, effective_modulus(E, NU, E, NU)
    convex = peak_pressure(1e4, 1 / 0.05 + 1 / roller, modulus)
    concave = peak_pressure(1e4, -1 / 0.05 + 1 / roller, modulus)
    assert concave < convex
    assert math.isclose(concave / convex, math.sqrt((1 / roller - 20) / (1 / roller + 20)))
    assert peak_pressure(0.0, 50.0, modulus) == 0.0
    assert peak_pressure(-3.0, 50.0, modulus) == 0.0  # a lifted follower carries nothing
    assert half_width(-3.0, 50.0, modulus) == 0.0
    assert np.isnan(peak_pressure(1e4, -5.0, modulus))  # undercut: no Hertz contact
    assert np.isnan(half_width(1e4, 0.0, modulus))
