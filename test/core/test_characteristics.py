"""A segment's characteristic values (MC_TableCharacValues) against independent references.

The cycloids of config/machine.yaml's pusher against their closed forms, the constant laws at
their segment's start, and every segment of the shipped machine and single cams against a dense
scan of the law: each extreme no further than the scan's, where the law takes that value.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design_from_config import build_design
from cam_ros.core.ecam.characteristics import characteristics, QUANTITIES
from cam_ros.core.machine import load_machine
from cam_ros.core.motion.segment import segment_values, segment_values_at

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
MACHINE = load_machine(CONFIG_DIR / 'machine.yaml')
DEG = math.pi / 180.0
TWO_PI = 2.0 * math.pi


def cycloid(h: float, beta: float, u: np.ndarray) -> np.ndarray:
    """Return s, ds, d2s, d3s (per rad) of a cycloidal travel h over beta rad at u, written out."""
    return np.array([h * (u - np.sin(TWO_PI * u) / TWO_PI),
                     h / beta * (1.0 - np.cos(TWO_PI * u)),
                     TWO_PI * h / beta ** 2 * np.sin(TWO_PI * u),
                     TWO_PI ** 2 * h / beta ** 3 * np.cos(TWO_PI * u)])


@pytest.mark.parametrize('number, start_deg, span_deg, s0, h', [
    (0, 0.0, 140.0, 0.0, 0.2),      # forward 200 mm over 0-140 deg
    (2, 200.0, 120.0, 0.2, -0.2),   # back over 200-320 deg
])
def test_a_cycloid_has_the_extremes_of_its_closed_form_where_they_are(
        number, start_deg, span_deg, s0, h):
    segment = characteristics(MACHINE.axis('feeder').design.program)[number]
    start, beta = start_deg * DEG, span_deg * DEG
    assert (segment.number, segment.law) == (number, 'cycloidal')
    assert segment.start == pytest.approx(start, abs=1e-12)
    assert segment.end == pytest.approx(start + beta, abs=1e-12)
    u = np.linspace(0.0, 1.0, 1_000_001)
    values = cycloid(h, beta, u)
    values[0] += s0
    for order, name in enumerate(QUANTITIES):
        low, high = segment.minimum[order], segment.maximum[order]
        scale = abs(h) / beta ** order
        assert low.value == pytest.approx(values[order].min(), abs=1e-12 * scale), name
        assert high.value == pytest.approx(values[order].max(), abs=1e-12 * scale), name
        for extreme in (low, high):  # the law takes the value there, inside the segment
            at = (extreme.angle - start) / beta
            assert -1e-12 <= at <= 1.0 + 1e-12, name
            there = cycloid(h, beta, np.array([at]))[order, 0] + (s0 if order == 0 else 0.0)
            assert there == pytest.approx(extreme.value, abs=1e-9 * scale), name
    # Where the extremes are unique: the peak velocity at mid-span, the peak accelerations a
    # quarter from either end, the jerk's peak of opposite sign to the ends' at mid-span.
    rising = h > 0
    velocity = segment.maximum[1] if rising else segment.minimum[1]
    assert velocity.angle == pytest.approx(start + beta / 2, abs=1e-7)
    assert segment.maximum[2].angle == pytest.approx(start + beta * (0.25 if rising else 0.75),
                                                     abs=1e-7)
    assert segment.minimum[2].angle == pytest.approx(start + beta * (0.75 if rising else 0.25),
                                                     abs=1e-7)
    jerk = segment.minimum[3] if rising else segment.maximum[3]
    assert jerk.angle == pytest.approx(start + beta / 2, abs=1e-7)
    first, last = (segment.minimum[0], segment.maximum[0])[::1 if rising else -1]
    assert (first.angle, last.angle) == pytest.approx((start, start + beta), abs=1e-9)


@pytest.mark.parametrize('axis, number, constant', [
    ('feeder', 1, (0.2, 0.0, 0.0, 0.0)),        # the dwell at 200 mm
    ('jaw', 0, (0.0, 0.0, 0.0, 0.0)),
    ('knife', 0, (None, 0.8, 0.0, 0.0)),        # 5 deg of knife over 6.25 deg of machine
])
def test_a_quantity_the_law_holds_constant_is_its_value_at_the_segment_start(
        axis, number, constant):
    segment = characteristics(MACHINE.axis(axis).design.program)[number]
    for order, value in enumerate(constant):
        if value is None:
            continue
        for extreme in (segment.minimum[order], segment.maximum[order]):
            assert extreme.value == pytest.approx(value, abs=1e-12)
            assert extreme.angle == segment.start
    if constant[0] is None:  # the knife's line: from 0 at its start to 5 deg at its end
        assert (segment.minimum[0].value, segment.minimum[0].angle) == (0.0, 0.0)
        assert segment.maximum[0].value == pytest.approx(5.0 * DEG, abs=1e-15)
        assert segment.maximum[0].angle == pytest.approx(6.25 * DEG, abs=1e-15)


def programs():
    """Return (name, program) of every shipped design: the machine's axes and single cams."""
    found = [(name, MACHINE.axis(name).design.program) for name in MACHINE.config.names]
    for name in ('default', 'polydyne', 'handbook_4567', 'flying_shear'):
        values = read_parameters_file(CONFIG_DIR / f'{name}.yaml')
        found.append((name, build_design(parse_parameters(values)).program))
    return found


@pytest.mark.parametrize('name, program', programs(), ids=[name for name, _ in programs()])
def test_every_extreme_is_the_dense_scans_or_beyond_it_where_the_law_takes_it(name, program):
    u = np.linspace(0.0, 1.0, 200_001)
    found = characteristics(program)
    assert [segment.number for segment in found] == list(range(len(program.segments)))
    for segment, source in zip(found, program.segments):
        assert (segment.law, segment.start, segment.end) == (source.law.name, source.start,
                                                             source.end)
        values = segment_values(source, u)
        scan = np.stack([values.y, values.y1, values.y2, values.y3])
        for order, quantity in enumerate(QUANTITIES):
            low, high = segment.minimum[order], segment.maximum[order]
            size = max(np.abs(scan[order]).max(), abs(source.stroke) / source.span ** order)
            tie = 1e-12 * size
            assert scan[order].min() - 1e-7 * size <= low.value <= scan[order].min() + tie
            assert scan[order].max() - tie <= high.value <= scan[order].max() + 1e-7 * size
            if scan[order].min() == scan[order].max():  # constant: at the start
                assert low.angle == high.angle == source.start, (name, quantity)
            for extreme in (low, high):
                at = (extreme.angle - source.start) / source.span
                assert -1e-12 <= at <= 1.0 + 1e-12, (name, segment.number, quantity)
                there = segment_values_at(source, min(max(at, 0.0), 1.0))[order]
                assert there == pytest.approx(extreme.value, abs=1e-9 * size), (name, quantity)
