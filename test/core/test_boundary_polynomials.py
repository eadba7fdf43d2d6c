"""Tests of the VDI 2143 boundary polynomials poly5/poly7, poly5 G-G as the 3-4-5
superposition, and the motion task names.

References, all written here (shared ones in motion_task_references) and independent of the code
under test:
* Poly5/Poly7: the 6x6 / 8x8 system of the end conditions in u (d^k/du^k u^p = p!/(p-k)! u^(p-k)),
  solved by numpy.linalg.solve; the closed-form quintic of Biagiotti & Melchiorri (ch. 2); the
  4-5-6-7 polynomial as the rest-to-rest septic.
* Poly5 G-G: s = s0 + v x + (H - v X) g(x / X) with the 3-4-5 g = 10 z^3 - 15 z^4 + 6 z^5 and its
  derivatives written out.
* Task names: end values of each end type (R: v = a = 0, G: v only, U: a only, B: both).
"""

import math

import numpy as np
import pytest
from hypothesis import given, HealthCheck, settings, strategies as st

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion._polynomial import Poly5, Poly7
from cam_ros.core.motion.laws import (ConstantAcceleration, ConstantVelocity, LAWS, make_law,
                                      Polynomial345, Polynomial4567)
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import motion_task, Segment, segment_values
from cam_ros.core.motion.tasks import build_segments, TaskSpec
from motion_task_references import (assert_close, deg, derivative_coefficients, EXACT_RTOL,
                                    EXAMPLES, gg_program, NAN, peak, PEAK_RTOL, polynomial_system,
                                    SOLVE_RTOL, travel, TWO_PI)


# 1. Poly5 and Poly7 through random end values -------------------------------------------------

strokes = st.one_of(st.just(0.0), st.floats(1e-6, 1.0), st.floats(-1.0, -1e-6))
spans = st.floats(deg(5.0), TWO_PI)
rates = st.floats(-2.0, 2.0, allow_subnormal=False)
starts = st.floats(-TWO_PI, TWO_PI)
positions = st.floats(-0.5, 0.5)


def evaluation_bound(coefficients, order, span):
    """Return sum_p |c_p| p!/(p - order)! / span**order: the size Horner's rounding scales with.

    A polynomial's derivative at u = 1 sums terms this large; 1e-12 of it is rounding, not error.
    """
    return sum(abs(c) * math.perm(p, order) for p, c in enumerate(coefficients)) / span ** order


def check_through(cls, stroke, span, start, end, theta0, s0):
    """Build a boundary polynomial's segment; check its end values and the direct solve."""
    law = cls.through(stroke, span, start, end)
    segment = Segment(law, theta0, theta0 + span, s0, s0 + stroke, amplitude=law.amplitude)
    expected = polynomial_system(span, stroke, start, end)
    size = travel(span, stroke, start, end)
    scale = [max(size / span ** k, evaluation_bound(expected, k, span)) for k in range(4)]
    scale[0] = max(scale[0], abs(s0))
    for at, position, derivatives in ((0.0, s0, start), (1.0, s0 + stroke, end)):
        values = segment_values(segment, at)
        assert_close(values.y, position, scale[0], what=f's at u = {at}')
        for k, value in enumerate(derivatives, 1):
            assert_close(values[k], value, scale[k], what=f'd{k}s at u = {at}')
    actual = np.zeros(expected.size)
    coefficients = np.array(law.coefficients) * law.amplitude
    actual[:coefficients.size] = coefficients
    assert_close(actual, expected, size, SOLVE_RTOL, 'coefficients of s - s_start in u')
    u = np.linspace(0.0, 1.0, 101)
    values = segment_values(segment, u)
    for k in range(4):
        reference = np.polynomial.polynomial.polyval(u, derivative_coefficients(expected, k))
        assert_close(values[k] - (s0 if k == 0 else 0.0), reference / span ** k,
                     scale[k], SOLVE_RTOL, f'd{k}s on [0, 1]')
    if stroke:
        assert law.amplitude == stroke
    return law, segment


@settings(max_examples=EXAMPLES, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(stroke=strokes, span=spans, v0=rates, a0=rates, v1=rates, a1=rates, theta0=starts,
       s0=positions)
def test_poly5_meets_its_end_values_and_the_direct_solve(stroke, span, v0, a0, v1, a1, theta0,
                                                         s0):
    check_through(Poly5, stroke, span, (v0, a0), (v1, a1), theta0, s0)


@settings(max_examples=EXAMPLES, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(stroke=strokes, span=spans, v0=rates, a0=rates, j0=rates, v1=rates, a1=rates,
       j1=rates, theta0=starts, s0=positions)
def test_poly7_meets_its_end_values_and_the_direct_solve(stroke, span, v0, a0, j0, v1, a1, j1,
                                                         theta0, s0):
    check_through(Poly7, stroke, span, (v0, a0, j0), (v1, a1, j1), theta0, s0)


@settings(max_examples=EXAMPLES, deadline=None, database=None)
@given(stroke=st.floats(-1.0, 1.0).filter(lambda h: abs(h) > 1e-6), span=spans, v0=rates,
       a0=rates, v1=rates, a1=rates)
def test_poly5_is_the_published_closed_form(stroke, span, v0, a0, v1, a1):
    """Biagiotti & Melchiorri's c3, c4, c5 of the general quintic (from the notes)."""
    law = Poly5.through(stroke, span, (v0, a0), (v1, a1))
    h, x, xx = stroke, span, span ** 2 / 2.0
    expected = [0.0, v0 * x, a0 * xx,
                10 * h - (6 * v0 + 4 * v1) * x - (3 * a0 - a1) * xx,
                -15 * h + (8 * v0 + 7 * v1) * x + (3 * a0 - 2 * a1) * xx,
                6 * h - 3 * (v0 + v1) * x - (a0 - a1) * xx]
    assert_close(np.array(law.coefficients) * law.amplitude, expected,
                 travel(span, stroke, (v0, a0), (v1, a1)), what='quintic coefficients')


def test_rest_to_rest_septic_is_the_4567_polynomial():
    law = Poly7.through(0.03, deg(120.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert law.amplitude == 0.03
    assert law.coefficients == pytest.approx([0, 0, 0, 0, 35, -84, 70, -20], abs=1e-10)


def test_rest_to_rest_quintic_is_the_345_polynomial():
    law = Poly5.through(-0.02, deg(90.0), (0.0, 0.0), (0.0, 0.0))
    assert law.amplitude == -0.02
    assert law.coefficients == pytest.approx([0, 0, 0, 10, -15, 6], abs=EXACT_RTOL * 20)


@pytest.mark.parametrize('cls, start, end', [
    (Poly5, (0.0, 3.0), (0.0, 3.0)),
    (Poly5, (0.4, -1.0), (0.7, 2.0)),
    (Poly7, (0.0, -2.0, 1.0), (0.0, -2.0, 0.0)),
])
def test_closed_loop_amplitude_is_its_largest_excursion(cls, start, end):
    """A segment that ends where it starts (stroke 0) scales y by its peak |s - s_start|."""
    span = 1.3
    law = cls.through(0.0, span, start, end)
    coefficients = polynomial_system(span, 0.0, start, end)
    excursion = peak(lambda u: np.polynomial.polynomial.polyval(u, coefficients))
    assert law.amplitude == pytest.approx(excursion, rel=PEAK_RTOL)
    assert np.max(np.abs(law.evaluate(np.linspace(0.0, 1.0, 2001)).y)) <= 1.0 + 1e-9


@pytest.mark.parametrize('cls, start, end, field', [
    (Poly5, (0.0, 0.0, 0.0), (0.0, 0.0), 'start'),
    (Poly5, (0.0, 0.0), (0.0,), 'end'),
    (Poly7, (0.0, 0.0), (0.0, 0.0, 0.0), 'start'),
    (Poly5, (0.0, math.inf), (0.0, 0.0), 'start'),
    (Poly7, (0.0, 0.0, 0.0), (0.0, NAN, 0.0), 'end'),
])
def test_boundary_polynomial_refuses_wrong_end_values(cls, start, end, field):
    with pytest.raises(InvalidParameter) as caught:
        cls.through(0.01, 1.0, start, end)
    assert caught.value.parameter == field


def test_boundary_polynomials_are_registered():
    assert LAWS['poly5'](stroke=1.0, span=1.0, start=(0.0, 0.0), end=(0.0, 0.0)).name == 'poly5'
    law = make_law('poly7', stroke=2.0, span=0.5, start=(1.0, 0.0, 0.0), end=(1.0, 0.0, 0.0))
    assert isinstance(law, Poly7)


# 2. Poly5 G-G equals the 3-4-5 superposition ---------------------------------------------------

@pytest.mark.parametrize('stroke, v', [(0.03, 0.02), (0.03, 0.05), (-0.01, 0.015), (0.0, -0.01)])
def test_poly5_with_equal_velocities_is_the_345_superposition(stroke, v):
    span = deg(70.0)
    poly = Poly5.through(stroke, span, (v, 0.0), (v, 0.0))
    segment = Segment(poly, 0.4, 0.4 + span, 0.1, 0.1 + stroke, amplitude=poly.amplitude)
    superposed = build_segments([
        TaskSpec(Polynomial345(), 0.4, 0.4 + span, 0.1, 0.1 + stroke, (v, NAN, NAN),
                 (v, NAN, NAN)),
        TaskSpec(ConstantVelocity(), 0.4 + span, 0.4 + TWO_PI, 0.1 + stroke,
                 0.1 + stroke + v * (TWO_PI - span), (v, NAN, NAN), (v, NAN, NAN))])[0]
    u = np.linspace(0.0, 1.0, 257)
    x, z = u * span, u
    g = [10 * z ** 3 - 15 * z ** 4 + 6 * z ** 5, 30 * z ** 2 - 60 * z ** 3 + 30 * z ** 4,
         60 * z - 180 * z ** 2 + 120 * z ** 3, 60 - 360 * z + 360 * z ** 2]
    rest = stroke - v * span
    closed = [0.1 + v * x + rest * g[0], v + rest * g[1] / span, rest * g[2] / span ** 2,
              rest * g[3] / span ** 3]
    size = travel(span, stroke, (v,))
    for k in range(4):
        assert_close(segment_values(segment, u)[k], closed[k], size / span ** k,
                     what=f'poly5 d{k}s')
        assert_close(segment_values(superposed, u)[k], closed[k], size / span ** k,
                     what=f'3-4-5 superposition d{k}s')


# 6. Motion task names ----------------------------------------------------------------------

END_TYPES = {'R': (0.0, 0.0), 'G': (0.011, 0.0), 'U': (0.0, -0.02), 'B': (-0.008, 0.015)}
JERKS = {'R': 0.0, 'G': 0.0, 'U': 0.003, 'B': -0.004}


@pytest.mark.parametrize('left', END_TYPES)
@pytest.mark.parametrize('right', END_TYPES)
@pytest.mark.parametrize('cls', [Poly5, Poly7])
def test_motion_task_names_every_pair(cls, left, right):
    start, end = END_TYPES[left], END_TYPES[right]
    if cls is Poly7:
        start, end = (*start, JERKS[left]), (*end, JERKS[right])
    law = cls.through(0.01, 1.1, start, end)
    segment = Segment(law, 0.2, 1.3, 0.0, 0.01, amplitude=law.amplitude)
    assert motion_task(segment) == f'{left}-{right}'


@pytest.mark.parametrize('task, begin, finish', [
    ('R-R', (0.0, 0.0), (0.0, 0.0)),
    ('R-G', (0.0, 0.0), (0.03, 0.0)),
    ('G-G', (0.01, 0.0), (0.03, 0.0)),
    ('G-U', (0.03, 0.0), (0.0, -0.02)),
    ('U-U', (0.0, 0.02), (0.0, -0.02)),
    ('B-B', (0.01, 0.02), (0.02, -0.01)),
    ('U-B', (0.0, 0.02), (0.01, 0.01)),
    ('B-R', (0.01, -0.02), (0.0, 0.0)),
])
def test_built_segments_report_their_task(task, begin, finish):
    """A poly5 task segment rising 0.02, back by two poly5 through a G joint (velocity -0.005)."""
    span, middle = 1.5, 1.5 + (TWO_PI - 1.5) / 2
    specs = [TaskSpec('poly5', 0.0, span, 0.0, 0.02, (*begin, NAN), (*finish, NAN)),
             TaskSpec('poly5', span, middle, 0.02, 0.01, (NAN,) * 3, (-0.005, 0.0, NAN)),
             TaskSpec('poly5', middle, TWO_PI, 0.01, 0.0)]
    program = MotionProgram(build_segments(specs))
    assert [item.task for item in program.segment_summary()] == [
        task, f'{task[-1]}-G', f'G-{task[0]}']
    assert [jump for jump in program.continuity_report() if jump.order <= 2] == []


def test_rest_to_rest_laws_give_r_r_and_g_g():
    assert gg_program(Polynomial4567()).segment_summary()[0].task == 'G-G'
    assert gg_program(Polynomial4567(), v=0.0).segment_summary()[0].task == 'R-R'
    # a rest-to-rest law solves G-G even where its own end acceleration does not vanish (the
    # continuity report lists that jump)
    assert gg_program(ConstantAcceleration()).segment_summary()[0].task == 'G-G'
    harmonic = Segment(make_law('simple_harmonic'), 0.0, 1.0, 0.0, 0.02)
    assert motion_task(harmonic) == 'R-R'


def test_a_loop_with_a_negligible_leading_term_keeps_its_excursion():
    """Hypothesis found it: v1 = 5e-274 left a 1e-273 z^5 term that lost the peak at z = 1/2."""
    law = Poly5.through(0.0, 1.0, (0.0, 1.0), (5.267373244881407e-274, 1.0))
    assert law.amplitude == pytest.approx(1.0 / 32.0, rel=1e-12)  # 0.5 z^2 (1 - z)^2 at 1/2
    check_through(Poly5, 0.0, 1.0, (0.0, 1.0), (5.267373244881407e-274, 1.0), 0.0, 0.0)
