"""Printed figures rounded to the safe side of their limit, never the lenient one.

A worst case (a peak, a deviation) is rounded up: a figure that reads below the truth would
understate it. A smallest allowance (a gap, a margin) is rounded down, for the same reason.
"""
from __future__ import annotations

import math
from decimal import Decimal, ROUND_CEILING, ROUND_FLOOR

#: Significant digits of a printed worst case.
DIGITS = 6


def _round_sig(value: float, digits: int, rounding: str) -> str:
    """Return value rounded to digits significant digits in the given direction, no exponent.

    The decimal is worked out from the shortest text that reads back as value (its repr), so
    0.1 stays 0.1 and the text differs from value by less than one unit of its last digit.
    """
    if not math.isfinite(value) or value == 0.0:
        return repr(value + 0.0)
    exact = Decimal(repr(float(value)))
    step = Decimal(1).scaleb(exact.adjusted() - digits + 1)
    text = format(exact.quantize(step, rounding=rounding), 'f')
    return text.rstrip('0').rstrip('.') if '.' in text else text


def ceil_sig(value: float, digits: int = DIGITS) -> str:
    """Return value rounded up (toward +inf) to digits significant digits, without exponent.

    The text read back is never below value and exceeds it by less than one unit of its last
    digit.
    """
    return _round_sig(value, digits, ROUND_CEILING)


def floor_sig(value: float, digits: int = DIGITS) -> str:
    """Return value rounded down (toward -inf) to digits significant digits, without exponent.

    The text read back is never above value (a smallest gap never reads larger than it is) and
    falls short of it by less than one unit of its last digit.
    """
    return _round_sig(value, digits, ROUND_FLOOR)
