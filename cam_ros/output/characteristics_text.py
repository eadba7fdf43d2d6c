"""The design's characteristic values as header lines of a cam table file.

One line per segment: the smallest and largest slave position, velocity, acceleration and jerk
per master degree (master velocity 1) and the master angle (deg) of each, from
core.ecam.characteristics.  A largest value is rounded up and a smallest one down (6
significant digits), so the printed range always holds the true one; a quantity the law holds
constant over the segment is printed once, as the law gives it (6 significant digits). Angles
are printed to 1e-9 deg: a flat extreme found 1e-11 deg from 0 is at 0.
"""
from __future__ import annotations

import math

from cam_ros.core import CamDesign
from cam_ros.core.ecam.characteristics import characteristics, QUANTITIES
from cam_ros.core.rounding import ceil_sig, floor_sig

DEGREE = math.pi / 180.0


def characteristic_notes(design: CamDesign) -> list[str]:
    """Return one note per segment with its refined extremes in the file's units (per deg)."""
    unit, factor = design.config.file_position_unit
    units = [unit] + [f'{unit}/deg' + (f'^{order}' if order > 1 else '') for order in (1, 2, 3)]
    notes = ['characteristic values (as MC_TableCharacValues): per segment the min and max of '
             'slave position, velocity, acceleration and jerk per master degree (master '
             'velocity 1) @ the master angle in deg; refined on the exact law, min rounded down '
             'and max up; an acceleration jump is an unbounded jerk, not listed']
    for segment in characteristics(design.program):
        parts = []
        for order, (name, low, high) in enumerate(zip(QUANTITIES, segment.minimum,
                                                      segment.maximum)):
            scale = factor * DEGREE ** order
            if low.value == high.value:  # constant on the segment: the law's one value
                parts.append(f'{name} {low.value * scale + 0.0:.6g} {units[order]} (constant)')
                continue
            parts.append(f'{name} {floor_sig(low.value * scale)} @ {_deg(low.angle)} .. '
                         f'{ceil_sig(high.value * scale)} @ {_deg(high.angle)} {units[order]}')
        notes.append(f'segment {segment.number} {segment.law} {_deg(segment.start)}-'
                     f'{_deg(segment.end)} deg: ' + '; '.join(parts))
    return notes


def _deg(angle: float) -> str:
    """Return a master angle (rad) in deg to 1e-9 deg, 10 significant digits at most."""
    return f'{round(math.degrees(angle), 9) + 0.0:.10g}'
