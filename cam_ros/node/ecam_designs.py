"""
What the electronic cam takes from its axes' designs, prepared before it takes its lock.

A MasterFollower is built from, and a design change hands it, one EcamDesigns: every axis's
engagement settings, limits, unit and command interface, the machine-wide master settings (the
first axis's), the master's speed limit and nominal speed, the design statuses for /diagnostics
and the switch table. Computing them (and a change's path limits) off the master thread keeps
a design change from stalling the master path.
"""
from __future__ import annotations

from typing import Any, Mapping, NamedTuple, Sequence

from diagnostic_msgs.msg import DiagnosticStatus
from rclpy.node import Node

from cam_ros.core import CamDesign
from cam_ros.core.ecam.follow import EngageConfig
from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.core.ecam.path_limits import PathLimits
from cam_ros.core.ecam.slave_limits import AxisUnit, SlaveLimits
from cam_ros.core.ecam.switches import switch_table, SwitchTable
from cam_ros.node.ecam_diagnostics import design_statuses, jump_speed


class EcamDesigns(NamedTuple):
    """The e-cam's view of (joint name, design) per axis; see the module."""

    names: list[str]
    cams: list[ElectronicCam]
    parameters: list[dict[str, Any]]
    master: MasterConfig  # the machine-wide master.* settings (the first axis's)
    engage: list[EngageConfig]
    limits: list[SlaveLimits]
    units: list[AxisUnit]
    interfaces: list[str]  # command.interface per axis: 'position' or 'velocity'
    speed_limit: tuple[float, str]  # the master speed to warn above, and what sets it
    statuses: list[DiagnosticStatus]
    switches: SwitchTable

    @classmethod
    def of(cls, node: Node, axes: Sequence[tuple[str, CamDesign]],
           switches: Mapping[str, Any]) -> 'EcamDesigns':
        """Prepare the designs of axes and the switches.* values."""
        configs = [design.config for _, design in axes]
        return cls([name for name, _ in axes], [design.electronic_cam for _, design in axes],
                   [dict(config.parameters) for config in configs],
                   MasterConfig.from_config(configs[0]),
                   [EngageConfig.from_parameters(config.parameters) for config in configs],
                   [SlaveLimits.from_config(config) for config in configs],
                   [AxisUnit.of(config) for config in configs],
                   [config.parameters['command.interface'] for config in configs],
                   min(MasterConfig.from_config(design.config).speed_limit(jump_speed(design))
                       for _, design in axes),
                   design_statuses(node, axes), switch_table(switches))

    @property
    def values(self) -> dict[str, Any]:
        """Return the machine-wide parameter values (the first axis's)."""
        return self.parameters[0]

    @property
    def one_way(self) -> bool:
        """Say whether any axis has slave.direction."""
        return any(limits.direction for limits in self.limits)

    def path_limits(self, also: Sequence[tuple[ElectronicCam, SlaveLimits]] = ()) -> PathLimits:
        """Return the line shaft's path limits of these designs, and of the (cam, limits) also
        given (a costly refinement)."""
        return PathLimits.of(self.cams + [cam for cam, _ in also],
                             self.limits + [limits for _, limits in also],
                             self.engage[0].nominal_speed, self.engage[0].distance)
