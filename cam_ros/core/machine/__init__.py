"""A machine: many cam axes on one master, and the pairs of them checked for collisions."""
from .config import InterferencePair, is_machine, MachineConfig, parse_machine
from .interference import check_interference, PairCheck
from .machine import Axis, build_machine, load_machine, Machine
from .report import machine_report, MachineReport

__all__ = ['Axis', 'build_machine', 'check_interference', 'InterferencePair', 'is_machine',
           'load_machine', 'Machine', 'MachineConfig', 'machine_report', 'MachineReport',
           'PairCheck', 'parse_machine']
