"""Printed worst cases rounded up: a figure that reads below the truth would understate it."""
from __future__ import annotations

import math
from decimal import Decimal, ROUND_CEILING

#: Significant digits of a printed worst case.
DIGITS = 6


def ceil_sig(value: float, digits: int = DIGITS) -> str:
    """Return value rounded up (toward +inf) to digits significant digits, without exponent.

    The decimal is worked out from the shortest text that reads back as value (its repr), so
    the text read back is never below value (0.1 stays 0.1) and exceeds it by less than one
    unit of its last digit.
    """
    if not math.isfinite(value) or value == 0.0:
        return repr(value + 0.0)
    exact = Decimal(repr(float(value)))
    step = Decimal(1).scaleb(exact.adjusted() - digits + 1)
    text = format(exact.quantize(step, rounding=ROUND_CEILING), 'f')
    return text.rstrip('0').rstrip('.') if '.' in text else text
