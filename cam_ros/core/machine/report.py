"""The machine report: each axis's design report and every interference pair's verdict."""
from __future__ import annotations

from dataclasses import dataclass

from ..report import design_report, DesignReport
from .interference import check_interference, PairCheck
from .machine import Machine


@dataclass(frozen=True)
class MachineReport:
    """Each axis's report (in axes order) and each interference pair's check."""

    machine: Machine
    axes: tuple[DesignReport, ...]
    interference: tuple[PairCheck, ...]

    @property
    def ok(self) -> bool:
        """Return True when every axis passes its own verdict and no pair collides."""
        return all(report.ok for report in self.axes) and all(
            check.ok for check in self.interference)


def machine_report(machine: Machine) -> MachineReport:
    """Compute the report of a machine."""
    return MachineReport(machine, tuple(design_report(axis.design) for axis in machine.axes),
                         check_interference(machine))
