"""Cam angles: one taken modulo a turn, a request's checked, angles printed in degrees."""
from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

TWO_PI = 2.0 * math.pi


def cam_degrees(angle: float, digits: int = 9, end: bool = False) -> float:
    """Return a cam angle (rad) in degrees rounded to digits: in [0, 360), or (0, 360] for an end.

    A position just short of a full turn reads 0, never 360; the end of a span reaching the
    full turn reads 360.
    """
    degrees = round(math.degrees(angle), digits) % 360.0
    return 360.0 if end and degrees == 0.0 else degrees


def cam_angles(angles: npt.ArrayLike) -> np.ndarray:
    """Return angles (rad) as a new float array taken modulo 2 pi (np.mod only when needed)."""
    theta = np.asarray(angles, dtype=float)
    if theta.size and 0.0 <= theta.min() and theta.max() < TWO_PI:  # NaN fails: np.mod
        return theta + 0.0  # a copy, -0.0 made 0.0 as np.mod does
    return np.mod(theta, TWO_PI)


def cam_angle(angle: float) -> float:
    """Return one angle (rad) modulo 2 pi: cam_angles' number, as a float."""
    return angle + 0.0 if 0.0 <= angle < TWO_PI else angle % TWO_PI


def check_angles(angles: np.ndarray, max_batch: int) -> str | None:
    """Return why a batch of requested angles cannot be evaluated, or None if it can."""
    if angles.size == 0:
        return 'angles is empty: give at least one cam angle (rad)'
    if angles.size > max_batch:
        return (f'angles has {angles.size} entries: more than output.max_batch = {max_batch}; '
                'split the request')
    finite = np.isfinite(angles)
    if not finite.all():
        index = int(np.argmin(finite))
        return f'angles[{index}] = {float(angles[index])!r}: must be a finite angle (rad)'
    return None
