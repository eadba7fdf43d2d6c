"""Shared references, constants and the G-G program of the motion task tests.

Used by test_boundary_polynomials, test_motion_tasks and test_task_refusals. The references are
written here and independent of the code under test:
* polynomial_system: the 6x6 / 8x8 system of a boundary polynomial's end conditions in u
  (d^k/du^k u^p = p!/(p-k)! u^(p-k)), solved by numpy.linalg.solve.
* peak, law_peaks: max |f| on a dense grid with a bounded refinement (scipy); a rest-to-rest
  law's Cv and Ca from its own g', g'' (each piece searched apart).
* travel, assert_close: the natural size of a segment's motion, and agreement relative to it.
* The tolerances, and the rest-to-rest and symmetric laws (with parameters) the tests run over.
gg_program builds a G-G segment of a law at velocity v and a poly5 back to the start.
"""

import math

import numpy as np
from scipy.optimize import minimize_scalar

from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.tasks import build_segments, TaskSpec
from test_laws import LAW_PARAMS

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

#: Registered laws that are not rest-to-rest rises (or are built from end values, not a shape).
NOT_REST_TO_REST = {'dwell', 'constant_velocity', 'poly5', 'poly7'}
#: Every registered law the G-G superposition serves (rest-to-rest rises), with the parameters
#: test_laws.py builds it from.
REST_TO_REST = {name: params for name, params in LAW_PARAMS.items()
                if name not in NOT_REST_TO_REST}
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


# The G-G program of the superposition, task-name and overshoot tests -------------------------

GG_SPAN, GG_STROKE, GG_VELOCITY = 1.2, 0.03, 0.01  # H/X = 0.025 > v: the law adds speed
GG_START, GG_POSITION = 0.3, 0.004


def gg_program(law, span=GG_SPAN, stroke=GG_STROKE, v=GG_VELOCITY, inflection=0.5):
    """A G-G segment of law at velocity v, then a poly5 back to the start at that velocity."""
    start, s0 = GG_START, GG_POSITION
    specs = [TaskSpec(law, start, start + span, s0, s0 + stroke, (v, NAN, NAN), (v, NAN, NAN),
                      inflection),
             TaskSpec('poly5', start + span, start + TWO_PI, s0 + stroke, s0)]
    return MotionProgram(build_segments(specs))
