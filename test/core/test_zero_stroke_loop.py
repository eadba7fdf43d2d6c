"""A U-U segment of zero stroke (a loop out and back), against its closed form.

Reference written here: a quintic through (0, 0, a0) and (0, 0, a1) over a span X is
s = X^2/2 z^2 (1 - z)^2 (a0 + (a1 - a0) z) (z = x / X; it has the six end values), so for
a0 = a1 = a: ds/dtheta = a X z (1 - z)(1 - 2 z), extremes +-a X / (6 sqrt 3) at
z = 1/2 -+ 1/sqrt 12, the far point a X^2 / 32 at z = 1/2, Cv = 16 / (3 sqrt 3) and Ca = 32
(docs/motion.md's Cv of a loop: of s over its largest excursion). With a0 a1 > 0 the last factor
keeps its sign, s stays on one side and turns once; with a0 a1 < 0 it changes sign inside, so
s crosses its start and turns twice: refused. The config case (U-U over 90 deg, 0.01 mm/deg^2 at
both ends) peaks at +-0.0866025 mm/deg.
"""

import math

import numpy as np
import pytest

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import Cycloidal
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import summarize
from cam_ros.core.motion.tasks import build_segments, TaskSpec

NAN = math.nan
DEGREE = math.pi / 180.0
SPAN = 90.0 * DEGREE
#: 0.01 mm/deg^2 in m/rad^2.
LOOP_ACCELERATION = 0.01e-3 / DEGREE ** 2
DENSE = np.linspace(0.0, 1.0, 100_001)


def loop_program(a0, a1, stroke=0.0):
    """A U-U poly5 over 0-90 deg from 0 to stroke, a poly5 on to 20 mm the way the loop's end
    acceleration points (U-R), and a cycloidal return."""
    level = math.copysign(0.02, a1)
    return MotionProgram(build_segments([
        TaskSpec('poly5', 0.0, SPAN, 0.0, stroke, (0.0, a0, NAN), (0.0, a1, NAN)),
        TaskSpec('poly5', SPAN, 200 * DEGREE, stroke, level, (NAN, NAN, NAN), (0.0, 0.0, NAN)),
        TaskSpec(Cycloidal(), 200 * DEGREE, 2 * math.pi, level, 0.0)]))


def closed_form(a0, a1, z):
    return SPAN ** 2 / 2 * z ** 2 * (1 - z) ** 2 * (a0 + (a1 - a0) * z)


def test_a_loop_with_equal_end_accelerations_is_its_closed_form():
    a = LOOP_ACCELERATION
    program = loop_program(a, a)
    values = program.evaluate(DENSE * SPAN)
    np.testing.assert_allclose(values.s, closed_form(a, a, DENSE), rtol=0, atol=1e-15)
    np.testing.assert_allclose(values.ds, a * SPAN * DENSE * (1 - DENSE) * (1 - 2 * DENSE),
                               rtol=0, atol=1e-15)
    summary = summarize(0, program.segments[0])
    assert summary.task == 'U-U'
    peak = a * SPAN / (6 * math.sqrt(3))
    assert summary.peak_ds == pytest.approx(peak, rel=1e-9)
    assert peak * 1e3 * DEGREE == pytest.approx(0.0866025, abs=5e-8)  # mm/deg
    assert summary.cv == pytest.approx(16 / (3 * math.sqrt(3)), rel=1e-9)
    assert summary.ca == pytest.approx(32.0, rel=1e-9)
    assert values.s.max() == pytest.approx(a * SPAN ** 2 / 32, rel=1e-12)


@pytest.mark.parametrize('a0, a1', [(1.0, 0.3), (0.2, 1.0), (-1.0, -0.5), (1.0, 1e-3),
                                    (0.0, 1.0), (-1.0, 0.0)])
def test_a_loop_whose_ends_lie_on_one_side_is_accepted(a0, a1):
    a0, a1 = a0 * LOOP_ACCELERATION, a1 * LOOP_ACCELERATION
    program = loop_program(a0, a1)
    np.testing.assert_allclose(program.evaluate(DENSE * SPAN).s, closed_form(a0, a1, DENSE),
                               rtol=0, atol=1e-15)


@pytest.mark.parametrize('a0, a1', [(1.0, -1.0), (-0.3, 1.0), (1.0, -0.01)])
def test_a_loop_that_crosses_its_start_is_refused(a0, a1):
    a0, a1 = a0 * LOOP_ACCELERATION, a1 * LOOP_ACCELERATION
    s = closed_form(a0, a1, DENSE[1:-1])
    assert s.max() > 0 > s.min()  # the closed form crosses its start: two turns inside
    with pytest.raises(InvalidParameter) as caught:
        loop_program(a0, a1)
    assert caught.value.parameter == 'segments[0].end_acceleration'
    assert 'zero stroke is a loop' in caught.value.rule and 'of one sign' in caught.value.rule


def test_a_reversal_behind_the_start_states_the_true_velocity_range():
    # A U-U of stroke h with 0.01 mm/deg^2 at both ends: the quintic with the six end values is
    # closed_form + h (10 z^3 - 15 z^4 + 6 z^5); its ds/dtheta extremes from the roots of d2s.
    a, stroke = LOOP_ACCELERATION, -1e-3
    with pytest.raises(InvalidParameter) as caught:
        loop_program(a, a, stroke)
    quintic = np.polynomial.Polynomial(
        [0, 0, SPAN ** 2 * a / 2, 10 * stroke - SPAN ** 2 * a, -15 * stroke + SPAN ** 2 * a / 2,
         6 * stroke])
    slope = quintic.deriv()
    z = np.concatenate(([0, 1], [r.real for r in slope.deriv().roots()
                                 if abs(r.imag) < 1e-12 and 0 < r.real < 1]))
    low, high = slope(z).min() / SPAN, slope(z).max() / SPAN
    assert low < 0 < high
    np.testing.assert_allclose(np.polynomial.Polynomial(quintic.coef)(DENSE), closed_form(
        a, a, DENSE) + stroke * (10 * DENSE ** 3 - 15 * DENSE ** 4 + 6 * DENSE ** 5), atol=1e-15)
    rule = caught.value.rule
    assert caught.value.parameter == 'segments[0].s_end'
    assert f'from {low:.6g} per rad^1 to {high:.6g} per rad^1' in rule
