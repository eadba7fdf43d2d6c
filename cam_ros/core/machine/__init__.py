"""A machine: many cam axes on one master, and the pairs of them checked for collisions."""
from .config import InterferencePair, is_machine, MachineConfig, parse_machine
from .machine import Axis, build_machine, load_machine, Machine

__all__ = ['Axis', 'build_machine', 'InterferencePair', 'is_machine', 'load_machine', 'Machine',
           'MachineConfig', 'parse_machine']
