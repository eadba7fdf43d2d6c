"""Array helpers every part of the core shares: the float array type and validated conversions."""
import math
from typing import Callable

import numpy as np
import numpy.typing as npt

from .errors import InvalidParameter

#: One sample as a float (one requested angle or master message: NumPy's per-call cost on an
#: array of one element would exceed the arithmetic), many as an array: for formulas that serve
#: both.
Values = float | np.ndarray

FloatArray = npt.NDArray[np.float64]
#: Samples per block of a fused array computation: its temporaries stay in a core's L2 cache.
BLOCK = 16384


def finite_float(parameter: str, value: object) -> float:
    """Return value as a finite float, or raise naming the parameter."""
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as err:
        raise InvalidParameter(parameter, value, 'must be a finite number') from err
    if not math.isfinite(number):
        raise InvalidParameter(parameter, value, 'must be a finite number')
    return number


def float_array(parameter: str, values: npt.ArrayLike, rule: str) -> FloatArray:
    """Return values as a float array (no copy when already one), or raise naming the parameter."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError) as err:
        raise InvalidParameter(parameter, values, rule) from err


def checked_array(parameter: str, values: npt.ArrayLike,
                  valid: Callable[[FloatArray], npt.NDArray[np.bool_]], rule: str) -> FloatArray:
    """Return values as a float array, or raise naming the parameter and the first bad value."""
    array = float_array(parameter, values, rule)
    good = valid(array)
    if not np.all(good):
        raise InvalidParameter(parameter, float(array[~good].flat[0]), rule)
    return array
