"""Evaluate requests at the edges: refused with a reason, or answered exactly; never a crash.

Any finite angle is a valid cam angle (taken modulo 2 pi, which is exact in floating point even
for 1e300 rad), so extreme finite values must be answered like the core answers them. Empty,
non-finite and over-cap batches get success false, a reason naming what is wrong, and no data.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from .support import (assert_serves, DEFAULT, design_with, evaluate, RESPONSE_FIELDS,
                      SAMPLE_ANGLES)

#: The batch cap of the short run (the heavy run uses the default cap, 1e6, i.e. 8 MB requests).
SHORT_RUN_CAP = 1000
DEFAULT_CAP = 1_000_000
BIG_CALL_TIMEOUT_S = 60.0
TINY = 5e-324  # smallest subnormal
HUGE = sys.float_info.max
EXTREME_ANGLES = [1e300, -1e300, HUGE, -HUGE, TINY, -TINY, -0.0, 2 * math.pi, -2 * math.pi,
                  1e16, -1e-17, 123456789.123, math.pi * 2 ** 60]


def refused(cap: int) -> list[tuple[str, list[float], str]]:
    """Return (id, angles, fragment of the reason) of requests that must be refused."""
    return [
        ('empty', [], 'angles is empty: give at least one cam angle (rad)'),
        ('nan', [math.nan], 'angles[0] = '),
        ('nan_later', [0.1, 0.2, math.nan], 'angles[2] = '),
        ('plus_inf', [math.inf], 'must be a finite angle (rad)'),
        ('minus_inf', [1.0, -math.inf], 'angles[1] = '),
        ('over_cap', [0.5] * (cap + 1), f'angles has {cap + 1} entries: more than '
                                        f'output.max_batch = {cap}; split the request'),
        ('over_cap_and_nan', [math.nan] * (cap + 1), f'output.max_batch = {cap}'),
    ]


def test_bad_requests_are_refused_and_extreme_angles_answered(start_cam_node, effort, report):
    cap = DEFAULT_CAP if effort.heavy else SHORT_RUN_CAP
    process, client = start_cam_node(DEFAULT, '-p', f'output.max_batch:={cap}')
    design = design_with(**{'output.max_batch': cap})
    cases = refused(cap)
    for name, angles, fragment in cases:
        response = evaluate(client, angles, timeout=BIG_CALL_TIMEOUT_S)
        assert not response.success, name
        assert fragment in response.message, (name, response.message)
        assert all(len(getattr(response, field)) == 0 for field in RESPONSE_FIELDS), name
        assert_serves(evaluate(client, SAMPLE_ANGLES), design)

    # Extreme but finite angles are cam angles like any other.
    assert_serves(evaluate(client, EXTREME_ANGLES), design, EXTREME_ANGLES)
    wrapped = np.mod(np.array(EXTREME_ANGLES), 2 * math.pi)
    assert_serves(evaluate(client, wrapped), design, wrapped)
    # Exactly the cap is allowed.
    full = np.linspace(-10.0, 10.0, cap)
    response = evaluate(client, full, timeout=BIG_CALL_TIMEOUT_S)
    assert_serves(response, design, full)
    assert response.message == f'{cap} angles evaluated'
    assert process.process.poll() is None
    report('refused evaluate requests', len(cases))
    report('batch cap tested', cap)
