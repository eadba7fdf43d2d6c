"""Tests of the VDI 2143 motion tasks of rest-to-rest laws: the G-G superposition of every
registered law, finite differences of task segments, and the inflection.

References, all written here (shared ones in motion_task_references) and independent of the code
under test:
* G-G: s = s0 + v x + (H - v X) g(x / X) from the law's own `evaluate` (g), with
  y'max = v + Cv (H/X - v) and |y''|max = Ca |H - v X| / X^2, Cv and Ca found on a dense grid
  of g', g'' with a bounded refinement (scipy), or their published closed forms.
* Inflection: f(z) = 2 lambda g(z / (2 lambda)) for z <= lambda, else
  1 - 2 (1 - lambda) (1 - g(1/2 + (z - lambda) / (2 (1 - lambda)))), its derivatives by the chain
  rule; peaks Ca / (2 lambda) and Ca / (2 (1 - lambda)) per side, Cv overall.
* Central finite differences of s over the cam angle.
"""

import math

import numpy as np
import pytest

from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.inflection import inflected, InflectedLaw
from cam_ros.core.motion.laws import Cycloidal, Dwell, LAWS, make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import segment_values
from cam_ros.core.motion.tasks import build_segments, TaskSpec
from motion_task_references import (assert_close, deg, EXACT_RTOL, FD_RTOL, FD_STEP, GG_POSITION,
                                    gg_program, GG_SPAN, GG_START, GG_STROKE, GG_VELOCITY,
                                    INFLECTIONS, law_peaks, LIMIT_RTOL, NAN, NOT_REST_TO_REST,
                                    peak, PEAK_RTOL, PI, REFERENCE_SAMPLES, REST_TO_REST,
                                    rest_to_rest, SYMMETRIC, symmetric, travel, TWO_PI)


# 3. G-G superposition of every rest-to-rest law ------------------------------------------------

def test_every_registered_law_is_classified():
    assert set(REST_TO_REST) | NOT_REST_TO_REST == set(LAWS)


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
