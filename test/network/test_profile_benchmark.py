"""Smoke test of `python -m benchmarks.middleware` (the profile's cost) on tiny sizes."""
from __future__ import annotations

import json
import math

from benchmarks.middleware import benchmark, ProfileSizes

TINY = ProfileSizes(calls=20, block=10, idle_s=0.5)
KEYS = {'profile_p50_ms', 'profile_p99_ms', 'profile_call_cpu_ms', 'profile_call_bytes',
        'profile_idle_cpu_percent', 'profile_idle_bytes_per_s'}


def test_the_profile_benchmark_runs_and_writes_sane_results(heavy, link, tmp_path):
    link.remove()  # only proves namespaces can be made here: the benchmark makes its own
    json_path, markdown_path = tmp_path / 'results.json', tmp_path / 'results.md'
    table = benchmark(TINY, json_path, markdown_path)
    figures = json.loads(json_path.read_text())['figures']
    assert set(figures) == KEYS
    for key, figure in figures.items():
        assert math.isfinite(figure['value']) and figure['value'] >= 0, key
        assert math.isfinite(figure['reference_value']) and figure['reference_value'] >= 0, key
    assert figures['profile_call_bytes']['value'] > 0  # the calls crossed the link
    assert table == markdown_path.read_text() and 'Fast DDS defaults' in table
