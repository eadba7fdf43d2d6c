"""The elastic follower train's parameters: natural frequency, damping ratio, compensation.

See vibration.py for the model and periodic.py for its response at speed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

from ..errors import InvalidParameter


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


def parse_train(values: Mapping[str, Any], inertia: float,
                inertia_name: str) -> Optional[TrainConfig]:
    """Return the train of checked flat values, None without a frequency or a stiffness.

    inertia is the follower's mass (kg) or arm inertia (kg m^2) named inertia_name, needed to
    turn dynamics.train_stiffness into a frequency: fn = sqrt(k / m) / (2 pi).
    """
    frequency = values['dynamics.train_natural_frequency']
    stiffness = values['dynamics.train_stiffness']
    if frequency and stiffness:
        raise InvalidParameter('dynamics.train_stiffness', stiffness,
                               'give dynamics.train_natural_frequency or '
                               'dynamics.train_stiffness, not both')
    if stiffness:
        if not inertia:
            raise InvalidParameter('dynamics.train_stiffness', stiffness,
                                   f'needs {inertia_name} to give a natural frequency (or give '
                                   'dynamics.train_natural_frequency instead)')
        frequency = math.sqrt(stiffness / inertia) / (2.0 * math.pi)
    compensate = values['dynamics.compensate']
    if not frequency:
        if compensate:
            raise InvalidParameter('dynamics.compensate', compensate,
                                   'needs the follower train: give '
                                   'dynamics.train_natural_frequency or dynamics.train_stiffness')
        return None
    return TrainConfig(frequency, values['dynamics.train_damping_ratio'], compensate)
