"""Timing helpers: warm-up, calibrated loops, interleaved repeats, medians, percentiles, CPU."""
from __future__ import annotations

import os
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

#: Each timed repeat runs a callable this long at least (s), so the clock's resolution vanishes.
MIN_REPEAT_S = 0.02
#: Untimed calls of each callable before timing (caches, allocator, lazy imports).
WARMUP_CALLS = 2


def loops_for(func: Callable[[], object], min_seconds: float = MIN_REPEAT_S) -> int:
    """Return how many calls of func in a row take at least min_seconds (1, 2, 5, 10, ...)."""
    for scale in (10 ** power for power in range(9)):
        for step in (1, 2, 5):
            loops = step * scale
            start = time.perf_counter()
            for _ in range(loops):
                func()
            if time.perf_counter() - start >= min_seconds:
                return loops
    return loops


def interleaved_medians(functions: Mapping[str, Callable[[], object]],
                        repeats: int) -> dict[str, float]:
    """
    Return the median ns per call of each callable, timed in turn in every repeat.

    Each callable is warmed up, calibrated to run MIN_REPEAT_S per repeat, then timed `repeats`
    times, alternating with the others so that drift on a shared machine hits all of them alike.
    """
    for func in functions.values():
        for _ in range(WARMUP_CALLS):
            func()
    loops = {name: loops_for(func) for name, func in functions.items()}
    samples: dict[str, list[float]] = {name: [] for name in functions}
    for _ in range(repeats):
        for name, func in functions.items():
            count = loops[name]
            start = time.perf_counter_ns()
            for _ in range(count):
                func()
            samples[name].append((time.perf_counter_ns() - start) / count)
    return {name: float(np.median(values)) for name, values in samples.items()}


def percentile_ms(latencies_ns: Sequence[int], percent: float) -> float:
    """Return a percentile of latencies given in ns, in ms."""
    return float(np.percentile(np.asarray(latencies_ns, dtype=float), percent)) * 1e-6


def cpu_seconds(pid: int) -> float:
    """Return the CPU time (user + system) process pid has used so far, in s (/proc/PID/stat)."""
    fields = Path(f'/proc/{pid}/stat').read_text().rpartition(')')[2].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')  # utime, stime
