"""Hertz line contact between a cam and its roller or flat face (two parallel cylinders).

For cylinders of radii R1, R2 pressed together by a load per unit length w (N/m):

* curvature sum K = 1/R1 + 1/R2 (1/m), a radius signed negative for a concave surface and
  1/R = 0 for a flat face; the effective radius is R' = 1/K;
* effective modulus E* from 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2;
* contact half-width b = sqrt(4 w / (pi E* K)) and peak pressure p0 = 2 w / (pi b)
  = sqrt(w E* K / pi).

So a concave cam surface (K smaller) lowers the stress. K <= 0 is no Hertz contact at all (an
undercut cam: the surface is concave more tightly than the roller, or a flat face meets a cusp);
there p0 and b are NaN. A load <= 0 (no contact) gives p0 = b = 0.
"""
from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]

#: Young's modulus (Pa) and Poisson's ratio of steel, the default of both bodies.
STEEL_MODULUS = 207e9
STEEL_POISSON = 0.3


def effective_modulus(modulus_1: float, poisson_1: float, modulus_2: float,
                      poisson_2: float) -> float:
    """Return E* (Pa) of two elastic bodies: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2."""
    return 1.0 / ((1.0 - poisson_1 ** 2) / modulus_1 + (1.0 - poisson_2 ** 2) / modulus_2)


def _hertz(load_per_width: npt.ArrayLike, curvature_sum: npt.ArrayLike, scale: float,
           inverse: bool) -> Array:
    """Return sqrt(scale * w * K) (or sqrt(scale * w / K)), NaN where K <= 0, 0 where w <= 0."""
    load = np.maximum(np.asarray(load_per_width, dtype=float), 0.0)
    curvature = np.asarray(curvature_sum, dtype=float)
    with np.errstate(divide='ignore', invalid='ignore'):
        value = np.sqrt(scale * load * (1.0 / curvature if inverse else curvature))
    return np.where(curvature > 0.0, value, np.nan)


def peak_pressure(load_per_width: npt.ArrayLike, curvature_sum: npt.ArrayLike,
                  modulus: float) -> Array:
    """Return p0 = sqrt(w E* K / pi) (Pa) of line contacts; arrays broadcast.

    load_per_width w (N/m; <= 0: no contact, p0 = 0), curvature_sum K = 1/R1 + 1/R2 (1/m),
    modulus E* (Pa).
    """
    return _hertz(load_per_width, curvature_sum, modulus / math.pi, inverse=False)


def half_width(load_per_width: npt.ArrayLike, curvature_sum: npt.ArrayLike,
               modulus: float) -> Array:
    """Return the contact half-width b = sqrt(4 w / (pi E* K)) (m); arguments as peak_pressure."""
    return _hertz(load_per_width, curvature_sum, 4.0 / (math.pi * modulus), inverse=True)
