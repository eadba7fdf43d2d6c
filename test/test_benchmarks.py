"""Smoke test of `make bench`: every benchmark figure runs on tiny sizes, results are sane."""
from __future__ import annotations

import json
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from benchmarks.__main__ import benchmark, Sizes
from benchmarks.cli import CliSizes
from benchmarks.ecam import EcamSizes
from benchmarks.machine import MachineSizes
from benchmarks.recording import RecordingSizes
from benchmarks.service import ServiceSizes
from benchmarks.studio import CHROMIUM, StudioSizes
from prerequisites import require

TINY = Sizes(
    core_counts=(1000,), core_repeats=3, loop_count=1000, loop_repeats=3, geometry_count=360,
    geometry_repeats=3, evaluate_counts=(1000,), memory_count=1000,
    service=ServiceSizes(calls=20, warmup_calls=5, block=10, batch=100, batch_repeats=3,
                         big_batch=1000, big_batch_repeats=1, startup_trials=1,
                         startup_warmup=False),
    recording=RecordingSizes(rates_hz=(500.0,), rate_seconds=0.3, sweep_rounds=1,
                             loop_rate_hz=500.0, loop_seconds=0.1, loop_rounds=1,
                             drop_rate_hz=500.0, drop_seconds=0.3),
    ecam=EcamSizes(seconds=0.5, warmup_seconds=0.2),
    machine=MachineSizes(axes=(1, 3), latency_axes=3, cpu_axes=3, seconds=0.3,
                         warmup_seconds=0.1),
    cli=CliSizes(rounds=1), studio=StudioSizes(edits=3, warmup=1))
CLI_FIGURES = {'cli_call_s', 'cli_param_get_s', 'cli_param_set_s', 'cli_lifecycle_get_s',
               'cli_lifecycle_set_s', 'cli_echo_once_s'}
STUDIO_FIGURES = {f'studio_edit_{design}_{edit}_p50_ms' for design in ('machine', '16_axes')
                  for edit in ('phase', 'speed')}
FIGURES = CLI_FIGURES | STUDIO_FIGURES | {
    'core_evaluation_1000', 'speedup_over_python_loop_1000', 'design_evaluate_ms',
    'design_geometry_ms', 'design_evaluate_1000', 'design_evaluate_peak_memory_1000',
    'design_report_ms', 'design_evaluate_dynamics_ms',
    'design_report_vibration_ms',
    'service_dynamics_p50_ms',
    'service_p50_ms', 'service_p99_ms', 'batch_100_ms', 'batch_1000_ms',
    'startup_s', 'node_peak_rss_mib', 'node_peak_rss_batch_1000_mib', 'recorder_messages_per_s',
    'recorder_written_at_500_hz', 'recording_publish_overhead', 'ecam_latency_p50_ms',
    'ecam_latency_p99_ms', 'machine_latency_p50_ms', 'machine_latency_p99_ms',
    'machine_cpu_us_per_message',
}
FIGURE_FIELDS = {'key', 'name', 'value', 'unit', 'reference', 'reference_value', 'target', 'note',
                 'inverse', 'extra', 'ratio', 'met'}
TARGETED = {*CLI_FIGURES, *STUDIO_FIGURES, 'service_p50_ms', 'service_p99_ms', 'design_report_ms',
            'design_evaluate_peak_memory_1000',
            'recorder_messages_per_s', 'recorder_written_at_500_hz',
            'recording_publish_overhead',
            'design_evaluate_dynamics_ms', 'design_report_vibration_ms', 'service_dynamics_p50_ms',
            'ecam_latency_p50_ms',
            'ecam_latency_p99_ms', 'machine_latency_p50_ms', 'machine_latency_p99_ms',
            'machine_cpu_us_per_message'}


def test_benchmarks_run_on_tiny_sizes_and_write_sane_results(tmp_path: Path) -> None:
    require(CHROMIUM, "make bench's studio rows need Debian's chromium (apt-get install "
            'chromium)')
    json_path, markdown_path = tmp_path / 'results.json', tmp_path / 'results.md'
    with ThreadPoolExecutor(1) as worker:  # Playwright's sync API wants a thread without the
        # event loop pytest-playwright runs in this process once the studio's tests have run
        header, table = worker.submit(benchmark, TINY, json_path, markdown_path).result()

    results = json.loads(json_path.read_text())
    assert set(results) == {'date', 'machine', 'config', 'run_time_s', 'figures'}
    assert results['machine']['cores'] >= 1 and results['machine']['cpu']
    assert 0 < results['run_time_s'] == header['run_time_s']
    assert set(results['figures']) == FIGURES
    for key, figure in results['figures'].items():
        assert set(figure) == FIGURE_FIELDS, key
        assert figure['key'] == key
        for field in ('value', 'reference_value', 'ratio'):
            assert math.isfinite(figure[field]) and figure[field] > 0, (key, field, figure)
        expected = figure['value'] / figure['reference_value']
        if figure['inverse']:
            expected = 1 / expected
        assert math.isclose(figure['ratio'], expected), key
        assert (figure['met'] is None) == (key not in TARGETED), key
    assert results['figures']['node_peak_rss_batch_1000_mib']['value'] >= \
        results['figures']['node_peak_rss_mib']['value']
    ecam = results['figures']['ecam_latency_p50_ms']  # says how loaded the machine was
    assert (f"cam_node {ecam['extra']['cpu_us_per_message']:.0f} us, relay "
            f"{ecam['extra']['relay_cpu_us_per_message']:.0f} us") in ecam['note']

    machine = results['figures']['machine_latency_p50_ms']  # the curve, every node in turn
    curve = machine['extra']['curve']
    assert set(curve) == {'single', 'machine1', 'machine3'}
    for name, row in curve.items():
        assert row['p50_ms'] <= row['p99_ms'] and row['cpu_us_per_message'] > 0, name
        assert f"{name} {row['p50_ms']:.3f} / {row['p99_ms']:.3f}" in machine['note']
    assert results['figures']['machine_cpu_us_per_message']['value'] == \
        curve['machine3']['cpu_us_per_message']
    assert 0 < machine['extra']['command_us_compiled'] < machine['extra'][
        'command_us_exact_per_axis'] * 10

    assert markdown_path.read_text() == table
    rows = [line for line in table.splitlines() if line.startswith('| ')]
    assert rows[0].startswith('| Figure | Measured | Reference (same run) | Ratio |')
    assert len(rows) == 1 + len(FIGURES)
