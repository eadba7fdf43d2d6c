"""A machine built: every axis's design and its electronic cam on the one master.

The machine angle theta (rad) is the master position; axis i commands

    y_i(theta) = k_i s_i(((theta - q0_i) / m_i) mod 2 pi) + y0_i

(MC_CamIn, see ecam.master): its own master offset q0 and scaling m (1 / m whole: the axis
repeats 1 / m times per machine cycle) and its slave offset y0 and scaling k.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..config.params_file import read_parameters_file
from ..design import CamDesign
from ..design_from_config import build_design
from ..ecam.master import ElectronicCam, Setpoints
from ..errors import InvalidParameter
from .config import axis_index, axis_error, MachineConfig, parse_machine


@dataclass(frozen=True)
class Axis:
    """One axis of a machine: its name (joint name), design and electronic cam."""

    name: str
    design: CamDesign
    cam: ElectronicCam


@dataclass(frozen=True, eq=False)
class Machine:
    """Every axis of a machine, in axes order."""

    config: MachineConfig
    axes: tuple[Axis, ...]

    def axis(self, name: str) -> Axis:
        """Return the axis called name."""
        return self.axes[axis_index(self.config.names, name)]

    def positions(self, theta: npt.ArrayLike) -> np.ndarray:
        """Return what each axis is commanded at machine angles theta (rad), SI.

        Shape theta's + (axes,): column i is axis i's position (m, or rad of an angular axis).
        """
        angles = np.asarray(theta, dtype=float)
        return np.stack([np.asarray(axis.cam.derivatives(angles).y, dtype=float)
                         for axis in self.axes], axis=-1)

    def setpoints(self, theta: npt.ArrayLike, omega: npt.ArrayLike = 0.0,
                  alpha: npt.ArrayLike = 0.0) -> tuple[Setpoints, ...]:
        """Return each axis's setpoints at machine angles theta, speed omega and accel alpha."""
        return tuple(axis.cam.setpoints(theta, omega, alpha) for axis in self.axes)


def build_machine(config: MachineConfig) -> Machine:
    """Build every axis's design and cam; errors name the axis-prefixed parameter."""
    axes = []
    for name, axis_config in zip(config.names, config.axes):
        try:
            design = build_design(axis_config)
        except InvalidParameter as err:
            raise axis_error(name, err) from err
        axes.append(Axis(name, design, design.electronic_cam))
    return Machine(config, tuple(axes))


def load_machine(path: str | Path) -> Machine:
    """Read, check and build a machine file."""
    return build_machine(parse_machine(read_parameters_file(path)))
