"""Moves checked on a machine (core/machine/move_check.py) where nothing moves, and the time
margin of zone stretches, against references written here.

config/machine.yaml: gap = 310 mm - feeder - jaw >= 15 mm, the pusher a cycloid out over 0-140
deg and back over 200-320 deg; the jaw closed (80 mm) over 220-270 deg, open (0) from 330 deg.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from test_move_check import machine

from cam_ros.core.ecam.moves import MasterMotion
from cam_ros.core.machine.move_check import (check_moves, plan_moves, Sequence, sequence_moves,
                                             time_margin)

DEG = math.pi / 180.0
TWO_PI = 2.0 * math.pi


def test_axes_resting_on_their_cams_are_checked_where_they_stand():
    # The master at rest at 240 deg, no axis moved off its cam: no time to check, the gap is
    # the machine's there (the pusher a third of the way back, the jaw closed), no margin ends.
    shop = machine()
    master = MasterMotion(240.0 * DEG)
    moves = plan_moves(shop, {}, master)
    assert isinstance(moves, dict) and all(move.duration == 0.0 for move in moves.values())
    found = sequence_moves(shop, moves, master)
    assert isinstance(found, Sequence) and found.order == ()  # together: no order
    clearance, zones = found.checks
    u = (240.0 - 200.0) / 120.0
    pusher = 0.2 * (1.0 - (u - math.sin(TWO_PI * u) / TWO_PI))
    assert clearance.check.value == pytest.approx(0.31 - pusher - 0.08, abs=1e-12)
    assert (clearance.time, clearance.ok) == (0.0, True)
    assert clearance.check.at == pytest.approx(240.0 * DEG, abs=1e-12)
    assert zones.check.value == math.inf and zones.ok
    assert zones.line('mm') == ('zones jaw-knife: never both in the zone, and no axis enters it '
                                'after the other leaves: limit >= 20 deg: ok')


def test_a_gap_exactly_at_its_limit_keeps_it():
    # At 340 deg both rest at 0: the gap is the offset, 310 mm, and so is the limit.
    shop = machine(**{'interference.min_clearance': [310.0, 0.0]})
    master = MasterMotion(340.0 * DEG)
    clearance = check_moves(shop, plan_moves(shop, {}, master), master)[0]
    assert clearance.check.value == shop.config.interference[0].min_clearance
    assert clearance.ok


def dense_margin(a, b, end: float, samples: int = 200_001) -> float:
    """Return the time margin of stretches on a dense time grid: the least time from a sample
    where one leaves its zone (inside, then outside; not at the window's end) to the next where
    the other enters (outside, then inside; not at the start); minus the longest run of both."""
    t = np.linspace(0.0, end, samples)
    inside = [np.any((t[:, None] >= s[0]) & (t[:, None] <= s[1]), axis=1)
              for s in (a, b)]
    both = inside[0] & inside[1]
    if both.any():
        runs = np.diff(np.flatnonzero(np.diff(np.concatenate(([0], both, [0])))))[::2]
        return -(runs.max() - 1) * t[1]
    best = math.inf
    for one, other in ((inside[0], inside[1]), (inside[1], inside[0])):
        leaves = np.flatnonzero(one[:-1] & ~one[1:])
        enters = np.flatnonzero(~other[:-1] & other[1:]) + 1
        for leave in leaves:
            later = enters[enters > leave]
            if later.size:
                best = min(best, (later[0] - leave) * t[1])
    return best


@pytest.mark.parametrize('seed', range(12))
def test_the_time_margin_of_stretches_is_a_dense_scans(seed):
    rng = np.random.default_rng(seed)
    end = 10.0
    edges = np.sort(rng.uniform(0.0, end, 8))  # stretches of a and b, apart or overlapping
    if seed % 3 == 0:
        edges[0] = 0.0  # one in its zone from the start
    if seed % 4 == 1:
        edges[-1] = end  # one in it to the end
    cut = [edges[0:2], edges[2:4], edges[4:6], edges[6:8]]
    owners = rng.permutation([0, 0, 1, 1]) if seed % 2 else np.array([0, 1, 0, 1])
    a = tuple(np.array([piece[k] for piece, o in zip(cut, owners) if o == 0]) for k in (0, 1))
    b = tuple(np.array([piece[k] for piece, o in zip(cut, owners) if o == 1]) for k in (0, 1))
    margin, _ = time_margin(a, b, end)
    reference = dense_margin(a, b, end)
    if reference == math.inf:
        assert margin == math.inf
    else:
        assert margin == pytest.approx(reference, abs=2.5 * end / 200_000)
