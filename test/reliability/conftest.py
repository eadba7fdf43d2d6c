"""Reliability effort: short bounded tests, the full ones with --heavy (see test/conftest.py)."""
from __future__ import annotations

from dataclasses import dataclass

import pytest


@dataclass(frozen=True)
class Effort:
    """How hard the reliability tests push: the short default or the --heavy run."""

    heavy: bool
    load_s: float  # seconds of concurrent evaluate calls
    clients: int  # client processes of the load test
    kills: int  # SIGKILLs of a recording node, each at a different moment
    vanishing_clients: int  # clients killed while their big request is being answered
    stall_s: float  # seconds the node runs on with stalled subscribers after the kills
    examples: int  # hypothesis max_examples of each property

    def scaled(self, short: int, full: int) -> int:
        """Return the short or the full number."""
        return full if self.heavy else short


@pytest.fixture(scope='session')
def effort(pytestconfig: pytest.Config) -> Effort:
    """Return the effort of this run (--heavy or not)."""
    if pytestconfig.getoption('--heavy'):
        return Effort(heavy=True, load_s=30.0, clients=3, kills=3, vanishing_clients=5,
                      stall_s=10.0, examples=1000)
    return Effort(heavy=False, load_s=5.0, clients=3, kills=1, vanishing_clients=2, stall_s=1.0,
                  examples=100)
