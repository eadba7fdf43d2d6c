"""
Keep a slave's commands within what its axis can do: velocity and acceleration limits, one
direction of motion, and the whole turns of a rotary slave.

A path y(q) of the master position q commands, at master speed omega and acceleration alpha,

    v = y'(q) omega        a = y''(q) omega^2 + y'(q) alpha

so a cam's peaks at a speed follow from its peaks per rad of master (CamPeaks, refined once per
cam: max |v| = max |y'| |omega| exactly, max |a| <= max |y''| omega^2 + max |y'| |alpha|, exact
at constant master speed and on the safe side otherwise).

Moves off the cam (moves.py) are planned PLAN_MARGIN below each limit. A rotary slave
(length_unit deg) joins the cam at a whole number of turns from its own position: the nearest, or
in the allowed direction when the nearest cannot be reached without turning back.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from ..cam_angles import TWO_PI
from ..config.parameters import UNITS
from ..config.schema import CamConfig
from ..extremes import refine_extrema
from .master import ElectronicCam

#: Grid of a peak search: samples per rad of cam angle travelled (0.1 deg), and the fewest.
SAMPLES_PER_RAD, FEWEST_SAMPLES = 180.0 / math.pi / 0.1, 512
#: Moves are planned this fraction below each limit: more than a refined peak's error.
PLAN_MARGIN = 1e-6
#: Velocity (m/s or rad/s) against slave.direction that counts as none (round-off in a dwell).
BACKWARD_TOLERANCE = 1e-9
DIRECTIONS = {'any': 0, 'positive': 1, 'negative': -1}


@dataclass(frozen=True)
class SlaveLimits:
    """slave.max_velocity, .max_acceleration, .max_jerk (SI, 0: none), .direction, the turn."""

    max_velocity: float = 0.0  # m/s or rad/s
    max_acceleration: float = 0.0  # m/s^2 or rad/s^2
    direction: int = 0  # +1 positive only, -1 negative only, 0 any
    turn: float = 0.0  # a rotary slave's turn (2 pi rad); 0 for any other
    max_jerk: float = 0.0  # m/s^3 or rad/s^3, of moves off the cam

    @classmethod
    def from_config(cls, config: CamConfig) -> 'SlaveLimits':
        """Read the (already checked) slave.* parameters in the axis's unit."""
        values = config.parameters
        unit = math.radians(1.0) if config.oscillating else UNITS[config.length_unit]

        def si(name: str) -> float:
            """A limit in SI: a positive one stays positive (only 0 means none), however small."""
            value = values[name]
            return max(value * unit, math.ulp(0.0)) if value > 0.0 else 0.0

        return cls(si('slave.max_velocity'), si('slave.max_acceleration'),
                   DIRECTIONS[values['slave.direction']],
                   TWO_PI if config.length_unit == 'deg' else 0.0, si('slave.max_jerk'))

    @property
    def limited(self) -> bool:
        """Say whether any limit or a direction is set."""
        return bool(self.max_velocity or self.max_acceleration or self.direction)


class AxisUnit(NamedTuple):
    """How an axis's values are said: in SI and in the config's unit (name, per SI unit)."""

    si: str = 'm'
    name: str = 'm'
    per_si: float = 1.0

    @classmethod
    def of(cls, config: CamConfig) -> 'AxisUnit':
        """Return the unit of a design's slave positions."""
        return cls(config.position_unit, *config.file_position_unit)

    def say(self, value: float, per: str = '') -> str:
        """Return a value (SI) with its unit, and in the config's unit beside when it differs."""
        text = f'{value:.6g} {self.si}{per}'
        if self.name == self.si:
            return text
        return f'{text} ({value * self.per_si:.6g} {self.name}{per})'


class Peaks(NamedTuple):
    """A command's largest |velocity|, |acceleration| and velocity against the direction."""

    velocity: float
    acceleration: float
    backward: float  # largest velocity against slave.direction (<= 0: never backward)

    def excess(self, limits: SlaveLimits, unit: AxisUnit) -> str:
        """Say which limits these peaks exceed ('' if none), with the figures."""
        over = []
        if limits.max_velocity and self.velocity > limits.max_velocity:
            over.append(f'velocity {unit.say(self.velocity, "/s")} over slave.max_velocity '
                        f'{unit.say(limits.max_velocity, "/s")}')
        if limits.max_acceleration and self.acceleration > limits.max_acceleration:
            over.append(f'acceleration {unit.say(self.acceleration, "/s^2")} over '
                        f'slave.max_acceleration {unit.say(limits.max_acceleration, "/s^2")}')
        if limits.direction and self.backward > BACKWARD_TOLERANCE:
            way = 'negative' if limits.direction > 0 else 'positive'
            over.append(f'moves {way} at {unit.say(self.backward, "/s")} against '
                        f'slave.direction')
        return '; '.join(over)


@dataclass(frozen=True)
class CamPeaks:
    """A cam's extremes per rad of master over a cycle: y' (least, most) and max |y''|."""

    slope: tuple[float, float]
    curvature: float

    @classmethod
    def of(cls, cam: ElectronicCam) -> 'CamPeaks':
        """Refine the cam's extremes over one master cycle."""
        low = cam.mapping.master_offset
        high = low + TWO_PI * cam.mapping.master_scaling
        (least, _), (most, _), (bend, _) = _refined(
            lambda q: _slopes(cam, q), low, high, ('min', 'max', 'max'), cam.breaks(low, high),
            cam)
        return cls((least, most), bend)

    def at(self, omega: float, alpha: float, direction: int) -> Peaks:
        """Return the cam's peaks at a master speed and acceleration (see the module)."""
        steepest = max(-self.slope[0], self.slope[1])
        against = max(-direction * self.slope[0] * omega, -direction * self.slope[1] * omega)
        return Peaks(steepest * abs(omega), self.curvature * omega * omega
                     + steepest * abs(alpha), against)


def _slopes(cam: ElectronicCam, q: np.ndarray) -> np.ndarray:
    """Return rows y', y', |y''| of a cam at master positions q (per rad of master)."""
    d = cam.derivatives(q)
    return np.array([d.dy, d.dy, np.abs(d.d2y)])


def _refined(func, low: float, high: float, kinds: tuple[str, ...], breaks: np.ndarray,
             cam: ElectronicCam) -> list[tuple[float, float]]:
    """Refine the extremes of func's rows over master positions [low, high] (see extremes)."""
    count = max(FEWEST_SAMPLES, math.ceil((high - low) / cam.mapping.master_scaling
                                          * SAMPLES_PER_RAD))
    q = np.unique(np.concatenate([np.linspace(low, high, count + 1), breaks]))
    return refine_extrema(func, q, func(q), kinds, breaks=breaks, period=None)


def shifted(cam: ElectronicCam, turns: int, limits: SlaveLimits) -> ElectronicCam:
    """Return the cam moved by whole turns of a rotary slave (itself for other slaves)."""
    if not turns or not limits.turn:
        return cam
    mapping = cam.mapping
    return ElectronicCam(cam.program, replace(mapping, slave_offset=mapping.slave_offset
                                              + turns * limits.turn))


def join_turns(cam: ElectronicCam, q0: float, position: float,
               limits: SlaveLimits) -> list[int]:
    """
    Return the whole slave turns to try, best first, for joining the cam from position at q0.

    The nearest; with a direction, also the nearest ahead of the slave in that direction (with
    the master at rest the only one it can reach without turning back: moves.plan_move refuses
    the other).
    """
    if not limits.turn:
        return [0]
    behind = (position - float(cam.derivatives(q0).y)) / limits.turn
    nearest = round(behind)
    if not limits.direction:
        return [nearest]
    ahead = math.ceil(behind) if limits.direction > 0 else math.floor(behind)
    return [ahead] if ahead == nearest else [nearest, ahead]
