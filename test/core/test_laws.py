"""Tests of the normalised motion laws: closed forms, finite differences, published values."""

import math
import subprocess
import sys

import numpy as np
import pytest

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import (ConstantAcceleration, Cycloidal, LAWS, LawValues, make_law,
                                      ModifiedSine, ModifiedTrapezoid, Polynomial345,
                                      Polynomial4567, Polynomial9, PolynomialLaw, SccaLaw,
                                      SimpleHarmonic, TableLaw, ViaPointLaw)

PI = math.pi
#: Agreement of two exact computations of the same quantity.
EXACT_ATOL = 1e-12
#: Agreement of characteristic values with their published closed forms (relative).
CHARACTERISTIC_RTOL = 1e-6
#: Central-difference step and allowed error (relative to max(1, peak)) per derivative order.
FD_STEP = {1: 1e-5, 2: 1e-4, 3: 1e-3}
FD_RTOL = {1: 1e-7, 2: 1e-5, 3: 1e-4}
#: Junction values printed with six decimals in the reference.
PRINTED_ATOL = 5e-7
#: A via point must be met this closely.
VIA_ATOL = 1e-9
#: Largest jump of y, y', y'' allowed at a junction that should be smooth.
JUNCTION_ATOL = 1e-9

#: seed 002: rise 0 -> 180 mm over 0-130 deg through (100 deg, 160 mm); the fall from 180 mm at
#: 170 deg through (200 deg, 160 mm) to 0 at 300 deg, normalised as a rise.
SEED_RISE_VIA = (100.0 / 130.0, 160.0 / 180.0)
SEED_FALL_VIA = (30.0 / 130.0, 20.0 / 180.0)

#: Parameters making every registered law; the first test checks nothing is missing.
LAW_PARAMS: dict[str, dict[str, object]] = {
    'dwell': {},
    'constant_velocity': {},
    'constant_acceleration': {},
    'simple_harmonic': {},
    'cycloidal': {},
    'polynomial_345': {},
    'polynomial_4567': {},
    'polynomial_9': {},
    'modified_trapezoid': {},
    'modified_sine': {},
    'scca': {'b': 0.3, 'c': 0.2, 'd': 0.5},
    'polynomial': {'conditions': [(0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0), (1.0, 0, 1.0),
                                  (1.0, 1, 0.0), (1.0, 2, 0.0), (0.5, 0, 0.6)]},
    'table': {'u': [0.0, 0.25, 0.5, 0.8, 1.0], 'y': [0.0, 0.1, 0.45, 0.9, 1.0]},
    'via_point': {'u_via': SEED_RISE_VIA[0], 'y_via': SEED_RISE_VIA[1]},
    # rest to rest over a unit stroke and span: the boundary polynomials of test_motion_tasks.py
    'poly5': {'stroke': 1.0, 'span': 1.0, 'start': (0.0, 0.0), 'end': (0.0, 0.0)},
    'poly7': {'stroke': 1.0, 'span': 1.0, 'start': (0.0, 0.0, 0.0), 'end': (0.0, 0.0, 0.0)},
}
RISES = [name for name in LAW_PARAMS if name != 'dwell']


def law_named(name):
    """Build a registered law with its test parameters."""
    return make_law(name, **LAW_PARAMS[name])


def test_every_registered_law_is_tested():
    assert set(LAW_PARAMS) == set(LAWS)


@pytest.mark.parametrize('name', LAW_PARAMS)
def test_law_reports_its_registry_name(name):
    assert law_named(name).name == name


@pytest.mark.parametrize('name', RISES)
def test_rise_starts_at_0_and_ends_at_1(name):
    y = law_named(name).evaluate([0.0, 1.0]).y
    assert y == pytest.approx([0.0, 1.0], abs=EXACT_ATOL)


def test_dwell_stays_at_0():
    values = law_named('dwell').evaluate(np.linspace(0.0, 1.0, 11))
    assert all(np.all(column == 0.0) for column in values)


@pytest.mark.parametrize('name', RISES)
def test_rise_never_moves_backwards(name):
    assert np.all(law_named(name).evaluate(np.linspace(0.0, 1.0, 2001)).y1 >= -EXACT_ATOL)


def _smooth_samples(law, margin):
    """Return u in (0, 1) at least margin away from the ends and the law's breakpoints."""
    u = np.linspace(0.02, 0.98, 193)
    for point in law.breakpoints:
        u = u[np.abs(u - point) > margin]
    return u


def _central_difference(f, u, order, h):
    """Return the central-difference estimate of the order-th derivative of f at u."""
    if order == 1:
        return (f(u + h) - f(u - h)) / (2.0 * h)
    if order == 2:
        return (f(u + h) - 2.0 * f(u) + f(u - h)) / h ** 2
    return (f(u + 2 * h) - 2.0 * f(u + h) + 2.0 * f(u - h) - f(u - 2 * h)) / (2.0 * h ** 3)


@pytest.mark.parametrize('order', [1, 2, 3])
@pytest.mark.parametrize('name', LAW_PARAMS)
def test_derivatives_match_finite_differences_of_y(name, order):
    law = law_named(name)
    h = FD_STEP[order]
    u = _smooth_samples(law, 3.0 * h)
    estimate = _central_difference(lambda x: law.evaluate(x).y, u, order, h)
    exact = law.evaluate(u)[order]
    scale = max(1.0, float(np.max(np.abs(exact))))
    assert np.max(np.abs(estimate - exact)) <= FD_RTOL[order] * scale


#: Characteristic values (peaks of |y'|, |y''|, |y'''|) from the reference table.  Constant
#: velocity: its acceleration impulses occur only against the neighbouring segments (reported by
#: the program), inside the law y'' = y''' = 0.  Constant acceleration: y'' steps inside, so the
#: jerk is unbounded.
REFERENCE_CHARACTERISTICS = {
    'dwell': (0.0, 0.0, 0.0),
    'constant_velocity': (1.0, 0.0, 0.0),
    'constant_acceleration': (2.0, 4.0, math.inf),
    'simple_harmonic': (PI / 2, PI ** 2 / 2, PI ** 3 / 2),
    'cycloidal': (2.0, 2 * PI, 4 * PI ** 2),
    'polynomial_345': (1.875, 10 / math.sqrt(3), 60.0),
    'polynomial_4567': (2.1875, 84 * math.sqrt(5) / 25, 52.5),
    # y' = 630 u^4 (1-u)^4; |y''| peaks where (u - 1/2)^2 = 1/28; |y'''| at u = 1/2.
    'polynomial_9': (630 / 256, 5040 * (3 / 14) ** 3 / math.sqrt(28), 2520 * 2 / 64),
    'modified_trapezoid': (2.0, 8 * PI / (PI + 2), 32 * PI ** 2 / (PI + 2)),
    'modified_sine': (4 * PI / (4 + PI), 4 * PI ** 2 / (4 + PI), 16 * PI ** 3 / (4 + PI)),
}
#: The same table as printed (4 to 5 significant digits), a check on the closed forms above.
PRINTED_CHARACTERISTICS = {
    'simple_harmonic': (1.5708, 4.9348, 15.503),
    'cycloidal': (2.0, 6.2832, 39.478),
    'polynomial_345': (1.875, 5.7735, 60.0),
    'polynomial_4567': (2.1875, 7.5132, 52.5),
    'modified_trapezoid': (2.0, 4.8881, 61.426),
    'modified_sine': (1.7596, 5.5280, 69.466),
}


@pytest.mark.parametrize('name', REFERENCE_CHARACTERISTICS)
def test_characteristic_values_match_the_reference_table(name):
    law = law_named(name)
    expected = REFERENCE_CHARACTERISTICS[name]
    assert (law.cv, law.ca, law.cj) == pytest.approx(expected, rel=CHARACTERISTIC_RTOL,
                                                     abs=EXACT_ATOL)


@pytest.mark.parametrize('name', PRINTED_CHARACTERISTICS)
def test_reference_closed_forms_match_the_printed_table(name):
    assert REFERENCE_CHARACTERISTICS[name] == pytest.approx(PRINTED_CHARACTERISTICS[name],
                                                            rel=5e-5)


@pytest.mark.parametrize('name', RISES)
def test_characteristic_values_bound_the_sampled_derivatives(name):
    law = law_named(name)
    values = law.evaluate(np.linspace(0.0, 1.0, 4001))
    for peak, column in zip((law.cv, law.ca, law.cj), values[1:]):
        sampled = float(np.max(np.abs(column)))
        assert sampled <= peak * (1 + CHARACTERISTIC_RTOL) + EXACT_ATOL
        if math.isfinite(peak):
            assert sampled == pytest.approx(peak, rel=1e-3, abs=EXACT_ATOL)


@pytest.mark.parametrize(('fractions', 'explicit'), [
    ((0.0, 1.0, 0.0), ConstantAcceleration()),
    ((0.0, 0.0, 1.0), SimpleHarmonic()),
    ((0.5, 0.0, 0.5), Cycloidal()),
    ((0.25, 0.5, 0.25), ModifiedTrapezoid()),
    ((0.25, 0.0, 0.75), ModifiedSine()),
    ((1e-310, 1.0, 1e-310), ConstantAcceleration()),  # pi / 1e-310 overflows: zones of 0
    ((1e-300, 1e-13, 1.0), SimpleHarmonic()),
], ids=['parabolic', 'harmonic', 'cycloidal', 'modified_trapezoid', 'modified_sine',
        'tiny_b_and_d', 'tiny_b_and_c'])
def test_scca_contains_the_classic_laws(fractions, explicit):
    u = np.linspace(0.0, 1.0, 801)
    scca, other = SccaLaw(*fractions).evaluate(u), explicit.evaluate(u)
    for mine, theirs in zip(scca, other):
        assert mine == pytest.approx(theirs, abs=1e-10)


@pytest.mark.parametrize('fractions', [(0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.5, 0.0, 0.5),
                                       (0.25, 0.5, 0.25), (0.25, 0.0, 0.75), (0.3, 0.2, 0.5),
                                       (0.1, 0.7, 0.2), (0.6, 0.4, 0.0)])
def test_scca_peak_acceleration_matches_the_closed_form(fractions):
    b, _, d = fractions
    expected = 4 * PI ** 2 / ((PI ** 2 - 8) * (b * b - d * d) - 2 * PI * (PI - 2) * b + PI ** 2)
    assert SccaLaw(*fractions).ca == pytest.approx(expected, rel=CHARACTERISTIC_RTOL)


def _modified_trapezoid_reference(u):
    """Reference piecewise y of the modified trapezoid (first half; second by symmetry)."""
    c, k = 8 * PI / (PI + 2), 4 * PI

    def first_half(x):
        y1 = c / k * (1 - math.cos(k / 8))
        y0 = c / k * (1 / 8 - math.sin(k / 8) / k)
        y2 = y0 + y1 * (3 / 8 - 1 / 8) + c / 2 * (3 / 8 - 1 / 8) ** 2
        v2 = y1 + c * (3 / 8 - 1 / 8)
        t = x - 3 / 8
        return np.where(x < 1 / 8, c / k * (x - np.sin(k * x) / k),
                        np.where(x < 3 / 8, y0 + y1 * (x - 1 / 8) + c / 2 * (x - 1 / 8) ** 2,
                                 y2 + v2 * t + c / k ** 2 * (1 - np.cos(k * t))))

    return np.where(u <= 0.5, first_half(u), 1 - first_half(1 - u))


def _modified_sine_reference(u):
    """Reference piecewise y of the modified sine."""
    c = 1 / (4 + PI)
    w = 4 * PI * u / 3 + PI / 3
    return np.where(u < 1 / 8, c * (PI * u - np.sin(4 * PI * u) / 4),
                    np.where(u < 7 / 8, c * (2 + PI * u - 9 / 4 * np.sin(w)),
                             c * (4 + PI * u - np.sin(4 * PI * u) / 4)))


@pytest.mark.parametrize(('law', 'reference'), [
    (ModifiedTrapezoid(), _modified_trapezoid_reference),
    (ModifiedSine(), _modified_sine_reference),
], ids=['modified_trapezoid', 'modified_sine'])
def test_piecewise_laws_match_the_reference_formulas(law, reference):
    u = np.linspace(0.0, 1.0, 1601)
    assert law.evaluate(u).y == pytest.approx(reference(u), abs=1e-12)


def test_modified_trapezoid_junction_values():
    values = ModifiedTrapezoid().evaluate([1 / 8, 3 / 8])
    assert values.y1 == pytest.approx([0.388985, 1.611015], abs=PRINTED_ATOL)
    assert values.y == pytest.approx([0.017669, 0.267669], abs=PRINTED_ATOL)


@pytest.mark.parametrize(('params', 'parameter'), [
    ({'b': -0.1, 'c': 0.6, 'd': 0.5}, 'b'),
    ({'b': 0.2, 'c': 1.2, 'd': 0.0}, 'c'),
    ({'b': 0.2, 'c': 0.2, 'd': math.nan}, 'd'),
    ({'b': 0.3, 'c': 0.3, 'd': 0.3}, 'b + c + d'),
])
def test_scca_rejects_bad_fractions(params, parameter):
    with pytest.raises(InvalidParameter) as caught:
        make_law('scca', **params)
    assert caught.value.parameter == parameter


# Polynomial laws -------------------------------------------------------------------------------

RISE_CONDITIONS = [(0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0),
                   (1.0, 0, 1.0), (1.0, 1, 0.0), (1.0, 2, 0.0)]
JERK_CONDITIONS = [(0.0, 3, 0.0), (1.0, 3, 0.0)]


@pytest.mark.parametrize(('conditions', 'expected'), [
    (RISE_CONDITIONS, [0, 0, 0, 10, -15, 6]),
    (RISE_CONDITIONS + JERK_CONDITIONS, [0, 0, 0, 0, 35, -84, 70, -20]),
    (RISE_CONDITIONS + [(0.5, 0, 0.6)], [0, 0, 0, 16.4, -34.2, 25.2, -6.4]),
], ids=['3-4-5', '4-5-6-7', '3-4-5 via y(1/2)=0.6'])
def test_polynomial_solve_reproduces_the_reference_coefficients(conditions, expected):
    law = PolynomialLaw.from_conditions(conditions)
    assert law.coefficients == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize('law', [Polynomial345(), Polynomial4567()], ids=['345', '4567'])
def test_named_polynomials_are_the_solved_ones(law):
    conditions = RISE_CONDITIONS + (JERK_CONDITIONS if len(law.coefficients) == 8 else [])
    assert PolynomialLaw.from_conditions(conditions).coefficients == pytest.approx(
        law.coefficients, abs=1e-9)


def test_polynomial_9_rests_to_the_fourth_derivative_at_both_ends():
    """Solved from y(1) = 1 and y' .. y'''' = 0 at both ends (ten conditions)."""
    conditions = [(at, order, 0.0) for at in (0.0, 1.0) for order in range(5)]
    conditions[5] = (1.0, 0, 1.0)
    solved = PolynomialLaw.from_conditions(conditions).coefficients
    assert solved == pytest.approx(Polynomial9().coefficients, abs=1e-7)
    assert solved[5:] == pytest.approx(_seed003_coefficients((5, 6, 7, 8, 9)), rel=1e-9)


def _seed003_coefficients(powers):
    """Seed 003, Eq. 4.6: C_p = prod over the other powers q of q / (q - p)."""
    return [math.prod(q / (q - p) for q in powers if q != p) for p in powers]


@pytest.mark.parametrize('powers', [(3, 4, 5), (4, 5, 6, 7), (3, 5, 7, 9), (2, 4, 6, 8, 10)])
def test_polynomial_solve_reproduces_the_seed_003_power_formula(powers):
    conditions = [(1.0, 0, 1.0)] + [(1.0, order, 0.0) for order in range(1, len(powers))]
    law = PolynomialLaw.from_conditions(conditions, powers=powers)
    solved = [law.coefficients[p] for p in powers]
    assert solved == pytest.approx(_seed003_coefficients(powers), rel=1e-9)
    others = [c for k, c in enumerate(law.coefficients) if k not in powers]
    assert others == pytest.approx([0.0] * len(others), abs=EXACT_ATOL)


def test_seed_003_worked_example_coefficients():
    assert _seed003_coefficients((4, 5, 6, 7)) == pytest.approx([35, -84, 70, -20])


@pytest.mark.parametrize(('conditions', 'powers', 'parameter'), [
    ([], None, 'conditions'),
    (RISE_CONDITIONS[:5] + [(0.0, 0, 0.0)], None, 'conditions'),  # repeated: singular
    (RISE_CONDITIONS, (3, 4, 5), 'conditions'),  # one power per condition
    ([(0.0, 0, 0.0), (1.5, 0, 1.0)], None, 'conditions[1]'),
    ([(0.0, -1, 0.0), (1.0, 0, 1.0)], None, 'conditions[0]'),
    ([(0.0, 0, 0.0), (1.0, 0)], None, 'conditions[1]'),
    ([(0.0, 0, 0.0), (1.0, 0, 1.0)], (1, 1), 'powers'),
])
def test_polynomial_solve_rejects_bad_conditions(conditions, powers, parameter):
    with pytest.raises(InvalidParameter) as caught:
        PolynomialLaw.from_conditions(conditions, powers)
    assert caught.value.parameter == parameter


def test_polynomial_must_be_a_rise():
    with pytest.raises(InvalidParameter, match=r'coefficients = .*y\(0\) = 0 and y\(1\) = 1'):
        PolynomialLaw((0.0, 2.0))


def test_polynomial_by_name_takes_coefficients_or_conditions():
    assert make_law('polynomial', coefficients=[0, 0, 3, -2]).evaluate(0.5).y == 0.5
    with pytest.raises(InvalidParameter, match='either coefficients or conditions'):
        make_law('polynomial')


# Table law -------------------------------------------------------------------------------------

def test_table_through_the_ends_only_is_the_345_polynomial():
    u = np.linspace(0.0, 1.0, 101)
    table, reference = TableLaw((0.0, 1.0), (0.0, 1.0)).evaluate(u), Polynomial345().evaluate(u)
    for mine, theirs in zip(table, reference):
        assert mine == pytest.approx(theirs, abs=1e-9)


def test_table_passes_its_points_and_starts_and_ends_at_rest():
    law = law_named('table')
    assert law.evaluate(law.u).y == pytest.approx(law.y, abs=EXACT_ATOL)
    ends = law.evaluate([0.0, 1.0])
    assert ends.y1 == pytest.approx([0, 0], abs=EXACT_ATOL)
    assert ends.y2 == pytest.approx([0, 0], abs=EXACT_ATOL)


def _limits(law, point):
    """Return the left and right limits of y, y', y'' at a breakpoint."""
    left = law.evaluate(np.nextafter(point, 0.0))
    right = law.evaluate(point)
    return np.array(left[:3], dtype=float), np.array(right[:3], dtype=float)


@pytest.mark.parametrize('name', ['table', 'via_point', 'modified_trapezoid', 'modified_sine'])
def test_piecewise_laws_are_c2_at_their_breakpoints(name):
    law = law_named(name)
    assert law.breakpoints
    for point in law.breakpoints:
        left, right = _limits(law, point)
        assert np.max(np.abs(right - left)) <= JUNCTION_ATOL


@pytest.mark.parametrize(('u', 'y', 'parameter'), [
    ([0.0, 0.5, 0.5, 1.0], [0.0, 0.3, 0.4, 1.0], 'u'),
    ([0.1, 0.5, 1.0], [0.0, 0.3, 1.0], 'u'),
    ([0.0, 0.5, 0.9], [0.0, 0.3, 1.0], 'u'),
    ([0.0, 1.0], [0.0, 0.5, 1.0], 'y'),
    ([0.0, 0.5, 1.0], [0.1, 0.3, 1.0], 'y'),
    ([0.0, 0.5, 1.0], [0.0, 1.2, 1.0], 'y'),
    ([0.0, math.nan, 1.0], [0.0, 0.3, 1.0], 'u'),
    ('abc', [0.0, 1.0], 'u'),
])
def test_table_rejects_bad_points(u, y, parameter):
    with pytest.raises(InvalidParameter) as caught:
        TableLaw(u, y)
    assert caught.value.parameter == parameter


# Via-point law (seed 002) ----------------------------------------------------------------------

VIA_POINTS = [SEED_RISE_VIA, SEED_FALL_VIA, (0.5, 0.5), (0.5, 0.9), (0.1, 0.9), (0.9, 0.05),
              (0.3, 0.3), (0.02, 0.5)]


@pytest.mark.parametrize('via', VIA_POINTS)
def test_via_point_law_passes_its_point_without_stopping(via):
    law = ViaPointLaw(*via)
    at_via = law.evaluate(via[0])
    assert float(at_via.y) == pytest.approx(via[1], abs=VIA_ATOL)
    assert float(at_via.y1) > 0.0
    inside = law.evaluate(np.linspace(0.0, 1.0, 20001)[1:-1])
    assert np.all(inside.y1 > 0.0)


@pytest.mark.parametrize('via', VIA_POINTS)
def test_via_point_law_starts_and_ends_at_rest(via):
    ends = ViaPointLaw(*via).evaluate([0.0, 1.0])
    assert ends.y == pytest.approx([0.0, 1.0], abs=VIA_ATOL)
    assert ends.y1 == pytest.approx([0.0, 0.0], abs=VIA_ATOL)
    assert ends.y2 == pytest.approx([0.0, 0.0], abs=VIA_ATOL)


@pytest.mark.parametrize('via', VIA_POINTS)
def test_via_point_law_is_c2_at_the_via_point(via):
    law = ViaPointLaw(*via)
    left, right = _limits(law, via[0])
    assert np.max(np.abs(right - left)) <= JUNCTION_ATOL
    assert right[2] == pytest.approx(0.0, abs=JUNCTION_ATOL)


def _two_lobe_acceleration(u_via, y_via, velocity, u):
    """The docstring's acceleration, written out: half-sine plus full-sine lobes per part."""
    first, second = u_via, 1 - u_via
    a1, b1 = PI * velocity / (2 * first), 2 * PI * (y_via - velocity * first / 2) / first ** 2
    a2 = PI * velocity / (2 * second)
    b2 = 2 * PI * (1 - y_via - velocity * second / 2) / second ** 2
    t1, t2 = u / first, (u - first) / second
    return np.where(u < u_via, a1 * np.sin(PI * t1) + b1 * np.sin(2 * PI * t1),
                    -a2 * np.sin(PI * t2) + b2 * np.sin(2 * PI * t2))


@pytest.mark.parametrize('via', VIA_POINTS)
def test_via_point_law_follows_its_documented_design(via):
    law = ViaPointLaw(*via)
    u = np.linspace(0.0, 1.0, 2001)
    expected = _two_lobe_acceleration(*via, law.velocity, u)
    assert law.evaluate(u).y2 == pytest.approx(expected, abs=1e-9 * law.ca)
    limit = 8 / 3 * min(via[1] / via[0], (1 - via[1]) / (1 - via[0]))
    assert 0.0 < law.velocity <= limit * (1 + 1e-12)
    # the chosen velocity gives the smallest peak acceleration among all admissible ones
    # (y'' is affine in the velocity, so all candidates are one array expression)
    dense = np.concatenate((np.linspace(0.0, via[0], 8001), np.linspace(via[0], 1.0, 8001)))
    offset = _two_lobe_acceleration(*via, 0.0, dense)
    slope = _two_lobe_acceleration(*via, 1.0, dense) - offset
    velocities = np.linspace(0.0, limit, 201)[1:, None]
    others = np.max(np.abs(offset + velocities * slope), axis=1)
    assert law.ca <= others.min() * (1 + 1e-6)


def test_seed_002_fall_is_the_mirror_image_of_the_rise():
    u = np.linspace(0.0, 1.0, 501)
    rise, fall = ViaPointLaw(*SEED_RISE_VIA), ViaPointLaw(*SEED_FALL_VIA)
    assert fall.evaluate(u).y == pytest.approx(1.0 - rise.evaluate(1.0 - u).y, abs=1e-12)


@pytest.mark.parametrize(('u_via', 'y_via', 'parameter'), [
    (0.0, 0.5, 'u_via'), (1.0, 0.5, 'u_via'), (-0.2, 0.5, 'u_via'), (math.nan, 0.5, 'u_via'),
    (0.5, 0.0, 'y_via'), (0.5, 1.0, 'y_via'), (0.5, 1.3, 'y_via'), (0.5, 'high', 'y_via'),
])
def test_via_point_law_rejects_unreachable_points(u_via, y_via, parameter):
    with pytest.raises(InvalidParameter) as caught:
        ViaPointLaw(u_via, y_via)
    assert caught.value.parameter == parameter
    assert 'strictly between 0 and 1' in str(caught.value) or 'finite' in str(caught.value)


# Registry and evaluation contract --------------------------------------------------------------

def test_unknown_law_name_lists_the_known_ones():
    with pytest.raises(InvalidParameter) as caught:
        make_law('cycloid')
    assert caught.value.parameter == 'law'
    assert str(caught.value).startswith("law = 'cycloid': must be one of dwell, ")
    assert all(name in str(caught.value) for name in LAWS)


def test_make_law_rejects_unknown_and_missing_parameters():
    with pytest.raises(InvalidParameter, match=r'^height = 2: is not a parameter of law cycl'):
        make_law('cycloidal', height=2)
    with pytest.raises(InvalidParameter, match=r'^y_via = None: is required by law via_point'):
        make_law('via_point', u_via=0.5)


@pytest.mark.parametrize('bad', [-0.1, 1.0 + 1e-12, math.nan, math.inf, 'half'])
def test_evaluate_rejects_u_outside_the_unit_interval(bad):
    with pytest.raises(InvalidParameter, match=r'^u = .*: must lie in \[0, 1\]'):
        Cycloidal().evaluate([0.5, bad])


@pytest.mark.parametrize('name', LAW_PARAMS)
def test_evaluate_keeps_the_shape_of_u(name):
    u = np.linspace(0.0, 1.0, 12).reshape(3, 4)
    values = law_named(name).evaluate(u)
    assert all(column.shape == (3, 4) for column in values)
    assert all(column.shape == () for column in law_named(name).evaluate(0.25))


def test_laws_are_immutable_values():
    law = ViaPointLaw(*SEED_RISE_VIA)
    with pytest.raises(AttributeError):
        law.u_via = 0.5  # type: ignore[misc]
    assert law == ViaPointLaw(*SEED_RISE_VIA)
    assert hash(SccaLaw(0.25, 0.5, 0.25)) == hash(SccaLaw(0.25, 0.5, 0.25))


@pytest.mark.parametrize('name', LAW_PARAMS)
def test_derivatives_into_the_callers_arrays_match_evaluate(name):
    u = np.linspace(0.0, 1.0, 101)
    values = LawValues(u.copy(), *(np.full(u.shape, math.nan) for _ in range(3)))
    law_named(name)._derivatives_into(values)  # the motion program's path
    for written, evaluated in zip(values, law_named(name).evaluate(u)):
        np.testing.assert_array_equal(written, evaluated)


def test_importing_the_core_and_evaluating_a_law_leave_scipy_unloaded():
    probe = ('import sys; from cam_ros.core import make_law; make_law("cycloidal").evaluate(0.5); '
             'print([name for name in sys.modules if name.split(".")[0] == "scipy"])')
    result = subprocess.run([sys.executable, '-c', probe], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == '[]'  # scipy costs the node 0.5 s of start-up
