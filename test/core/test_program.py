"""Tests of motion programs against the seeds' tables and worked examples, and their rules."""

import math
import sys

import numpy as np
import pytest

from cam_ros.core.arrays import BLOCK
from cam_ros.core.errors import InvalidParameter
from cam_ros.core.motion.laws import (ConstantAcceleration, ConstantVelocity, Cycloidal, Dwell,
                                      make_law, Polynomial4567, SimpleHarmonic, ViaPointLaw)
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

PI = math.pi
deg = math.radians
#: Agreement of two exact computations (SI values of order 1e-2..1e3).
EXACT_RTOL = 1e-9
#: Half a unit in the last printed digit of seed 000's table (3 decimals).
TABLE_ATOL = 5e-4 + 1e-12


def program(*rows):
    """Build a program from rows (law, start_deg, end_deg, s_start, s_end)."""
    return MotionProgram([Segment(law, deg(start), deg(end), s0, s1)
                          for law, start, end, s0, s1 in rows])


def approx(expected, rel=EXACT_RTOL, abs=1e-12):  # noqa: A002 - mirrors pytest.approx
    """Compare arrays with the file's default tolerances."""
    return pytest.approx(expected, rel=rel, abs=abs)


# Seed 001 (Tables 9.1-9.4): rise and fall formulas with offsets H0 and HF --------------------

H0, HI = 0.010, 0.030  # rise from H0 by Hi (m)
HJ = 0.025  # fall by Hj ...
HF = H0 + HI - HJ  # ... down to HF
BETA_I, BETA_J = deg(100.0), deg(120.0)
OMEGA = 12.0  # rad/s


def _rise_table(law, phi):
    """Seed 001 rise columns (displacement, velocity, acceleration) at phi in the rise."""
    b, x = BETA_I, phi / BETA_I
    if law == 'constant_velocity':
        return H0 + HI * x, HI * OMEGA / b + 0 * x, 0 * x
    if law == 'constant_acceleration':  # second half: the table's '+ 2Hi(...)^2' is an OCR slip
        first = x < 0.5
        return (np.where(first, H0 + 2 * HI * x ** 2, H0 + HI - 2 * HI * (1 - x) ** 2),
                np.where(first, 4 * HI * OMEGA * phi / b ** 2, 4 * HI * OMEGA / b * (1 - x)),
                np.where(first, 4 * HI * OMEGA ** 2 / b ** 2, -4 * HI * OMEGA ** 2 / b ** 2))
    if law == 'simple_harmonic':
        return (H0 + HI / 2 * (1 - np.cos(PI * x)), PI * HI * OMEGA / (2 * b) * np.sin(PI * x),
                PI ** 2 * HI * OMEGA ** 2 / (2 * b ** 2) * np.cos(PI * x))
    return (H0 + HI * (x - np.sin(2 * PI * x) / (2 * PI)),
            HI * OMEGA / b * (1 - np.cos(2 * PI * x)),
            2 * PI * HI * OMEGA ** 2 / b ** 2 * np.sin(2 * PI * x))


def _fall_table(law, phi):
    """Seed 001 fall columns at phi in the fall (OCR slips corrected as noted)."""
    b, x = BETA_J, phi / BETA_J
    if law == 'constant_velocity':
        return HF + HJ * (1 - x), -HJ * OMEGA / b + 0 * x, 0 * x
    if law == 'constant_acceleration':
        first = x < 0.5
        return (np.where(first, HF + HJ - 2 * HJ * x ** 2, HF + 2 * HJ * (1 - x) ** 2),
                np.where(first, -4 * HJ * OMEGA * phi / b ** 2, -4 * HJ * OMEGA / b * (1 - x)),
                np.where(first, -4 * HJ * OMEGA ** 2 / b ** 2, 4 * HJ * OMEGA ** 2 / b ** 2))
    if law == 'simple_harmonic':  # the phi form prints '1 - cos'; the t form's '1 + cos' is right
        return (HF + HJ / 2 * (1 + np.cos(PI * x)), -PI * HJ * OMEGA / (2 * b) * np.sin(PI * x),
                -PI ** 2 * HJ * OMEGA ** 2 / (2 * b ** 2) * np.cos(PI * x))
    # cycloidal: the phi form prints the rise; the t form HF + Hj[1 - x + sin(2 pi x)/2pi] is right
    return (HF + HJ * (1 - x + np.sin(2 * PI * x) / (2 * PI)),
            -HJ * OMEGA / b * (1 - np.cos(2 * PI * x)),
            -2 * PI * HJ * OMEGA ** 2 / b ** 2 * np.sin(2 * PI * x))


SEED_001_LAWS = ['constant_velocity', 'constant_acceleration', 'simple_harmonic', 'cycloidal']


def _seed_001_program(name):
    """Rise 0-100 deg, dwell, fall 150-270 deg, dwell, cycloidal return to H0 over 300-360."""
    law = make_law(name)
    return program((law, 0, 100, H0, H0 + HI), (Dwell(), 100, 150, H0 + HI, H0 + HI),
                   (law, 150, 270, HF + HJ, HF), (Dwell(), 270, 300, HF, HF),
                   (Cycloidal(), 300, 360, HF, H0))


@pytest.mark.parametrize('name', SEED_001_LAWS)
@pytest.mark.parametrize('motion', ['rise', 'fall'])
def test_seed_001_tables(name, motion):
    phi = np.linspace(0.0, 1.0, 41)[1:-1] * (BETA_I if motion == 'rise' else BETA_J)
    start = 0.0 if motion == 'rise' else deg(150.0)
    table = (_rise_table if motion == 'rise' else _fall_table)(name, phi)
    timed = _seed_001_program(name).evaluate(start + phi).at_speed(OMEGA)
    assert timed.position == approx(table[0])
    assert timed.velocity == approx(table[1])
    assert timed.acceleration == approx(table[2])


# Seed 003: 4-5-6-7 rise of 0.5 in over 60 deg ------------------------------------------------

def test_seed_003_4567_rise_in_physical_units():
    h, beta = 0.5 * 0.0254, deg(60.0)
    cam = program((Polynomial4567(), 0, 60, 0.0, h), (Dwell(), 60, 180, h, h),
                  (Polynomial4567(), 180, 240, h, 0.0), (Dwell(), 240, 360, 0.0, 0.0))
    q = np.linspace(0.0, 1.0, 61)
    values = cam.evaluate(q * beta)
    y = 35 * q ** 4 - 84 * q ** 5 + 70 * q ** 6 - 20 * q ** 7
    y1 = 140 * q ** 3 - 420 * q ** 4 + 420 * q ** 5 - 140 * q ** 6
    y2 = 420 * q ** 2 - 1680 * q ** 3 + 2100 * q ** 4 - 840 * q ** 5  # OCR prints '84q^5'
    assert values.s == approx(h * y)
    assert values.ds == approx(h * y1 / beta)  # m/rad
    assert values.d2s == approx(h * y2 / beta ** 2)
    fall = cam.evaluate(deg(180.0) + q * beta)
    assert fall.s == approx(h * (1 - y))
    assert fall.ds == approx(-h * y1 / beta)


# Seed 000: dwell, cycloidal rise 2 cm, dwell, harmonic return; table every 10 deg --------------

#: (deg, f cm, f' cm/rad, f'' cm/rad^2) as printed, OCR slips corrected where noted.  The closed
#: forms: rise f = 2[x/b - sin(2 pi x/b)/(2 pi)], b = pi/2; return f = 1 + cos(1.5 x).
SEED_000_TABLE = [
    (90, 0.000, 0.000, 0.000),
    (100, 0.018, 0.298, 3.274),  # f printed 'G.018'
    (110, 0.131, 1.052, 5.016),  # f'' printed '5.018'; (16/pi) sin(80 deg) = 5.0156
    (120, 0.391, 1.910, 4.411),  # f'' printed '4419'; (16/pi) sin(120 deg) = 4.4106
    (130, 0.780, 2.470, 1.742),
    (140, 1.220, 2.470, -1.742),
    (150, 1.609, 1.910, -4.411),  # f'' printed '- 441'
    (160, 1.869, 1.052, -5.016),
    (170, 1.982, 0.298, -3.274),
    (180, 2.000, 0.000, 0.000),  # f printed '2.0G0'
    (240, 2.000, -0.000, -2.250),
    (250, 1.966, -0.388, -2.173),  # f printed '1.968'; 1 + cos(15 deg) = 1.9659
    (260, 1.866, -0.750, -1.949),
    (270, 1.707, -1.061, -1.591),
    (280, 1.500, -1.299, -1.125),
    (290, 1.259, -1.449, -0.582),
    (300, 1.000, -1.500, 0.000),
    (310, 0.741, -1.449, 0.582),  # f' printed '=1.449'
    (320, 0.500, -1.299, 1.125),  # f' printed '- 1.289'; -1.5 sin(120 deg) = -1.2990
    (330, 0.293, -1.061, 1.591),
    (340, 0.134, -0.750, 1.949),
    (350, 0.034, -0.388, 2.173),
]
# (The table's last column t = f' has its own slips: '0.338' for -0.388 at 250 and 350 deg.)


def test_seed_000_worked_example_table():
    cam = program((Dwell(), 0, 90, 0.0, 0.0), (Cycloidal(), 90, 180, 0.0, 0.02),
                  (Dwell(), 180, 240, 0.02, 0.02), (SimpleHarmonic(), 240, 360, 0.02, 0.0))
    angle, f, f1, f2 = np.array(SEED_000_TABLE).T
    values = cam.evaluate(np.radians(angle))
    assert 100 * values.s == pytest.approx(f, abs=TABLE_ATOL)  # cm
    assert 100 * values.ds == pytest.approx(f1, abs=TABLE_ATOL)
    assert 100 * values.d2s == pytest.approx(f2, abs=TABLE_ATOL)


# Seed 002: rise and fall through via points -------------------------------------------------

def _seed_002_program():
    """Rise 0 -> 180 mm over 0-130 deg via (100 deg, 160 mm); fall 170-300 via (200, 160)."""
    return program((ViaPointLaw(100 / 130, 160 / 180), 0, 130, 0.0, 0.18),
                   (Dwell(), 130, 170, 0.18, 0.18),
                   (ViaPointLaw(30 / 130, 20 / 180), 170, 300, 0.18, 0.0),
                   (Dwell(), 300, 360, 0.0, 0.0))


def test_seed_002_passes_both_via_points_without_stopping():
    cam = _seed_002_program()
    values = cam.evaluate(np.radians([100.0, 200.0]))
    assert values.s == pytest.approx([0.16, 0.16], abs=1e-10)
    assert values.ds[0] > 0.0 > values.ds[1]
    rise = cam.evaluate(np.radians(np.linspace(0.0, 130.0, 2601)[1:-1]))
    fall = cam.evaluate(np.radians(np.linspace(170.0, 300.0, 2601)[1:-1]))
    assert np.all(rise.ds > 0.0) and np.all(fall.ds < 0.0)


def test_seed_002_only_the_jerk_jumps():
    report = _seed_002_program().continuity_report()
    assert {item.order for item in report} == {3}
    assert [round(math.degrees(item.angle), 9) for item in report] == [0, 100, 130, 170, 200, 300]


# Continuity report ---------------------------------------------------------------------------

H, BETA = 0.02, deg(90.0)


def _rise_return(law):
    """Dwell 0-90, rise by H over 90-180, dwell 180-270, return over 270-360 (same law)."""
    return program((Dwell(), 0, 90, 0.0, 0.0), (law, 90, 180, 0.0, H), (Dwell(), 180, 270, H, H),
                   (law, 270, 360, H, 0.0))


def _jumps(report):
    """Return (angle deg, order, jump) triples of a continuity report."""
    return [(round(math.degrees(item.angle), 9), item.order, item.jump) for item in report]


def test_constant_velocity_next_to_dwells_jumps_in_ds():
    jump = H / BETA
    expected = [(0, 1, jump), (90, 1, jump), (180, 1, -jump), (270, 1, -jump)]
    report = _jumps(_rise_return(ConstantVelocity()).continuity_report())
    assert [item[:2] for item in report] == [item[:2] for item in expected]
    assert [item[2] for item in report] == approx([item[2] for item in expected])


def test_cycloidal_next_to_dwells_jumps_only_in_jerk():
    jerk = H * 4 * PI ** 2 / BETA ** 3
    report = _jumps(_rise_return(Cycloidal()).continuity_report())
    assert [item[:2] for item in report] == [(0, 3), (90, 3), (180, 3), (270, 3)]
    assert [item[2] for item in report] == approx([jerk, jerk, -jerk, -jerk])


def test_simple_harmonic_next_to_dwells_jumps_in_acceleration():
    acceleration = H * PI ** 2 / (2 * BETA ** 2)
    report = _jumps(_rise_return(SimpleHarmonic()).continuity_report())
    # y''' = -(pi^3/2) sin(pi u) vanishes at the ends: no jerk jump
    assert [item[:2] for item in report] == [(0, 2), (90, 2), (180, 2), (270, 2)]
    assert [item[2] for item in report] == approx([-acceleration, acceleration, acceleration,
                                                   -acceleration])


def test_constant_acceleration_jumps_inside_the_segment_too():
    acceleration = 4 * H / BETA ** 2
    report = _jumps(_rise_return(ConstantAcceleration()).continuity_report())
    assert [item[:2] for item in report] == [(0, 2), (90, 2), (135, 2), (180, 2), (270, 2),
                                             (315, 2)]
    assert [item[2] for item in report] == approx(
        [-acceleration, acceleration, -2 * acceleration, acceleration, -acceleration,
         2 * acceleration])
    assert _rise_return(ConstantAcceleration()).continuity_report()[2].segment == 1


def test_wrap_joint_reports_the_last_segment_against_the_first():
    cam = program((Cycloidal(), -90, 0, 0.0, H), (Dwell(), 0, 180, H, H),
                  (SimpleHarmonic(), 180, 270, H, 0.0))
    wrap = [item for item in cam.continuity_report() if item.segment == 0]
    angles = [(round(math.degrees(item.angle), 9), item.order) for item in wrap]
    assert angles == [(-90, 2), (-90, 3)]  # harmonic y'' against cycloidal y'''
    assert wrap[0].left == approx(H * PI ** 2 / (2 * BETA ** 2))
    assert wrap[0].right == 0.0


def _steep(law, rise, span_deg):
    """Dwell, a rise by rise (m) over span_deg, dwell, the same law back over 90 deg."""
    return program((Dwell(), 0, 90, 0.0, 0.0), (law, 90, 90 + span_deg, 0.0, rise),
                   (Dwell(), 90 + span_deg, 270, rise, rise), (law, 270, 360, rise, 0.0))


def test_rounding_at_smooth_joints_is_not_a_jump():
    """Leave out rounding noise where the jerk is continuous in exact arithmetic.

    Harmonic y''' = -(pi^3/2) sin(pi u) is 0 at u = 1, ~1e-16 computed: on a 1000 m rise over
    3 deg (h / beta^3 = 7e6 m/rad^3) a 1e-8 'jump' against the dwell. Modified sine has y''' = 0
    on both sides of its inner breakpoints (u = 1/8, 7/8). Only the real jumps remain.
    """
    harmonic = _steep(SimpleHarmonic(), 1000.0, 3.0)
    values = harmonic.evaluate(np.array([deg(93.0) - 1e-12]))
    assert values.d3s[0] != 0.0  # the rounding the report must see through
    assert [(round(math.degrees(item.angle), 9), item.order)
            for item in harmonic.continuity_report()] == [(0, 2), (90, 2), (93, 2), (270, 2)]
    law = make_law('modified_sine')
    report = _jumps(_steep(law, 1000.0, 3.0).continuity_report())
    assert [item[:2] for item in report] == [(0, 3), (90, 3), (93, 3), (270, 3)]
    jerk = 1000.0 * law.cj / deg(3.0) ** 3  # modified sine's peak |y'''| is at its ends
    assert report[1][2] == approx(jerk) and report[2][2] == approx(-jerk)


@pytest.mark.parametrize('scale', [1e-12, 1e-6, 1e3])
def test_the_report_does_not_depend_on_the_length_scale(scale):
    """Scaling every stroke scales every jump: the same joints at any size (1 pm to 1 km)."""
    expected = _jumps(_rise_return(Cycloidal()).continuity_report())
    rise = H * scale
    cam = program((Dwell(), 0, 90, 0.0, 0.0), (Cycloidal(), 90, 180, 0.0, rise),
                  (Dwell(), 180, 270, rise, rise), (Cycloidal(), 270, 360, rise, 0.0))
    report = _jumps(cam.continuity_report())
    assert [item[:2] for item in report] == [item[:2] for item in expected]
    assert [item[2] for item in report] == approx([item[2] * scale for item in expected], abs=0.0)


# Evaluation: modulo 2 pi, shapes, time derivatives, speed -----------------------------------

def test_evaluate_takes_angles_modulo_a_revolution():
    cam = _seed_002_program()
    theta = np.linspace(0.0, 2 * PI, 997, endpoint=False)
    reference = cam.evaluate(theta)
    for turns in (-3, -1, 1, 5):
        shifted = cam.evaluate(theta + 2 * PI * turns)
        for mine, theirs in zip((shifted.s, shifted.ds, shifted.d2s, shifted.d3s),
                                (reference.s, reference.ds, reference.d2s, reference.d3s)):
            assert mine == pytest.approx(theirs, rel=1e-9, abs=1e-9)


def test_program_may_start_at_any_angle():
    rotated = program((Cycloidal(), -90, 0, 0.0, H), (Dwell(), 0, 180, H, H),
                      (SimpleHarmonic(), 180, 270, H, 0.0))
    plain = program((Cycloidal(), 0, 90, 0.0, H), (Dwell(), 90, 270, H, H),
                    (SimpleHarmonic(), 270, 360, H, 0.0))
    theta = np.linspace(-4 * PI, 4 * PI, 1001)
    assert rotated.evaluate(theta).s == approx(plain.evaluate(theta + deg(90.0)).s)
    assert rotated.evaluate(deg(-90.0)).s == pytest.approx(0.0)


@pytest.mark.parametrize(('angle_deg', 'number'), [
    (-90.0, 0), (-45.0, 0), (0.0, 1), (179.9, 1), (180.0, 2), (269.9, 2), (270.0, 0),
    (630.0, 0), (-181.0, 1), (-91.0, 2)])
def test_segment_at_names_the_segment_owning_any_angle(angle_deg, number):
    rotated = program((Cycloidal(), -90, 0, 0.0, H), (Dwell(), 0, 180, H, H),
                      (SimpleHarmonic(), 180, 270, H, 0.0))
    assert rotated.segment_at(deg(angle_deg)) == number


def test_evaluate_keeps_the_shape_and_returns_read_only_arrays():
    values = _seed_002_program().evaluate(np.zeros((2, 3)))
    assert values.s.shape == (2, 3)
    with pytest.raises(ValueError):
        values.s[0, 0] = 1.0
    assert _seed_002_program().evaluate(1.0).s.shape == ()


def test_time_derivatives_scale_with_the_cam_speed():
    values = _seed_002_program().evaluate(np.linspace(0.0, 6.0, 50))
    timed = values.at_speed(-3.0)
    assert timed.position is values.s
    assert timed.velocity == approx(-3.0 * values.ds)
    assert timed.acceleration == approx(9.0 * values.d2s)
    assert timed.jerk == approx(-27.0 * values.d3s)
    with pytest.raises(InvalidParameter, match='^omega = nan'):
        values.at_speed(math.nan)


@pytest.mark.parametrize(('theta', 'shown'), [([0.0, math.inf], 'inf'), ([math.nan], 'nan'),
                                              (['north'], "['north']")])
def test_evaluate_rejects_non_finite_angles(theta, shown):
    with pytest.raises(InvalidParameter) as caught:
        _seed_002_program().evaluate(theta)
    assert str(caught.value) == f'theta = {shown}: must be finite (rad)'


def python_lines(run) -> int:
    """Return how many lines of Python run() executes (C code such as ufuncs not counted)."""
    lines = 0

    def trace(frame, event, arg):
        nonlocal lines
        lines += event == 'line'
        return trace

    sys.settrace(trace)
    try:
        run()
    finally:
        sys.settrace(None)
    return lines


def test_python_work_grows_per_block_not_per_angle():
    """Vectorised: Python runs once per block of BLOCK angles of a segment, never per angle."""
    cam = _seed_002_program()
    rng = np.random.default_rng(1)
    few, many = (rng.uniform(-10.0, 10.0, size) for size in (10 ** 3, 10 ** 6))
    cam.evaluate(few)  # first use imports SciPy (loaded lazily) and fills caches
    blocks = many.size // BLOCK + len(cam.segments)
    assert python_lines(lambda: cam.evaluate(many)) <= blocks * python_lines(
        lambda: cam.evaluate(few))
    more = rng.uniform(-10.0, 10.0, 5 * few.size)  # still one block per segment
    assert python_lines(lambda: cam.evaluate(more)) == python_lines(lambda: cam.evaluate(few))
    assert cam.evaluate(many).s.shape == many.shape


@pytest.mark.parametrize('make', [_seed_002_program, lambda: _rise_return(Cycloidal()),
                                  lambda: _seed_001_program('constant_acceleration')],
                         ids=['via_point', 'cycloidal', 'constant_acceleration'])
def test_an_angle_gets_the_same_values_in_any_order_or_batch(make):
    cam = make()
    joints = [segment.start for segment in cam.segments]
    inside = np.random.default_rng(2).uniform(0.0, 2 * PI - 1e-6, 3000)
    theta = np.sort(np.concatenate([joints, cam.start + inside]))  # sorted: split into slices
    shuffle = np.random.default_rng(3).permutation(theta.size)  # any order: grouped by segment
    ordered, shuffled = cam.evaluate(theta), cam.evaluate(theta[shuffle])
    alone = [cam.evaluate(angle) for angle in theta[::37]]
    for name in ('s', 'ds', 'd2s', 'd3s'):
        expected = getattr(ordered, name)
        np.testing.assert_array_equal(getattr(shuffled, name), expected[shuffle])
        np.testing.assert_array_equal([getattr(values, name) for values in alone], expected[::37])


def test_an_angle_in_a_joint_gap_takes_the_end_of_the_segment_before():
    gap = 0.5e-9  # accepted: below ANGLE_TOLERANCE
    cam = MotionProgram([Segment(ConstantVelocity(), 0.0, PI, 0.0, H),
                         Segment(Cycloidal(), PI + gap, 2 * PI, H, 0.0)])
    values = cam.evaluate([PI + gap / 2, PI])
    assert values.s.tolist() == [H, H]  # u clipped to 1, not a hair past it
    assert values.ds.tolist() == [H / PI, H / PI]


def test_an_overlap_past_a_short_segment_stays_with_the_segment_before():
    short, overlap = 0.1e-9, 0.6e-9  # accepted: the third segment starts before the second
    cam = MotionProgram([Segment(Cycloidal(), 0.0, 1.0, 0.0, H),
                         Segment(Dwell(), 1.0, 1.0 + short, H, H),
                         Segment(SimpleHarmonic(), 1.0 + short - overlap, 2 * PI, H, 0.0)])
    theta = np.sort(np.concatenate([np.linspace(0.0, 2 * PI, 1000, endpoint=False),
                                    1.0 + np.array([-1.0, -0.5, 0.0, 0.05, 0.1, 0.5]) * 1e-9]))
    ordered, backwards = cam.evaluate(theta), cam.evaluate(theta[::-1])
    for name in ('s', 'ds', 'd2s', 'd3s'):
        assert np.all(np.isfinite(getattr(ordered, name)))
        np.testing.assert_array_equal(getattr(backwards, name)[::-1], getattr(ordered, name))
    first = theta < 1.0  # the second segment's start: the first keeps the overlap
    law = cam.segments[0].law.evaluate(theta[first])
    assert ordered.s[first] == approx(H * law.y)
    assert ordered.d2s[first] == approx(H * law.y2)


# Segment summary -----------------------------------------------------------------------------

def test_segment_summary_scales_the_characteristic_values():
    cam = _rise_return(Cycloidal())
    summary = cam.segment_summary()
    assert [item.law for item in summary] == ['dwell', 'cycloidal', 'dwell', 'cycloidal']
    rise = summary[1]
    assert (rise.index, rise.start, rise.end, rise.s_start, rise.s_end) == (
        1, deg(90), deg(180), 0.0, H)
    assert (rise.peak_ds, rise.peak_d2s, rise.peak_d3s) == approx(
        (2 * H / BETA, 2 * PI * H / BETA ** 2, 4 * PI ** 2 * H / BETA ** 3))
    assert (summary[0].peak_ds, summary[0].peak_d2s, summary[0].peak_d3s) == (0.0, 0.0, 0.0)


def test_segment_summary_peaks_bound_the_sampled_motion():
    cam = _seed_002_program()
    for item in cam.segment_summary():
        values = cam.evaluate(np.linspace(item.start, item.end - 1e-12, 4001))
        for peak, column in zip((item.peak_ds, item.peak_d2s, item.peak_d3s),
                                (values.ds, values.d2s, values.d3s)):
            sampled = float(np.max(np.abs(column)))
            assert sampled <= peak * (1 + 1e-6) + 1e-12
            assert sampled == pytest.approx(peak, rel=1e-3, abs=1e-12)


# Validation ----------------------------------------------------------------------------------

def _segments():
    """Valid segments of a dwell-rise-dwell-return program, to break one rule at a time."""
    return [Segment(Dwell(), 0.0, deg(90), 0.0, 0.0), Segment(Cycloidal(), deg(90), PI, 0.0, H),
            Segment(Dwell(), PI, deg(270), H, H), Segment(Cycloidal(), deg(270), 2 * PI, H, 0.0)]


def _replace(index, **changes):
    """Return the valid segments with one segment's fields changed."""
    segments = _segments()
    fields = {name: getattr(segments[index], name)
              for name in ('law', 'start', 'end', 's_start', 's_end')}
    segments[index] = Segment(**{**fields, **changes})
    return segments


@pytest.mark.parametrize(('segments', 'parameter', 'rule'), [
    ([], 'segments', 'at least one segment'),
    (7, 'segments', 'must be a sequence'),
    (_segments()[:3] + ['cycloidal'], 'segments[3]', 'must be a Segment'),
    (_replace(1, law='cycloidal'), 'segments[1].law', 'must be a MotionLaw'),
    (_replace(1, start=math.nan), 'segments[1].start', 'finite'),
    (_replace(2, s_end=math.inf), 'segments[2].s_end', 'finite'),
    (_replace(1, end=deg(90)), 'segments[1].end', 'must exceed start'),
    (_replace(2, start=deg(181)), 'segments[2].start', 'leaves a gap of 1 deg'),
    (_replace(2, start=deg(179)), 'segments[2].start', 'leaves an overlap of 1 deg'),
    (_replace(3, end=deg(350)), 'segments[3].end', 'must cover 360 deg'),
    (_replace(2, s_start=0.019, s_end=0.019), 'segments[2].s_start',
     'must equal segments[1].s_end'),
    (_replace(3, s_end=0.001), 'segments[0].s_start', 'the wrap joint 360 -> 0 deg'),
    (_replace(2, s_end=0.0), 'segments[2].s_end', 'a dwell must end where it starts'),
])
def test_program_rejects_broken_rules(segments, parameter, rule):
    with pytest.raises(InvalidParameter) as caught:
        MotionProgram(segments)
    assert caught.value.parameter == parameter
    assert rule in str(caught.value)
    assert str(caught.value).startswith(f'{parameter} = ')


def test_program_accepts_round_off_at_the_joints():
    segments = _replace(2, start=PI + 1e-12)
    assert len(MotionProgram(segments).segments) == 4


def test_program_is_an_immutable_value():
    cam = MotionProgram(_segments())
    assert isinstance(cam.segments, tuple)
    with pytest.raises(AttributeError):
        cam.segments = ()  # type: ignore[misc]
    assert cam == MotionProgram(_segments())


def test_breaks_are_the_joints_and_the_laws_breakpoints():
    cam = program((Dwell(), 0, 90, 0.0, 0.0), (ConstantAcceleration(), 90, 210, 0.0, 0.02),
                  (Dwell(), 210, 250, 0.02, 0.02), (Cycloidal(), 250, 360, 0.02, 0.0))
    assert cam.breaks == approx(np.radians([0, 90, 150, 210, 250]))  # 150: the flip of y''
    jumps = {round(math.degrees(item.angle), 9) for item in cam.continuity_report()}
    assert jumps and jumps <= set(np.round(np.degrees(cam.breaks), 9))
    with pytest.raises(ValueError):
        cam.breaks[0] = 1.0


@pytest.mark.parametrize('make', [_seed_002_program, lambda: _rise_return(Cycloidal())],
                         ids=['via_point', 'cycloidal'])
def test_evaluate_at_speed_is_evaluate_then_at_speed(make):
    cam = make()
    theta = np.random.default_rng(4).uniform(-10.0, 10.0, 2 * BLOCK + 3)  # blocks, any order
    direct, two_steps = cam.evaluate_at_speed(theta, 7.5), cam.evaluate(theta).at_speed(7.5)
    for name in ('position', 'velocity', 'acceleration', 'jerk'):
        np.testing.assert_array_equal(getattr(direct, name), getattr(two_steps, name))
    with pytest.raises(InvalidParameter):
        cam.evaluate_at_speed(theta, math.inf)


@pytest.mark.parametrize('advancing', [False, True])
def test_one_angle_gives_the_very_numbers_of_an_array_of_angles(advancing):
    """The one-angle paths (a master message) skip the grouping, not a digit of the result."""
    end = 0.36 if advancing else 0.0  # an advancing program ends above its start
    cam = MotionProgram([Segment(law, deg(start), deg(stop), s0, s1, ramp=ramp)
                         for law, start, stop, s0, s1, ramp
                         in ((Cycloidal(), -30.0, 100.0, 0.0, 0.2, 0.03),  # a ramp under it
                             (Dwell(), 100.0, 150.0, 0.2, 0.2, 0.0),
                             (Polynomial4567(), 150.0, 330.0, 0.2, end, 0.0))], advance=end)
    angles = np.concatenate([np.random.default_rng(1).uniform(-40.0, 40.0, 400),
                             [deg(-30.0), deg(100.0), deg(150.0), deg(330.0), 2 * PI, -0.0,
                              np.nextafter(deg(330.0), 0.0), 1e6]])
    together = cam.evaluate(angles)
    one_by_one = [cam.evaluate(angle) for angle in angles.tolist()]
    in_floats = np.array([cam.at(angle) for angle in angles.tolist()])
    for column, name in enumerate(('s', 'ds', 'd2s', 'd3s')):
        np.testing.assert_array_equal([getattr(v, name) for v in one_by_one],
                                      getattr(together, name))
        np.testing.assert_array_equal(in_floats[:, column], getattr(together, name))
    assert all(type(value) is float for value in cam.at(1.0))
    in_arrays_of_one = [cam.evaluate(np.array([[angle]])).d2s for angle in angles.tolist()]
    np.testing.assert_array_equal(np.ravel(in_arrays_of_one), together.d2s)
    assert one_by_one[0].s.shape == () and cam.evaluate(np.float64(1.0)).s.shape == ()
    assert in_arrays_of_one[0].shape == (1, 1)
    with pytest.raises(InvalidParameter, match='theta'):
        cam.evaluate(math.nan)
    with pytest.raises(InvalidParameter, match='theta'):
        cam.at(math.inf)
