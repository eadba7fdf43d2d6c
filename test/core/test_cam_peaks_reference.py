"""A cam's peaks at a master speed and acceleration against a dense scan of the chain rule, and
what a one-way axis's refusal says of the way it would move."""
from __future__ import annotations

import numpy as np
import pytest

from cam_ros.core.ecam.slave_limits import AxisUnit, CamPeaks, Peaks, SlaveLimits

from line_shaft_support import line

KNIFE = line().cams[1]


@pytest.mark.parametrize('omega, alpha', [(10.0, 0.0), (10.0, 40.0), (-6.0, -25.0)])
def test_a_cams_acceleration_peak_bounds_the_chain_rule_on_the_safe_side(omega, alpha):
    # a = y'' w^2 + y' alpha: max |a| <= max |y''| w^2 + max |y'| |alpha| (the bound), equal at
    # constant speed; the bound from a dense scan of y' and y'' (refined peaks within 1e-6).
    q = KNIFE.mapping.master_offset + np.linspace(0.0, 2 * np.pi, 2_000_001)
    d = KNIFE.derivatives(q)
    steepest, bend = np.abs(d.dy).max(), np.abs(d.d2y).max()
    peaks = CamPeaks.of(KNIFE).at(omega, alpha, 1)
    bound = bend * omega ** 2 + steepest * abs(alpha)
    assert peaks.acceleration == pytest.approx(bound, rel=1e-6)
    assert peaks.acceleration >= np.abs(d.d2y * omega ** 2 + d.dy * alpha).max() * (1 - 1e-9)
    assert peaks.velocity == pytest.approx(steepest * abs(omega), rel=1e-6)


@pytest.mark.parametrize('direction, way', [(1, 'negative'), (-1, 'positive')])
def test_a_one_way_axis_against_its_direction_is_said_to_move_the_other_way(direction, way):
    said = Peaks(0.0, 0.0, 0.25).excess(SlaveLimits(direction=direction), AxisUnit())
    assert said == f'moves {way} at 0.25 m/s against slave.direction'
