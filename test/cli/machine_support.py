"""The shipped machine (config/machine.yaml) written out independently of the code under test.

The feeder's cycloids and the jaw's modified sines in closed form, the knife through its own
program (the core's, tested in test/core) coupled by MC_CamIn written out here; the interference
figures by a dense scan refined by scipy's root finder and bounded minimiser.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import numpy as np
import yaml
from cli_support import CONFIG_DIR
from scipy.optimize import brentq, minimize_scalar

from cam_ros.core.machine import load_machine

MACHINE = CONFIG_DIR / 'machine.yaml'
TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
CAM_SPEED = 10.471975511965978
NAMES = ('feeder', 'knife', 'jaw')
MM = 1e-3
#: The knife's coupling: master offset 100 deg, slave offset -20 deg, a turn per cycle.
KNIFE_MASTER_OFFSET, KNIFE_SLAVE_OFFSET = 100.0 * DEG, -20.0 * DEG
SCAN = 200001  # dense scan points over one machine cycle


def cycloidal(u: np.ndarray) -> np.ndarray:
    """Return the cycloidal rise fraction at u in [0, 1]."""
    return u - np.sin(TWO_PI * u) / TWO_PI


def modified_sine(u: np.ndarray) -> np.ndarray:
    """Return the modified-sine rise fraction at u in [0, 1] (Norton's three pieces)."""
    k = 4.0 + math.pi
    middle = 2.0 / k + math.pi * u / k - 9.0 * np.sin(math.pi * (1.0 + 4.0 * u) / 3.0) / (4 * k)
    ends = np.where(u <= 0.125, 0.0, 4.0 / k) + math.pi * u / k - np.sin(4 * math.pi * u) / (
        4 * k)
    return np.where((u > 0.125) & (u < 0.875), middle, ends)


def feeder_s(theta: np.ndarray) -> np.ndarray:
    """Return the pusher's position (m) at its cam angle (rad in [0, 2 pi))."""
    d = np.degrees(theta)
    return 0.2 * (cycloidal(np.clip(d / 140.0, 0.0, 1.0))
                  - cycloidal(np.clip((d - 200.0) / 120.0, 0.0, 1.0)))


def jaw_s(theta: np.ndarray) -> np.ndarray:
    """Return the jaw's position (m) at its cam angle (rad in [0, 2 pi))."""
    d = np.degrees(theta)
    return 0.08 * (modified_sine(np.clip((d - 150.0) / 70.0, 0.0, 1.0))
                   - modified_sine(np.clip((d - 270.0) / 60.0, 0.0, 1.0)))


def knife_s() -> Callable[[np.ndarray], np.ndarray]:
    """Return the knife's cam s(theta) (rad) over its cam angle, from its program."""
    program = load_machine(MACHINE).axis('knife').design.program
    return lambda theta: np.asarray(program.evaluate(np.mod(theta, TWO_PI)).s, dtype=float)


def coupled(q: np.ndarray, s: Callable[[np.ndarray], np.ndarray], master_offset: float = 0.0,
            slave_offset: float = 0.0, advance: float = 0.0) -> np.ndarray:
    """MC_CamIn: theta = (q - q0) mod 2 pi, y = s(theta) + advance per whole turn + y0."""
    turns = q - master_offset
    return s(np.mod(turns, TWO_PI)) + advance * np.floor(turns / TWO_PI) + slave_offset


def reference_positions(q: np.ndarray, knife: Callable | None = None) -> dict[str, np.ndarray]:
    """Return each shipped axis's commanded position (SI) at machine angles q (rad)."""
    knife = knife or knife_s()
    return {'feeder': coupled(q, feeder_s),
            'knife': coupled(q, knife, KNIFE_MASTER_OFFSET, KNIFE_SLAVE_OFFSET, TWO_PI),
            'jaw': coupled(q, jaw_s)}


def smallest(f: Callable[[np.ndarray], np.ndarray], q: np.ndarray) -> tuple[float, float]:
    """Return the minimum of f over a cycle and where: dense scan, then a bounded minimiser."""
    values = f(q)
    index = int(np.argmin(values))
    step = q[1] - q[0]
    found = minimize_scalar(lambda x: float(f(np.array([x]))[0]), method='bounded',
                            bounds=(q[index] - step, q[index] + step),
                            options={'xatol': 1e-13})
    return min(float(found.fun), float(values[index])), float(found.x) % TWO_PI


def crossings(f: Callable[[np.ndarray], np.ndarray], q: np.ndarray) -> tuple[np.ndarray, ...]:
    """Return the machine angles where f goes above 0 and where it goes below (brentq)."""
    values = f(q)
    up = np.flatnonzero((values[:-1] <= 0.0) & (values[1:] > 0.0))
    down = np.flatnonzero((values[:-1] > 0.0) & (values[1:] <= 0.0))

    def root(i: int) -> float:
        return brentq(lambda x: float(f(np.array([x]))[0]), q[i], q[i + 1], xtol=1e-14)
    return (np.array([root(i) for i in up]) % TWO_PI,
            np.array([root(i) for i in down]) % TWO_PI)


def edited_machine(directory: Path, name: str, edit: Callable[[dict[str, Any]], None]) -> Path:
    """Write the shipped machine after edit(parameters) changed it; return its path."""
    data = yaml.safe_load(MACHINE.read_text())
    edit(data['/**']['ros__parameters'])
    path = directory / f'{name}.yaml'
    path.write_text(yaml.safe_dump(data))
    return path
