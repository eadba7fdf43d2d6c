"""Lengths and angles a user types: a number in the config's unit, or a number with its unit.

`0.01` is in the config's `length_unit` (deg for an oscillating follower's arm angle); `0.01mm`,
`10um`, `1e-5m`, `0.1deg` carry their own unit. Values come back in SI (m or rad).
"""
from __future__ import annotations

import math
import re

from ..errors import InvalidParameter
from .parameters import LENGTH_UNITS

#: Every length unit a typed value may carry, in metres.
TYPED_LENGTHS = {**LENGTH_UNITS, 'um': 1e-6, 'µm': 1e-6}
#: Every angle unit a typed value may carry, in radians.
TYPED_ANGLES = {'deg': math.pi / 180.0, 'rad': 1.0}
_QUANTITY = re.compile(r'\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-zµ]*)\s*')


def split_quantity(parameter: str, text: str) -> tuple[float, str]:
    """Return (number, unit suffix or '') of a typed quantity, or raise naming the parameter."""
    match = _QUANTITY.fullmatch(text)
    units = ', '.join((*TYPED_LENGTHS, *TYPED_ANGLES))
    if match is None or not math.isfinite(float(match.group(1))):
        raise InvalidParameter(parameter, text, f'must be a finite number, optionally with a '
                                                f'unit ({units})')
    number, unit = float(match.group(1)), match.group(2)
    if unit and unit not in TYPED_LENGTHS and unit not in TYPED_ANGLES:
        raise InvalidParameter(parameter, text, f'has an unknown unit {unit!r} (one of {units})')
    return number, unit


def typed_quantity(parameter: str, text: str, length_unit: str, angular: bool) -> float:
    """Return a typed length (angle when angular) in SI: m, or rad.

    A bare number is in length_unit, or in deg when angular; a suffix must be of the same kind.
    """
    number, unit = split_quantity(parameter, text)
    table, kind = (TYPED_ANGLES, 'an angle') if angular else (TYPED_LENGTHS, 'a length')
    bare = 'deg' if angular else length_unit
    unit = unit or bare
    if unit not in table:
        raise InvalidParameter(parameter, text, f'must be {kind} here ({", ".join(table)}, or '
                                                f'a bare number in {bare})')
    return number * table[unit]
