"""Tests of the motion tasks a program refuses, forced velocity overshoot and programs that
advance.

References, all written here (shared ones in motion_task_references) and independent of the code
under test:
* Refusals: the field each InvalidParameter names and what its message offers (poly5/poly7).
* Forced overshoot of an R-G quintic with H = v X: ds = v (18 z^2 - 32 z^3 + 15 z^4) peaks at
  z = 3/5 with 1.512 v, so it passes v by 0.512 v; with H = v X / 2, ds = v (3 z^2 - 2 z^3) stays
  below v. A G-G cycloidal with H/X > v peaks at v + 2 (H/X - v).
* Advance: s(theta + 2 pi n) = s(theta) + 2 pi n with unchanged derivatives.
"""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import ConstantVelocity, Cycloidal, Dwell, Polynomial4567
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment, segment_values
from cam_ros.core.motion.tasks import build_segments, TaskSpec
from motion_task_references import (deg, EXACT_RTOL, gg_program, GG_SPAN, GG_STROKE, GG_VELOCITY,
                                    NAN, PEAK_RTOL, PI, REFERENCE_SAMPLES, REFINE_XATOL, TWO_PI)


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
