"""Handover between two electronic cams: where they agree, and when a change is due."""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from cam_ros.core.ecam.handover import agreement, Handover, POSITION_TOLERANCE, SLOPE_TOLERANCE
from cam_ros.core.motion.laws import Cycloidal, Dwell, SimpleHarmonic
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

deg = math.radians
MAPPING = CamMapping()
#: A bisection-refined end lies within this of the true end of agreement (rad).
END_ATOL = 1e-9


def cam(stroke: float, mapping: CamMapping = MAPPING) -> ElectronicCam:
    """Dwell at 0 over 0-90 deg, cycloidal rise by stroke, dwell, harmonic return (seed 000)."""
    return ElectronicCam(MotionProgram((
        Segment(Dwell(), deg(0), deg(90), 0.0, 0.0),
        Segment(Cycloidal(), deg(90), deg(180), 0.0, stroke),
        Segment(Dwell(), deg(180), deg(240), stroke, stroke),
        Segment(SimpleHarmonic(), deg(240), deg(360), stroke, 0.0))), mapping)


def rise_fall(stroke: float) -> ElectronicCam:
    """Cycloidal rise over 0-180 deg and fall over 180-360: at rest only at 0."""
    return ElectronicCam(MotionProgram((
        Segment(Cycloidal(), 0.0, math.pi, 0.0, stroke),
        Segment(Cycloidal(), math.pi, 2 * math.pi, stroke, 0.0))), MAPPING)


def agrees(old: ElectronicCam, new: ElectronicCam, theta) -> np.ndarray:
    """Agreement written out from the programs (not the module's helper)."""
    a, b = old.program.evaluate(theta), new.program.evaluate(theta)
    return (np.abs(a.s - b.s) <= POSITION_TOLERANCE) & (np.abs(a.ds - b.ds) <= SLOPE_TOLERANCE)


def test_identical_cams_agree_everywhere_and_hand_over_at_once():
    intervals = agreement(cam(0.02), cam(0.02))
    np.testing.assert_array_equal(intervals, [[0.0, 2 * math.pi]])
    assert Handover(cam(0.02), cam(0.02)).due(1.0, 0.01)


def test_a_common_dwell_is_found_and_its_ends_are_exact():
    old, new = cam(0.02), cam(0.03)
    intervals = agreement(old, new)
    assert intervals.shape == (1, 2)
    low, high = intervals[0]
    # The dwell at 0 (0-90 deg) plus where the rise and the return stay within the tolerance.
    assert deg(359.0) < low < 2 * math.pi and deg(90.0) < high - 2 * math.pi < deg(91.0)
    assert agrees(old, new, np.array([low, high])).all()
    assert not agrees(old, new, np.array([low - END_ATOL, high + END_ATOL])).any()
    # Brute force: every agreeing angle of a fine sweep lies in the interval.
    theta = np.linspace(0.0, 2 * math.pi, 1_000_001)
    inside = (theta >= low) | (theta <= high - 2 * math.pi)
    np.testing.assert_array_equal(agrees(old, new, theta), inside)


def law(name: str, start_deg: float, end_deg: float, s0: float, s1: float):
    """Return s(theta) and ds/dtheta of one segment in closed form (sin and cos, for the test)."""
    start, beta, h = deg(start_deg), deg(end_deg - start_deg), s1 - s0
    if name == 'simple_harmonic':
        return (lambda t: s0 + h / 2 * (1 - math.cos(math.pi * (t - start) / beta)),
                lambda t: h / 2 * math.pi / beta * math.sin(math.pi * (t - start) / beta))
    assert name == 'cycloidal'
    return (lambda t: s0 + h * ((t - start) / beta
                                - math.sin(2 * math.pi * (t - start) / beta) / (2 * math.pi)),
            lambda t: h / beta * 2 * math.sin(math.pi * (t - start) / beta) ** 2)


def end_of_agreement(old, new, inside: float, outside: float) -> float:
    """Solve for the angle between inside and outside where the agreement ends (brentq)."""
    def excess(theta: float) -> float:
        (old_s, old_ds), (new_s, new_ds) = ((s(theta), ds(theta)) for s, ds in (old, new))
        return max(abs(new_s - old_s) - POSITION_TOLERANCE, abs(new_ds - old_ds) - SLOPE_TOLERANCE)
    return brentq(excess, inside, outside, xtol=1e-15, rtol=4 * np.finfo(float).eps)


def test_two_dwells_at_equal_height_give_two_intervals():
    old, new = cam(0.02), ElectronicCam(MotionProgram((
        Segment(Dwell(), deg(0), deg(90), 0.0, 0.0),
        Segment(SimpleHarmonic(), deg(90), deg(150), 0.0, 0.02),
        Segment(Dwell(), deg(150), deg(260), 0.02, 0.02),
        Segment(Cycloidal(), deg(260), deg(360), 0.02, 0.0))), MAPPING)
    intervals = agreement(old, new)
    assert intervals.shape == (2, 2)
    # Each end from the closed forms of the two segments that meet there: the dwells agree
    # exactly, so an end lies a little past the joint where one cam leaves the common height.
    high_dwell = (lambda t: 0.02, lambda t: 0.0)
    expected = [
        [end_of_agreement(law('cycloidal', 90, 180, 0.0, 0.02), high_dwell, deg(180), deg(179)),
         end_of_agreement(law('simple_harmonic', 240, 360, 0.02, 0.0), high_dwell, deg(240),
                          deg(241))],
        [end_of_agreement(law('simple_harmonic', 240, 360, 0.02, 0.0),
                          law('cycloidal', 260, 360, 0.02, 0.0), deg(360), deg(359)),
         2 * math.pi + end_of_agreement(law('cycloidal', 90, 180, 0.0, 0.02),
                                        law('simple_harmonic', 90, 150, 0.0, 0.02), deg(90),
                                        deg(91))]]
    # Bisection to round-off: within 1e-12 rad (9e-16 measured), far inside END_ATOL.
    np.testing.assert_allclose(intervals, expected, rtol=0.0, atol=1e-12)
    # Every end lies past its joint by more than END_ATOL (1e-8 rad at the least): checked
    # this closely, no end is its joint.
    joints = np.radians([[180.0, 240.0], [360.0, 450.0]])
    assert (np.abs(intervals - joints) > 10 * END_ATOL).all()


def test_the_cycle_start_of_two_rises_is_found_and_crossing_it_makes_the_change_due():
    old, new = rise_fall(0.02), rise_fall(0.03)
    intervals = agreement(old, new)
    assert len(intervals) == 1
    low, high = intervals[0]
    assert low > deg(355.0) and high - 2 * math.pi < deg(5.0)  # a narrow band around 0
    handover = Handover(old, new)
    step = deg(20.0)
    assert handover.due(deg(10.0) + 6 * math.pi, step)  # crossed 0 going forward
    assert handover.due(deg(350.0) - 4 * math.pi, -step)  # and going backward
    assert not handover.due(deg(100.0), step)
    assert not handover.due(deg(300.0), step)
    assert not handover.due(deg(100.0), 0.0)  # a standing master: only in a common place
    assert handover.due(0.0, 0.0)


def test_a_change_crossing_the_start_at_speed_moves_the_command_by_a_small_fraction_of_a_step():
    old, new = rise_fall(0.02), rise_fall(0.03)
    handover = Handover(old, new)
    step = 600 * 2 * math.pi / 60 / 1000  # 600 rpm sampled at 1 kHz (rad per message)
    master = np.arange(deg(300.0), deg(420.0), step)
    due = [handover.due(q, step) for q in master.tolist()]
    first = due.index(True)
    q = master[first]
    moved = abs(float(new.setpoints(q).position - old.setpoints(q).position))
    # Taylor from the agreeing point within the last step: tolerances + max |d2 difference| / 2.
    arc = np.linspace(q - step, q, 1001)
    curvature = np.abs(new.program.evaluate(arc).d2s - old.program.evaluate(arc).d2s).max()
    assert moved <= POSITION_TOLERANCE + SLOPE_TOLERANCE * step + curvature * step ** 2 / 2
    elsewhere = abs(float(new.setpoints(math.pi / 2).position - old.setpoints(math.pi / 2)
                          .position))
    assert moved < 1e-5 * elsewhere
    assert not any(due[:first])


def test_different_master_mappings_share_nothing_and_are_never_due():
    # (such a change is a move onto the new cam: test_follow)
    old, new = cam(0.02), cam(0.02, CamMapping(master_scaling=2.0))
    assert agreement(old, new).shape == (0, 2)
    handover = Handover(old, new)
    assert not handover.due(1.0, 0.5)
    assert not handover.due(1.0, 0.0)


def test_describe_names_the_places_in_degrees():
    text = Handover(cam(0.02), cam(0.03)).describe()
    assert text.startswith('waits for cam angle 360.00-90.01') and text.endswith(' deg')
