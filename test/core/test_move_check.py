"""Moves off the cams on a machine (core/machine/move_check.py): pairs checked over the moves'
time, against a brute-force dense sampling written here; orders found where one exists.

config/machine.yaml: gap = 310 mm - feeder - jaw >= 15 mm; the jaw in its zone above 60 mm, the
knife above 320 deg (modulo a turn), 20 deg of machine angle apart (at cam_speed, 600 deg/s).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONFIG_DIR

from cam_ros.core import read_parameters_file
from cam_ros.core.ecam.moves import AxisState, MasterMotion
from cam_ros.core.machine.move_check import (check_moves, MoveCheck, plan_moves, Sequence,
                                             sequence_moves, time_margin)
from cam_ros.core.machine.served import machine_from_values

MACHINE = CONFIG_DIR / 'machine.yaml'
DEG = math.pi / 180.0
CAM_SPEED = 10.471975511965978  # rad/s of machine angle: the margins' speed at master rest
SAMPLES = 1_000_001


def machine(**changes):
    values = read_parameters_file(MACHINE)
    values.update(changes)
    return machine_from_values(values)


def planned(shop, starts, master):
    moves = plan_moves(shop, {name: AxisState(value) for name, value in starts.items()}, master)
    assert isinstance(moves, dict), moves
    return moves


def dense(moves, end):
    """Return sample times and every axis's commanded position there (brute force)."""
    t = np.linspace(0.0, end, SAMPLES)
    return t, {name: move.at(t).position for name, move in moves.items()}


def by_pair(checks) -> dict[str, MoveCheck]:
    return {check.check.pair.type: check for check in checks}


def stretches(inside: np.ndarray, t: np.ndarray) -> list[tuple[float, float]]:
    """Return the (start, end) of every run of True samples."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], inside.astype(int), [0]))))
    return [(t[a], t[b - 1]) for a, b in zip(edges[::2], edges[1::2])]


AT_240 = MasterMotion(240.0 * DEG)  # jaw closed on its cam (80 mm), knife at 112 deg, at rest


#: A pusher slower than the jaw: 0.2 m/s, 4 m/s^2 (its cam at rest uses none of it).
SLOW_PUSHER = {'feeder.slave.max_velocity': 200.0, 'feeder.slave.max_acceleration': 4000.0}


def test_a_clearance_collision_during_the_moves_is_found_and_refined():
    # The jaw closes (0 -> 80 mm in 0.089 s) while the pusher backs off slowly from 240 mm:
    # at the start and the end the gap is 70 and 69 mm, in between it falls below 15 mm.
    shop = machine(**SLOW_PUSHER)
    moves = planned(shop, {'feeder': 0.24, 'jaw': 0.0}, AT_240)
    clearance = by_pair(check_moves(shop, moves, AT_240))['clearance']
    end = max(move.duration for move in moves.values())
    t, y = dense(moves, end)
    gap = 0.31 - y['feeder'] - y['jaw']
    assert gap[0] == pytest.approx(0.07) and gap[-1] > 0.06 and gap.min() < 0.015
    assert not clearance.ok
    assert clearance.check.value <= gap.min() + 1e-12  # the true minimum, not a sample
    assert clearance.check.value == pytest.approx(gap.min(), abs=1e-9)
    assert clearance.time == pytest.approx(t[np.argmin(gap)], abs=2e-6)
    assert clearance.check.at == pytest.approx(240.0 * DEG)  # the master at rest


def test_the_colliding_moves_are_ordered_the_pusher_first():
    shop = machine(**SLOW_PUSHER)
    moves = planned(shop, {'feeder': 0.24, 'jaw': 0.0}, AT_240)
    found = sequence_moves(shop, moves, AT_240)
    assert isinstance(found, Sequence), found
    assert found.order == ('feeder', 'jaw')
    assert all(check.ok for check in found.checks)
    ordered = found.moves
    assert ordered['jaw'].delay == pytest.approx(moves['feeder'].duration)
    t, y = dense(ordered, ordered['jaw'].duration)
    gap = 0.31 - y['feeder'] - y['jaw']
    assert gap.min() >= 0.015
    assert by_pair(found.checks)['clearance'].check.value == pytest.approx(gap.min(), abs=1e-9)
    np.testing.assert_array_equal(y['jaw'][t < ordered['jaw'].delay], 0.0)  # it waits open


def test_a_zone_overlap_during_the_moves_is_found_and_the_knife_goes_first():
    # The knife at 300 deg (out of its zone) turns forward onto its cam at 112 deg + a turn,
    # through 320-360 (its zone); the jaw closes into its zone meanwhile.
    shop = machine()
    moves = planned(shop, {'knife': 300.0 * DEG, 'jaw': 0.0}, AT_240)
    zones = by_pair(check_moves(shop, moves, AT_240))['zones']
    end = max(move.duration for move in moves.values())
    t, y = dense(moves, end)
    knife_in = np.mod(y['knife'], 2.0 * math.pi) > 320.0 * DEG
    jaw_in = y['jaw'] > 0.06
    both = stretches(knife_in & jaw_in, t)
    assert len(both) == 1
    overlap = both[0][1] - both[0][0]
    assert not zones.ok
    assert -zones.check.value / CAM_SPEED == pytest.approx(overlap, abs=3 * t[1])
    assert zones.time == pytest.approx(both[0][0], abs=3 * t[1])

    found = sequence_moves(shop, moves, AT_240)
    assert isinstance(found, Sequence) and found.order == ('knife', 'jaw'), found
    t, y = dense(found.moves, found.moves['jaw'].duration)
    knife_in = np.mod(y['knife'], 2.0 * math.pi) > 320.0 * DEG
    jaw_in = y['jaw'] > 0.06
    assert not (knife_in & jaw_in).any()
    knife_leaves = stretches(knife_in, t)[-1][1]
    jaw_enters = stretches(jaw_in, t)[0][0]
    margin = by_pair(found.checks)['zones']
    assert margin.ok
    assert margin.check.value / CAM_SPEED == pytest.approx(jaw_enters - knife_leaves,
                                                           abs=3 * t[1])
    assert margin.time == pytest.approx(knife_leaves, abs=3 * t[1])


def test_moves_that_collide_in_every_order_are_refused_naming_the_pair():
    # The pusher at 240 mm and the jaw closed at 80 mm: 10 mm apart before anything moves.
    shop = machine()
    moves = planned(shop, {'feeder': 0.24, 'jaw': 0.08}, MasterMotion(100.0 * DEG))
    found = sequence_moves(shop, moves, MasterMotion(100.0 * DEG))
    assert isinstance(found, str) and '\n' not in found
    assert found.startswith('the moves collide together or one after another: clearance '
                            'feeder-jaw: smallest gap -')
    assert 'mm' in found and 'at 100.00 deg' in found and 'COLLIDES' in found
    assert 's into the moves)' in found


def test_a_move_that_cannot_be_made_is_refused_naming_the_axis():
    shop = machine(**{'knife.slave.max_velocity': 300.0})  # deg/s; the cam peaks at 728
    nominal = CAM_SPEED
    why = plan_moves(shop, {'knife': AxisState(0.0)}, MasterMotion(0.0, nominal))
    assert isinstance(why, str)
    assert why.startswith('axis knife: its cam itself at master speed 10.472 rad/s: velocity ')
    assert 'over slave.max_velocity 5.23599 rad/s (300 deg/s)' in why


def test_with_the_master_turning_the_axes_on_their_cams_keep_the_cycle_checks_figures():
    # The pusher returning onto its cam at cam_speed; the others on theirs: the zone pair's
    # margin (no axis of it moves off its cam) is the cycle check's 70.5368 deg where it falls
    # in the window, or more.
    shop = machine()
    master = MasterMotion(60.0 * DEG, CAM_SPEED)
    moves = planned(shop, {'feeder': 0.1}, master)
    checks = by_pair(check_moves(shop, moves, master))
    assert checks['zones'].ok and checks['zones'].check.value >= 70.5368 * DEG
    end = moves['feeder'].duration + 20.0 * DEG / CAM_SPEED  # and a zone margin's time after
    t, y = dense(moves, end)
    gap = 0.31 - y['feeder'] - y['jaw']
    assert checks['clearance'].check.value == pytest.approx(gap.min(), abs=1e-9)


def test_the_time_margin_of_stretches():
    # a leaves at 1, b enters at 1.5 and leaves at 2, a enters again at 4 (window 0-5)
    a = (np.array([0.0, 4.0]), np.array([1.0, 5.0]))
    b = (np.array([1.5]), np.array([2.0]))
    assert time_margin(a, b, 5.0) == (0.5, 1.0)
    # overlapping: minus the longest overlap, from where it starts
    assert time_margin(a, (np.array([0.5]), np.array([3.0])), 5.0) == (-0.5, 0.5)
    # in the zone from the start and to the end: no entering, no leaving
    assert time_margin((np.array([0.0]), np.array([1.0])), (np.array([2.0]), np.array([5.0])),
                       5.0) == (1.0, 1.0)
    assert time_margin((np.zeros(0), np.zeros(0)), b, 5.0)[0] == math.inf
