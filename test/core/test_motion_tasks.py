"""Tests of the VDI 2143 motion tasks: poly5/poly7, G-G superposition, inflection, task names,
refusals, forced velocity overshoot and programs that advance.

References, all written here and independent of the code under test:
* Poly5/Poly7: the 6x6 / 8x8 system of the end conditions in u (d^k/du^k u^p = p!/(p-k)! u^(p-k)),
  solved by numpy.linalg.solve; the closed-form quintic of Biagiotti & Melchiorri (ch. 2); the
  4-5-6-7 polynomial as the rest-to-rest septic.
* G-G: s = s0 + v x + (H - v X) g(x / X) from the law's own `evaluate` (g), with
  y'max = v + Cv (H/X - v) and |y''|max = Ca |H - v X| / X^2, Cv and Ca found here on a dense grid
  of g', g'' with a bounded refinement (scipy), or their published closed forms.
* Inflection: f(z) = 2 lambda g(z / (2 lambda)) for z <= lambda, else
  1 - 2 (1 - lambda) (1 - g(1/2 + (z - lambda) / (2 (1 - lambda)))), its derivatives by the chain
  rule; peaks Ca / (2 lambda) and Ca / (2 (1 - lambda)) per side, Cv overall.
* Forced overshoot of an R-G quintic with H = v X: ds = v (18 z^2 - 32 z^3 + 15 z^4) peaks at
  z = 3/5 with 1.512 v, so it passes v by 0.512 v; with H = v X / 2, ds = v (3 z^2 - 2 z^3) stays
  below v.
* Central finite differences of s over the cam angle.
"""

import math

import numpy as np
import pytest
from hypothesis import given, HealthCheck, settings, strategies as st
from scipy.optimize import minimize_scalar

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion._polynomial import Poly5, Poly7
from cam_ros.core.motion.inflection import inflected, InflectedLaw
from cam_ros.core.motion.laws import (ConstantAcceleration, ConstantVelocity, Cycloidal, Dwell,
                                      LAWS, make_law, Polynomial345, Polynomial4567)
from cam_ros.core.motion.program import (motion_task, MotionProgram, Segment,
                                         segment_values)
from cam_ros.core.motion.tasks import build_segments, TaskSpec

PI = math.pi
TWO_PI = 2.0 * math.pi
NAN = math.nan
deg = math.radians
#: Agreement of two exact computations, relative to the natural scale of the quantity.
EXACT_RTOL = 1e-12
#: Agreement of a polynomial with the direct solve of its 8x8 system (condition number ~1e5).
SOLVE_RTOL = 1e-10
#: Agreement of a peak with its reference (dense grid + bounded refinement on both sides).
PEAK_RTOL = 1e-9
#: Samples of the reference peak searches, and the refinement's bracket tolerance in u.
REFERENCE_SAMPLES = 20_001
REFINE_XATOL = 1e-14
#: Central-difference step (rad) and allowed error relative to the derivative's scale.
FD_STEP = {1: 1e-5, 2: 1e-5, 3: 1e-5}
FD_RTOL = {1: 1e-8, 2: 1e-7, 3: 1e-6}
#: Limits of s and its derivatives from either side of the inflection, one ulp apart in u.
LIMIT_RTOL = 1e-9
#: Examples per hypothesis property.
EXAMPLES = 150

#: Every registered law the G-G superposition serves (rest-to-rest rises), with its parameters.
REST_TO_REST = {
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
    'via_point': {'u_via': 0.4, 'y_via': 0.5},
}
#: Registered laws that are not rest-to-rest rises (or are built from end values, not a shape).
NOT_REST_TO_REST = {'dwell', 'constant_velocity', 'poly5', 'poly7'}
#: Symmetric laws (g(u) + g(1 - u) = 1) whose inflection may move; the table's points are
#: symmetric about (1/2, 1/2), so its spline is too.
SYMMETRIC = {
    'cycloidal': {},
    'simple_harmonic': {},
    'polynomial_345': {},
    'polynomial_4567': {},
    'polynomial_9': {},
    'modified_trapezoid': {},
    'modified_sine': {},
    'constant_acceleration': {},
    'scca': {'b': 0.2, 'c': 0.3, 'd': 0.5},
    'table': {'u': [0.0, 0.3, 0.5, 0.7, 1.0], 'y': [0.0, 0.2, 0.5, 0.8, 1.0]},
}
INFLECTIONS = (0.15, 0.3, 0.45, 0.62, 0.85)


# Independent references ----------------------------------------------------------------------

def polynomial_system(span, stroke, start, end):
    """Return the coefficients in u of s(u) - s_start through the end derivatives (per rad).

    One row per condition d^k/du^k p(u0) = value * span**k, written out here and solved by
    numpy.linalg.solve.
    """
    orders = len(start)
    size = 2 * (orders + 1)
    rows, values = [], []
    for at, position, derivatives in ((0.0, 0.0, start), (1.0, stroke, end)):
        for k, value in enumerate((position, *derivatives)):
            rows.append([math.perm(p, k) * at ** (p - k) if p >= k else 0.0
                         for p in range(size)])
            values.append(value * span ** k)
    return np.linalg.solve(np.array(rows), np.array(values))


def derivative_coefficients(coefficients, order):
    """Return the coefficients (lowest power first) of the order-th derivative in u."""
    c = np.array(coefficients, dtype=float)
    for _ in range(order):
        c = c[1:] * np.arange(1, c.size)
    return c


def travel(span, stroke, *ends):
    """Return the natural size of a segment's motion: the largest |d^k s| span^k at its ends."""
    sizes = [abs(stroke)]
    for derivatives in ends:
        sizes += [abs(value) * span ** k for k, value in enumerate(derivatives, 1)]
    return max(sizes)


def peak(function, low=0.0, high=1.0, samples=REFERENCE_SAMPLES):
    """Return max |function| over [low, high]: a dense grid and a bounded refinement."""
    u = np.linspace(low, high, samples)
    values = np.abs(function(u))
    index = int(np.argmax(values))
    bracket = (u[max(index - 1, 0)], u[min(index + 1, samples - 1)])
    refined = minimize_scalar(lambda x: -abs(float(function(np.array([x]))[0])), bounds=bracket,
                              method='bounded', options={'xatol': REFINE_XATOL})
    return max(float(values[index]), -float(refined.fun))


def law_peaks(law):
    """Return (Cv, Ca) of a rest-to-rest law from its g', g'' (each piece searched apart)."""
    edges = [0.0, *law.breakpoints, 1.0]
    result = []
    for order in (1, 2):
        result.append(max(peak(lambda u, k=order: law.evaluate(np.clip(u, 0.0, 1.0))[k],
                               low, np.nextafter(high, -np.inf))
                          for low, high in zip(edges[:-1], edges[1:])))
    return tuple(result)


def rest_to_rest(name):
    return make_law(name, **REST_TO_REST[name])


def symmetric(name):
    return make_law(name, **SYMMETRIC[name])


def assert_close(actual, expected, scale, rtol=EXACT_RTOL, what=''):
    """Check |actual - expected| <= rtol * scale everywhere, reporting the worst."""
    error = np.max(np.abs(np.asarray(actual, dtype=float) - np.asarray(expected, dtype=float)))
    assert error <= rtol * scale, f'{what}: error {error:.3g} > {rtol:g} * {scale:.3g}'


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


# 3. G-G superposition of every rest-to-rest law ------------------------------------------------

GG_SPAN, GG_STROKE, GG_VELOCITY = 1.2, 0.03, 0.01  # H/X = 0.025 > v: the law adds speed
GG_START, GG_POSITION = 0.3, 0.004


def test_every_registered_law_is_classified():
    assert set(REST_TO_REST) | NOT_REST_TO_REST == set(LAWS)


def gg_program(law, span=GG_SPAN, stroke=GG_STROKE, v=GG_VELOCITY, inflection=0.5):
    """A G-G segment of law at velocity v, then a poly5 back to the start at that velocity."""
    start, s0 = GG_START, GG_POSITION
    specs = [TaskSpec(law, start, start + span, s0, s0 + stroke, (v, NAN, NAN), (v, NAN, NAN),
                      inflection),
             TaskSpec('poly5', start + span, start + TWO_PI, s0 + stroke, s0)]
    return MotionProgram(build_segments(specs))


@pytest.mark.parametrize('name', REST_TO_REST)
def test_gg_superposition_is_the_closed_form(name):
    law = rest_to_rest(name)
    program = gg_program(law)
    x = np.linspace(0.0, GG_SPAN, 1001)
    values = program.evaluate(GG_START + x[:-1])  # the next segment owns the joint
    values = [np.append(getattr(values, name), float(value)) for name, value in
              zip(('s', 'ds', 'd2s', 'd3s'), segment_values(program.segments[0], 1.0))]
    g = law.evaluate(np.clip(x / GG_SPAN, 0.0, 1.0))
    rest = GG_STROKE - GG_VELOCITY * GG_SPAN
    closed = [GG_POSITION + GG_VELOCITY * x + rest * g.y,
              GG_VELOCITY + rest * g.y1 / GG_SPAN, rest * g.y2 / GG_SPAN ** 2,
              rest * g.y3 / GG_SPAN ** 3]
    size = travel(GG_SPAN, GG_STROKE, (GG_VELOCITY,))
    for k, name_k in enumerate(('s', 'ds', 'd2s', 'd3s')):
        got = values[k]
        if k >= 2:  # d2s, d3s of a piecewise law may be one-sided at a breakpoint: skip those
            inside = np.all(np.abs(x[:, None] / GG_SPAN - np.array([*law.breakpoints, -9.0]))
                            > 1e-9, axis=1)
            got, want = got[inside], closed[k][inside]
        else:
            want = closed[k]
        assert_close(got, want, size / GG_SPAN ** k * max(1.0, law.cj if k == 3 else 1.0),
                     what=f'{name} {name_k}')
    assert program.segment_summary()[0].task == 'G-G'


@pytest.mark.parametrize('name', REST_TO_REST)
def test_gg_peaks_follow_cv_and_ca(name):
    law = rest_to_rest(name)
    cv, ca = law_peaks(law)
    summary = gg_program(law).segment_summary()[0]
    assert (summary.cv, summary.ca) == (pytest.approx(cv, rel=PEAK_RTOL),
                                        pytest.approx(ca, rel=PEAK_RTOL))
    rest = GG_STROKE - GG_VELOCITY * GG_SPAN
    assert summary.peak_d2s == pytest.approx(ca * abs(rest) / GG_SPAN ** 2, rel=PEAK_RTOL)
    slope = law.evaluate(np.linspace(0.0, 1.0, REFERENCE_SAMPLES)).y1
    if slope.min() >= 0.0:  # y' = v + (H/X - v) g' peaks where g' does
        expected = GG_VELOCITY + cv * (GG_STROKE / GG_SPAN - GG_VELOCITY)
    else:  # the law runs backwards somewhere: the larger of its two extremes
        expected = peak(lambda u: GG_VELOCITY + rest / GG_SPAN * law.evaluate(u).y1)
    assert summary.peak_ds == pytest.approx(expected, rel=PEAK_RTOL)


@pytest.mark.parametrize('name, cv, ca', [
    ('cycloidal', 2.0, TWO_PI), ('simple_harmonic', PI / 2, PI ** 2 / 2),
    ('polynomial_345', 1.875, 10 / math.sqrt(3)), ('constant_acceleration', 2.0, 4.0),
    ('polynomial_4567', 35 / 16, 84 * math.sqrt(5) / 25),
])
def test_gg_peaks_with_published_coefficients(name, cv, ca):
    """The same peaks with Cv, Ca in closed form (4-5-6-7: y'' = 420 u^2 (1-u)^2 (1-2u)...)."""
    law = rest_to_rest(name)
    span, stroke, v = 0.9, -0.02, -0.005  # a fall, faster than its G ends
    summary = gg_program(law, span, stroke, v).segment_summary()[0]
    assert summary.peak_ds == pytest.approx(abs(v + cv * (stroke / span - v)), rel=PEAK_RTOL)
    assert summary.peak_d2s == pytest.approx(ca * abs(stroke - v * span) / span ** 2,
                                             rel=PEAK_RTOL)


def test_gg_slower_than_its_ends_dips_by_cv():
    """H/X < v: the law takes speed away; the peak is v at the ends, the dip v - Cv (v - H/X)."""
    span, stroke, v = 1.0, 0.01, 0.02
    program = gg_program(Cycloidal(), span, stroke, v)
    summary = program.segment_summary()[0]
    assert summary.peak_ds == pytest.approx(v, rel=PEAK_RTOL)
    ds = program.evaluate(GG_START + np.linspace(0.0, span, 20001)).ds
    assert ds.min() == pytest.approx(v - 2.0 * (v - stroke / span), rel=1e-6)
    assert summary.overshoot == 0.0


# 4. Finite differences of task segments ----------------------------------------------------

def fd_programs():
    """Programs of task segments: ramp (G-G), poly5 B-B, poly7, an inflected law with a ramp."""
    v = 0.012
    ramp = gg_program(make_law('modified_sine'))
    inflected_ramp = gg_program(Cycloidal(), inflection=0.3)
    poly = MotionProgram(build_segments([
        TaskSpec('poly5', 0.0, 2.0, 0.0, 0.03, (NAN, NAN, NAN), (v, -0.004, NAN)),
        TaskSpec('poly7', 2.0, 4.0, 0.03, 0.04, (NAN, NAN, 0.002), (0.0, 0.0, 0.0)),
        TaskSpec(Dwell(), 4.0, 4.5, 0.04, 0.04),
        TaskSpec(make_law('polynomial_4567'), 4.5, TWO_PI, 0.04, 0.0, inflection=0.7)]))
    return {'ramp': ramp, 'inflected_ramp': inflected_ramp, 'poly': poly}


@pytest.mark.parametrize('which', ['ramp', 'inflected_ramp', 'poly'])
def test_task_derivatives_match_finite_differences(which):
    program = fd_programs()[which]
    theta = program.start + np.linspace(0.0, TWO_PI, 4001)[1:-1]
    breaks = np.asarray(program.breaks)
    far = np.min(np.abs((theta[:, None] - breaks[None, :] + PI) % TWO_PI - PI), axis=1) > 1e-3
    theta = theta[far]
    values = program.evaluate(theta)
    series = (values.s, values.ds, values.d2s, values.d3s)
    for k in (1, 2, 3):
        h = FD_STEP[k]
        above, below = program.evaluate(theta + h), program.evaluate(theta - h)
        lower = ('s', 'ds', 'd2s')[k - 1]
        difference = (getattr(above, lower) - getattr(below, lower)) / (2 * h)
        size = max(float(np.max(np.abs(series[k]))), float(np.max(np.abs(series[k - 1]))))
        assert_close(difference, series[k], size, FD_RTOL[k], f'{which} d{k}s')


# 5. Inflection ---------------------------------------------------------------------------

def inflection_reference(law, lam, z):
    """Return f, f', f'', f''' at z by the construction, from g = law.evaluate."""
    z = np.asarray(z, dtype=float)
    left = z <= lam
    w = np.where(left, z / (2 * lam), 0.5 + (z - lam) / (2 * (1 - lam)))
    g = law.evaluate(np.clip(w, 0.0, 1.0))
    scale = np.where(left, 2 * lam, 2 * (1 - lam))
    f = np.where(left, 2 * lam * g.y, 1 - 2 * (1 - lam) * (1 - g.y))
    return f, g.y1, g.y2 / scale, g.y3 / scale ** 2


@pytest.mark.parametrize('name', SYMMETRIC)
def test_inflected_law_is_the_construction(name):
    law = symmetric(name)
    for lam in INFLECTIONS:
        shaped = inflected(law, lam)
        assert isinstance(shaped, InflectedLaw)
        assert shaped.name == law.name
        # u = lambda itself belongs to one side only: test_value_at_the_inflection_... checks it
        z = np.linspace(0.0, 1.0, 2001)
        z = z[np.abs(z - lam) > 1e-12]
        got = shaped.evaluate(z)
        for k, want in enumerate(inflection_reference(law, lam, z)):
            assert_close(got[k], want, max(1.0, float(np.max(np.abs(want)))),
                         what=f'{name} lambda {lam} y^({k})')
        assert float(shaped.evaluate(lam).y) == pytest.approx(lam, abs=EXACT_RTOL)
        assert lam in shaped.breakpoints


@pytest.mark.parametrize('name', SYMMETRIC)
def test_inflection_keeps_s_and_velocity_continuous(name):
    law = symmetric(name)
    for lam in INFLECTIONS:
        shaped = inflected(law, lam)
        below = shaped.evaluate(np.nextafter(lam, -np.inf))
        above = shaped.evaluate(np.nextafter(lam, np.inf))
        orders = (0, 1) if name == 'constant_acceleration' else (0, 1, 2)
        for k in orders:
            size = max(1.0, abs(float(below[k])))
            assert abs(float(above[k]) - float(below[k])) <= LIMIT_RTOL * size, (name, lam, k)
        if name == 'constant_acceleration':  # g'' = +4, -4: each side keeps its own value
            assert float(below.y2) == pytest.approx(4.0 / (2 * lam))
            assert float(above.y2) == pytest.approx(-4.0 / (2 * (1 - lam)))


@pytest.mark.parametrize('name', ['constant_acceleration', 'cycloidal', 'modified_sine'])
def test_value_at_the_inflection_is_the_decelerating_sides(name):
    """At a breakpoint a law gives its next piece's value (piece_grid, continuity_report and
    the base laws: constant acceleration's y''(1/2) = -4): at lambda the decelerating side's."""
    law = symmetric(name)
    for lam in INFLECTIONS:
        shaped = inflected(law, lam)
        at = shaped.evaluate(lam)
        above = shaped.evaluate(np.nextafter(lam, np.inf))
        for k in (2, 3):
            size = max(1.0, abs(float(above[k])))
            assert abs(float(at[k]) - float(above[k])) <= LIMIT_RTOL * size, (name, lam, k)


@pytest.mark.parametrize('name', SYMMETRIC)
def test_inflection_peaks_per_side(name):
    law = symmetric(name)
    cv, ca = law_peaks(law)
    for lam in (0.2, 0.5, 0.7):
        shaped = inflected(law, lam)
        edges = sorted({0.0, lam, *shaped.breakpoints, 1.0})
        pieces = list(zip(edges[:-1], edges[1:]))

        def side_peak(order, low_side, high_side):
            """Peak |y^(order)| over the open pieces inside [low_side, high_side]."""
            return max(peak(lambda u: shaped.evaluate(np.clip(u, 0.0, 1.0))[order],
                            np.nextafter(a, np.inf), np.nextafter(b, -np.inf))
                       for a, b in pieces if a >= low_side and b <= high_side)

        side_peaks = [side_peak(2, 0.0, lam), side_peak(2, lam, 1.0)]
        assert side_peaks[0] == pytest.approx(ca / (2 * lam), rel=PEAK_RTOL), (name, lam)
        assert side_peaks[1] == pytest.approx(ca / (2 * (1 - lam)), rel=PEAK_RTOL), (name, lam)
        velocity = side_peak(1, 0.0, 1.0)
        assert velocity == pytest.approx(cv, rel=PEAK_RTOL)
        assert shaped.cv == pytest.approx(cv, rel=PEAK_RTOL)
        assert shaped.ca == pytest.approx(max(side_peaks), rel=PEAK_RTOL)


def test_inflected_segment_summary_and_jerk_jump():
    """An inflected cycloidal rise: its summary, and d3s jumps at the inflection only."""
    lam, span, stroke = 0.3, deg(120.0), 0.02
    program = MotionProgram(build_segments([
        TaskSpec(Cycloidal(), 0.0, span, 0.0, stroke, inflection=lam),
        TaskSpec(Dwell(), span, deg(180.0), stroke, stroke),
        TaskSpec(Cycloidal(), deg(180.0), TWO_PI, stroke, 0.0)]))
    summary = program.segment_summary()[0]
    assert summary.inflection == lam
    assert summary.task == 'R-R'
    assert summary.peak_ds == pytest.approx(stroke * 2.0 / span, rel=PEAK_RTOL)
    assert summary.peak_d2s == pytest.approx(stroke * TWO_PI / (2 * lam) / span ** 2,
                                             rel=PEAK_RTOL)
    inside = [jump for jump in program.continuity_report()
              if 0.0 < jump.angle < span and jump.order <= 3]
    assert [(jump.order, jump.angle) for jump in inside] == [(3, pytest.approx(lam * span))]
    # g''' (1/2) = 4 pi^2 cos(pi) = -4 pi^2, over the side's (2 lambda)^2 or (2 (1 - lambda))^2
    g3 = -4 * PI ** 2 * stroke / span ** 3
    assert inside[0].left == pytest.approx(g3 / (2 * lam) ** 2, rel=1e-9)
    assert inside[0].right == pytest.approx(g3 / (2 * (1 - lam)) ** 2, rel=1e-9)
    assert program.segment_summary()[2].inflection == 0.5


def test_half_inflection_is_the_law_itself():
    law = Cycloidal()
    assert inflected(law, 0.5) is law


@pytest.mark.parametrize('lam', [0.0, 1.0, -0.2, 1.3, NAN])
def test_inflection_outside_0_1_is_refused(lam):
    with pytest.raises(InvalidParameter) as caught:
        inflected(Cycloidal(), lam)
    assert caught.value.parameter == 'inflection'
    with pytest.raises(InvalidParameter) as caught:
        build_segments([TaskSpec(Cycloidal(), 0.0, PI, 0.0, 0.01, inflection=lam),
                        TaskSpec(Cycloidal(), PI, TWO_PI, 0.01, 0.0)])
    assert caught.value.parameter == 'segments[0].inflection'


@pytest.mark.parametrize('name, params', [
    ('table', {'u': [0.0, 0.25, 0.5, 0.8, 1.0], 'y': [0.0, 0.1, 0.45, 0.9, 1.0]}),
    ('via_point', {'u_via': 0.4, 'y_via': 0.5}),
    ('dwell', {}),
])
def test_inflection_of_an_asymmetric_law_is_refused(name, params):
    law = make_law(name, **params)
    with pytest.raises(InvalidParameter) as caught:
        inflected(law, 0.3)
    assert caught.value.parameter == 'inflection'
    assert name in str(caught.value) and 'symmetric' in str(caught.value)
    with pytest.raises(InvalidParameter) as caught:
        build_segments([TaskSpec(Cycloidal(), 0.0, PI, 0.0, 0.01),
                        TaskSpec(law, PI, TWO_PI, 0.01, 0.01 if name == 'dwell' else 0.02,
                                 inflection=0.3),
                        ])
    assert caught.value.parameter == 'segments[1].inflection'


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


# 7. Refusals --------------------------------------------------------------------------------

def refusal(specs):
    with pytest.raises(InvalidParameter) as caught:
        MotionProgram(build_segments(specs))
    return caught.value


def test_unequal_velocities_on_a_rest_to_rest_law_are_refused():
    err = refusal([TaskSpec(Cycloidal(), 0.0, PI, 0.0, 0.02, (0.004, NAN, NAN),
                            (0.006, NAN, NAN)),
                   TaskSpec('poly5', PI, TWO_PI, 0.02, 0.0)])
    assert err.parameter == 'segments[0].end_velocity'
    assert 'poly5' in str(err) and 'poly7' in str(err)


def test_automatic_end_of_a_rest_to_rest_law_is_rest():
    """A given start velocity with an automatic end: the end is at rest, so they differ."""
    err = refusal([TaskSpec(Cycloidal(), 0.0, PI, 0.0, 0.02, (0.004, NAN, NAN)),
                   TaskSpec('poly5', PI, TWO_PI, 0.02, 0.0)])
    assert err.parameter == 'segments[0].end_velocity'


@pytest.mark.parametrize('begin, finish, field', [
    ((NAN, NAN, NAN), (NAN, 0.3, NAN), 'end_acceleration'),
    ((NAN, -0.1, NAN), (NAN, NAN, NAN), 'start_acceleration'),
    ((NAN, NAN, 1.0), (NAN, NAN, NAN), 'start_jerk'),
    ((0.001, NAN, NAN), (0.001, 0.5, NAN), 'end_acceleration'),
])
def test_given_value_the_law_does_not_have_is_refused(begin, finish, field):
    err = refusal([TaskSpec(Cycloidal(), 0.0, PI, 0.0, 0.02, begin, finish),
                   TaskSpec('poly7', PI, TWO_PI, 0.02, 0.0)])
    assert err.parameter == f'segments[0].{field}'
    assert 'poly5' in str(err) and 'poly7' in str(err)


def test_given_value_the_law_has_is_accepted():
    """Cycloidal: d2s = 0 at both ends, d3s = 4 pi^2 H / X^3 at the start."""
    span, stroke = PI, 0.02
    jerk = 4 * PI ** 2 * stroke / span ** 3
    segments = build_segments([
        TaskSpec(Cycloidal(), 0.0, span, 0.0, stroke, (0.0, 0.0, jerk), (0.0, 0.0, jerk)),
        TaskSpec('poly7', span, TWO_PI, stroke, 0.0)])
    assert float(segment_values(segments[1], 0.0).y3) == pytest.approx(jerk, rel=EXACT_RTOL)


def test_poly5_with_a_jerk_is_refused():
    err = refusal([TaskSpec('poly5', 0.0, PI, 0.0, 0.02, (0.0, 0.0, 0.5), (0.0, 0.0, NAN)),
                   TaskSpec(Cycloidal(), PI, TWO_PI, 0.02, 0.0)])
    assert err.parameter == 'segments[0].start_jerk'
    assert 'poly7' in str(err)


def test_adjacent_automatic_boundary_ends_are_refused_naming_both():
    err = refusal([TaskSpec(Cycloidal(), 0.0, 2.0, 0.0, 0.02),
                   TaskSpec('poly5', 2.0, 4.0, 0.02, 0.03, (NAN, NAN, NAN), (NAN, 0.0, NAN)),
                   TaskSpec('poly5', 4.0, TWO_PI, 0.03, 0.0)])
    assert err.parameter == 'segments[1].end_velocity'
    assert 'segments[2].start_velocity' in str(err)


def test_boundary_law_inherits_a_given_value_of_its_boundary_neighbour():
    segments = build_segments([
        TaskSpec(Cycloidal(), 0.0, 2.0, 0.0, 0.02),
        TaskSpec('poly5', 2.0, 4.0, 0.02, 0.03, (NAN, NAN, NAN), (NAN, 0.001, NAN)),
        TaskSpec('poly5', 4.0, TWO_PI, 0.03, 0.0, (0.004, NAN, NAN), (NAN, NAN, NAN))])
    joint = segment_values(segments[1], 1.0), segment_values(segments[2], 0.0)
    for values in joint:
        assert float(values.y1) == pytest.approx(0.004, rel=EXACT_RTOL)
        assert float(values.y2) == pytest.approx(0.001, rel=EXACT_RTOL)


def test_reversal_behind_the_start_is_refused():
    """G-U: moving up at the start, stopping at its end, but the end lies below the start."""
    err = refusal([TaskSpec('poly5', 0.0, 1.0, 0.0, -0.005, (0.01, 0.0, NAN), (0.0, -0.02, NAN)),
                   TaskSpec('poly5', 1.0, TWO_PI, -0.005, 0.0, (0.0, -0.02, NAN),
                            (0.01, 0.0, NAN))])
    assert err.parameter == 'segments[0].s_end'
    assert 'G-U' in str(err) and 'behind' in str(err)


def test_inflection_of_a_boundary_law_is_refused():
    err = refusal([TaskSpec('poly5', 0.0, PI, 0.0, 0.02, inflection=0.3),
                   TaskSpec(Cycloidal(), PI, TWO_PI, 0.02, 0.0)])
    assert err.parameter == 'segments[0].inflection'


def test_moving_dwell_is_refused():
    err = refusal([TaskSpec(Dwell(), 0.0, PI, 0.0, 0.0, (0.01, NAN, NAN), (0.01, NAN, NAN)),
                   TaskSpec(Cycloidal(), PI, TWO_PI, 0.0, 0.0)])
    assert err.parameter == 'segments[0].start_velocity'


# 8. Forced overshoot -------------------------------------------------------------------------

def flying(stroke_rg, v=0.01, span=1.0, sync=1.0):
    """R-G poly5, G-G constant velocity v, G-R poly5 with H = v X / 2, a cycloidal return."""
    s1 = stroke_rg
    s2 = s1 + v * sync
    s3 = s2 + v * span / 2
    a, b, c = span, span + sync, 2 * span + sync
    return MotionProgram(build_segments([
        TaskSpec('poly5', 0.0, a, 0.0, s1), TaskSpec(ConstantVelocity(), a, b, s1, s2),
        TaskSpec('poly5', b, c, s2, s3), TaskSpec(Cycloidal(), c, TWO_PI, s3, 0.0)]))


def test_r_g_with_mean_slope_equal_to_the_end_velocity_overshoots():
    v, span = 0.01, 1.0
    program = flying(v * span, v, span)
    summary = program.segment_summary()
    assert [item.task for item in summary] == ['R-G', 'G-G', 'G-R', 'R-R']
    segment = program.segments[0]
    grid = np.linspace(0.0, 1.0, REFERENCE_SAMPLES)
    ds = segment_values(segment, grid).y1
    best = int(np.argmax(ds))
    refined = minimize_scalar(lambda u: -float(segment_values(segment, u).y1),
                              bounds=(grid[best - 1], grid[best + 1]), method='bounded',
                              options={'xatol': REFINE_XATOL})
    assert refined.x == pytest.approx(0.6, abs=1e-6)
    assert -refined.fun == pytest.approx(1.512 * v, rel=1e-12)
    assert summary[0].overshoot == pytest.approx(-refined.fun - v, rel=PEAK_RTOL)
    assert summary[0].overshoot == pytest.approx(0.512 * v, rel=PEAK_RTOL)
    assert summary[0].peak_ds == pytest.approx(1.512 * v, rel=PEAK_RTOL)
    assert summary[1].overshoot == 0.0 and summary[2].overshoot == 0.0


def test_r_g_with_half_the_mean_slope_does_not_overshoot():
    v, span = 0.01, 1.0
    program = flying(v * span / 2, v, span)
    summary = program.segment_summary()
    assert [item.overshoot for item in summary] == [0.0, 0.0, 0.0, 0.0]
    assert summary[0].peak_ds == pytest.approx(v, rel=PEAK_RTOL)


def test_falling_r_g_overshoot_counts_in_the_fall_direction():
    """The mirror image: a fall to -v with H = -v X passes -v by 0.512 v."""
    v, span = -0.01, 1.0
    program = MotionProgram(build_segments([
        TaskSpec('poly5', 0.0, span, 0.0, v * span, (NAN, NAN, NAN), (v, 0.0, NAN)),
        TaskSpec('poly5', span, TWO_PI, v * span, 0.0, (NAN, NAN, NAN), (0.0, 0.0, NAN))]))
    summary = program.segment_summary()[0]
    assert summary.task == 'R-G'
    assert summary.overshoot == pytest.approx(0.512 * abs(v), rel=PEAK_RTOL)


def test_gg_law_faster_than_its_ends_overshoots_by_cv():
    """G-G cycloidal with H/X > v: ds peaks at v + 2 (H/X - v), which passes v."""
    summary = gg_program(Cycloidal()).segment_summary()[0]
    mean = GG_STROKE / GG_SPAN
    assert summary.overshoot == pytest.approx(2.0 * (mean - GG_VELOCITY), rel=PEAK_RTOL)


def test_monotonic_speed_change_does_not_overshoot():
    """G-G from 2v to v with H = 1.5 v X and no end acceleration: ds = 2v - v (3z^2 - 2z^3)
    falls monotonically from 2v to v, so peak |ds| equals the larger end |ds|: no overshoot.
    (SegmentSummary: 'How far peak |ds| exceeds the larger end |ds| of a task that starts or
    ends moving'.)"""
    v, span = 0.01, 1.0
    program = MotionProgram(build_segments([
        TaskSpec('poly5', 0.0, span, 0.0, 1.5 * v * span, (2 * v, 0.0, NAN), (v, 0.0, NAN)),
        TaskSpec('poly5', span, TWO_PI, 1.5 * v * span, 0.0, (NAN, NAN, NAN),
                 (2 * v, 0.0, NAN))]))
    summary = program.segment_summary()[0]
    u = np.linspace(0.0, 1.0, 1001)
    ds = segment_values(program.segments[0], u).y1
    assert ds == pytest.approx(2 * v - v * (3 * u ** 2 - 2 * u ** 3), rel=1e-12)
    assert summary.task == 'G-G'
    assert summary.peak_ds == pytest.approx(2 * v, rel=PEAK_RTOL)
    assert summary.overshoot == 0.0


# 9. Programs that advance ---------------------------------------------------------------------

def rotary_knife(advance=TWO_PI, s_first=0.0):
    """A rotary slave: 1.2 per rad synchronous for 60 deg, a 4-5-6-7 G-G recovery, one turn
    per cycle."""
    ratio = 1.2
    sync = deg(60.0)
    s1 = s_first + ratio * sync
    return [Segment(ConstantVelocity(), deg(-30.0), deg(30.0), s_first, s1),
            Segment(Polynomial4567(), deg(30.0), deg(330.0), s1, s_first + advance, ramp=ratio)]


def test_program_advances_by_whole_cycles():
    program = MotionProgram(rotary_knife(), advance=TWO_PI)
    theta = np.linspace(deg(-30.0), deg(330.0), 721)[:-1]
    base = program.evaluate(theta)
    for n in range(-3, 4):
        shifted = program.evaluate(theta + TWO_PI * n)
        assert shifted.s == pytest.approx(base.s + n * TWO_PI, rel=1e-12, abs=1e-11)
        for name in ('ds', 'd2s', 'd3s'):
            assert getattr(shifted, name) == pytest.approx(getattr(base, name), rel=1e-9,
                                                           abs=1e-9)
    scattered = np.array([7.0, -4.0, 0.1, 20.0, -13.5])
    assert program.evaluate(scattered).s == pytest.approx(
        [float(program.evaluate(x).s) for x in scattered], rel=1e-12)


def test_advancing_program_has_a_smooth_wrap():
    program = MotionProgram(rotary_knife(), advance=TWO_PI)
    assert program.continuity_report() == ()
    assert [item.task for item in program.segment_summary()] == ['G-G', 'G-G']
    below = program.evaluate(deg(-30.0) - 1e-9)
    above = program.evaluate(deg(-30.0))
    assert float(above.s - below.s) == pytest.approx(1.2e-9, rel=1e-3)


def test_advance_must_match_the_wrap():
    with pytest.raises(InvalidParameter) as caught:
        MotionProgram(rotary_knife(), advance=0.0)
    assert caught.value.parameter == 'segments[0].s_start'
    with pytest.raises(InvalidParameter) as caught:
        MotionProgram(rotary_knife(advance=TWO_PI), advance=PI)
    assert caught.value.parameter == 'segments[0].s_start'
    assert 'advance' in str(caught.value)


def test_advance_must_be_finite():
    with pytest.raises(InvalidParameter) as caught:
        MotionProgram(rotary_knife(), advance=math.inf)
    assert caught.value.parameter == 'advance'
