"""Motion functions of the CODESYS default cam: three quintics, every one native and exact.

The cam (test_vendor_example.py; CODESYS Online Help, "Creating Cams Programmatically") is
X 0/120/240/360, Y 0/120/240/360, V 0/1/1/0, A 0: R-G, G-G, G-R quintics, the slave advancing
360 per cycle.  Written as motion-function points, each segment is one interval whose boundary
values are the published table's, and each quintic through them is the segment itself.
"""
import math

import numpy as np

from cam_ros.core.ecam.motion_functions import LINE, motion_function, QUINTIC, REST_QUINTIC
from cam_ros.core.motion.laws import make_law
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment
from cam_ros.core.motion.tasks import build_segments, TaskSpec

K = math.pi / 180.0
TABLE = ((0.0, 0.0, 0.0, 0.0), (120.0, 120.0, 1.0, 0.0), (240.0, 240.0, 1.0, 0.0),
         (360.0, 360.0, 0.0, 0.0))


def codesys_default_cam():
    specs = [TaskSpec('poly5', x0 * K, x1 * K, y0 * K, y1 * K, finish=(v1, a1 / K, math.nan))
             for (x0, y0, _, _), (x1, y1, v1, a1) in zip(TABLE[:-1], TABLE[1:])]
    return MotionProgram(build_segments(specs), advance=360.0 * K)


def quintic(x0, x1, left, right, x):
    """Return the quintic through (y, y', y'') at x0 and x1, by one 6 x 6 solve."""
    d = x1 - x0
    rows = [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
            [1, d, d ** 2, d ** 3, d ** 4, d ** 5], [0, 1, 2 * d, 3 * d ** 2, 4 * d ** 3,
                                                     5 * d ** 4],
            [0, 0, 2, 6 * d, 12 * d ** 2, 20 * d ** 3]]
    c = np.linalg.solve(np.array(rows, float), [*left, *right])
    return np.polyval(c[::-1], x - x0)


def test_every_segment_is_one_native_interval_with_the_tables_values():
    program = codesys_default_cam()
    function = motion_function(program)
    assert function.pieced == {} and function.max_error == 0.0
    assert function.kinds == (QUINTIC,) * 3  # the G-G poly5 too (a line, as a quintic)
    np.testing.assert_allclose(np.degrees(function.angle), [row[0] for row in TABLE],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(function.s / K, [row[1] for row in TABLE], rtol=0, atol=1e-12)
    np.testing.assert_allclose(function.ds, [row[2] for row in TABLE], rtol=0, atol=1e-12)
    np.testing.assert_allclose(function.d2s, 0.0, rtol=0, atol=1e-12)


def test_the_quintics_through_the_points_are_the_design_to_1e_12_of_the_stroke():
    program = codesys_default_cam()
    function = motion_function(program)
    for i in range(len(function.kinds)):
        x0, x1 = function.angle[i:i + 2]
        x = np.linspace(x0, x1, 10_001)[:-1]
        values = [(function.s[j], function.ds[j], function.d2s[j]) for j in (i, i + 1)]
        np.testing.assert_allclose(quintic(x0, x1, *values, x), program.evaluate(x).s,
                                   rtol=0, atol=1e-12 * 360.0 * K)


def test_a_design_of_dwells_and_trigonometric_laws_is_lines_and_quintic_pieces():
    """Seed 000: the dwells are exact lines; the cycloidal rise and harmonic return become
    quintic pieces, each within the tolerance of the design (2001 angles per interval)."""
    rise, tolerance = 0.02, 1e-6
    program = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * K, 0.0, 0.0),
                             Segment(make_law('cycloidal'), 90 * K, 180 * K, 0.0, rise),
                             Segment(make_law('dwell'), 180 * K, 240 * K, rise, rise),
                             Segment(make_law('simple_harmonic'), 240 * K, 360 * K, rise, 0.0)))
    function = motion_function(program, tolerance)
    assert set(function.pieced) == {1, 3} and function.max_error <= tolerance
    for i, (kind, owner) in enumerate(zip(function.kinds, function.owner)):
        x0, x1 = function.angle[i:i + 2]
        assert program.segment_at(0.5 * (x0 + x1)) == owner
        assert (kind == LINE) == (owner in (0, 2))
        x = np.linspace(x0, x1, 2001)
        assert np.abs(interval_positions(function, i, x) - program.evaluate(x).s).max() \
            <= tolerance


def interval_positions(function, i, x):
    """Return interval i's positions at x: its line, or its quintic through its two points."""
    x0, x1 = function.angle[i:i + 2]
    if function.kinds[i] == LINE:
        return np.interp(x, [x0, x1], function.s[i:i + 2])
    values = [(function.s[j], function.ds[j], function.d2s[j]) for j in (i, i + 1)]
    return quintic(x0, x1, *values, x)


def test_a_3_4_5_rise_between_dwells_is_one_rest_to_rest_quintic():
    """The 3-4-5 polynomial is the quintic from rest to rest: native, at rest at both ends."""
    rise = 0.02
    program = MotionProgram((Segment(make_law('dwell'), 0.0, 90 * K, 0.0, 0.0),
                             Segment(make_law('polynomial_345'), 90 * K, 180 * K, 0.0, rise),
                             Segment(make_law('dwell'), 180 * K, 240 * K, rise, rise),
                             Segment(make_law('polynomial_345'), 240 * K, 360 * K, rise, 0.0)))
    function = motion_function(program)
    assert function.kinds == (LINE, REST_QUINTIC, LINE, REST_QUINTIC)
    np.testing.assert_allclose(function.ds, 0.0, rtol=0, atol=1e-15)  # at rest at every point
    np.testing.assert_allclose(function.d2s, 0.0, rtol=0, atol=1e-12)


def test_a_3_4_5_segment_ending_where_the_velocity_jumps_is_pieced_within_the_tolerance():
    """Each 3-4-5 rise or return ends at rest where a constant velocity starts (the return at
    the cycle's end, where the first segment starts): a point holds one velocity, so both are
    pieced, and the quintic through each interval's points (a 6 x 6 solve here) stays within
    the tolerance of the design (2001 angles per interval)."""
    tolerance = 1e-6
    program = MotionProgram((Segment(make_law('constant_velocity'), 0.0, 90 * K, 0.0, 0.01),
                             Segment(make_law('polynomial_345'), 90 * K, 180 * K, 0.01, 0.02),
                             Segment(make_law('constant_velocity'), 180 * K, 270 * K, 0.02,
                                     0.03),
                             Segment(make_law('polynomial_345'), 270 * K, 360 * K, 0.03, 0.0)))
    function = motion_function(program, tolerance)
    assert set(function.pieced) == {1, 3} and function.max_error <= tolerance
    for i in range(len(function.kinds)):
        x = np.linspace(*function.angle[i:i + 2], 2001)
        assert np.abs(interval_positions(function, i, x) - program.evaluate(x).s).max() \
            <= tolerance, i
