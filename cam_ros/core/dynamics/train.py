"""The elastic follower train's parameters: natural frequency, damping ratio, compensation.

See vibration.py for the model and periodic.py for its response at speed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional


@dataclass(frozen=True)
class TrainConfig:
    """The follower train's lowest natural frequency (Hz, cam side held) and damping ratio.

    compensate: the cam is shaped so that the train's output is the designed motion (polydyne).
    """

    natural_frequency: float
    damping_ratio: float
    compensate: bool = False

    @property
    def omega_n(self) -> float:
        """Return the natural angular frequency (rad/s)."""
        return 2.0 * math.pi * self.natural_frequency


def parse_train(values: Mapping[str, Any], inertia: float) -> Optional[TrainConfig]:
    """Return the train of checked flat values, None without a frequency or a stiffness.

    inertia is the follower's mass (kg) or arm inertia (kg m^2), which turns
    dynamics.train_stiffness into a frequency (train_frequency); the rules across the train's
    parameters are config.schema's.
    """
    frequency = train_frequency(values, inertia)
    if not frequency:
        return None
    return TrainConfig(frequency, values['dynamics.train_damping_ratio'],
                       values['dynamics.compensate'])


def train_frequency(values: Mapping[str, Any], inertia: float) -> float:
    """Return the train's natural frequency (Hz; 0: rigid): given, or sqrt(k / m) / (2 pi)."""
    stiffness = values['dynamics.train_stiffness']
    if stiffness and inertia:
        return math.sqrt(stiffness / inertia) / (2.0 * math.pi)
    return float(values['dynamics.train_natural_frequency'])
