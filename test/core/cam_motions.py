"""Follower motions written out in closed form for the geometry and sizing tests."""
import math

import numpy as np


def cycloidal(theta, start, span, rise):
    """Return s, ds, d2s of a cycloidal rise of height rise over [start, start + span] (rad)."""
    u = (theta - start) / span
    s = rise * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    ds = rise / span * (1 - np.cos(2 * np.pi * u))
    d2s = 2 * np.pi * rise / span ** 2 * np.sin(2 * np.pi * u)
    return s, ds, d2s


def seed_000(theta, rise=0.02):
    """Return s, ds, d2s of seed 000's program (theta in [0, 2 pi] rad).

    Dwell 0-90 deg, cycloidal rise 90-180 deg, dwell to 240 deg, simple harmonic return 240-360.
    """
    s, ds, d2s = (np.zeros_like(theta) for _ in range(3))
    rising = (theta >= math.pi / 2) & (theta <= math.pi)
    s[rising], ds[rising], d2s[rising] = cycloidal(theta[rising], math.pi / 2, math.pi / 2, rise)
    s[(theta > math.pi) & (theta < 4 * math.pi / 3)] = rise
    back = theta >= 4 * math.pi / 3
    span = 2 * math.pi / 3
    x = math.pi * (theta[back] - 4 * math.pi / 3) / span
    s[back] = rise / 2 * (1 + np.cos(x))
    ds[back] = -rise * math.pi / (2 * span) * np.sin(x)
    d2s[back] = -rise * math.pi ** 2 / (2 * span ** 2) * np.cos(x)
    return s, ds, d2s


def rise_return(theta, rise, split=5 * math.pi / 6):
    """Return s, ds, d2s of a cycloidal rise over [0, split] and cycloidal return to 2 pi.

    s, ds and d2s are continuous over the whole turn (no dwell), so finite differences of the
    profile converge everywhere.
    """
    up = theta <= split
    s, ds, d2s = (np.zeros_like(theta) for _ in range(3))
    s[up], ds[up], d2s[up] = cycloidal(theta[up], 0.0, split, rise)
    down = cycloidal(theta[~up], split, 2 * math.pi - split, rise)
    s[~up], ds[~up], d2s[~up] = rise - down[0], -down[1], -down[2]
    return s, ds, d2s
