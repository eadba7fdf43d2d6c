"""
Run every benchmark: ``python -m benchmarks`` (``make bench``), a few minutes on 2 cores.

Prints the markdown table, writes it to benchmarks/results.md and everything (with the machine,
the date and the run time) to benchmarks/results.json.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Sequence

from benchmarks.cli import cli_figures, CliSizes
from benchmarks.core import (core_figures, evaluate_figures, geometry_figures, loop_figure,
                             memory_figure, report_figure)
from benchmarks.dynamics import evaluate_figure, vibration_figure
from benchmarks.ecam import ecam_figures, EcamSizes
from benchmarks.machine import machine_figures, MachineSizes
from benchmarks.recording import recording_figures, RecordingSizes
from benchmarks.report import Figure, machine, write_results
from benchmarks.ros import BENCH_DIR, DEFAULT_CONFIG, REPO, RosGraph
from benchmarks.service import service_figures, ServiceSizes
from benchmarks.studio import studio_figures, StudioSizes
from cam_ros.core import build_design, load_config


@dataclass(frozen=True)
class Sizes:
    """How much every benchmark measures (the defaults are the published run's)."""

    core_counts: tuple[int, ...] = (10 ** 3, 10 ** 5, 10 ** 6)
    core_repeats: int = 9
    loop_count: int = 10 ** 5
    loop_repeats: int = 5
    geometry_count: int = 3600
    evaluate_counts: tuple[int, ...] = (10 ** 3, 10 ** 4, 10 ** 5, 10 ** 6, 10 ** 7)
    memory_count: int = 10 ** 7
    geometry_repeats: int = 9
    service: ServiceSizes = field(default_factory=ServiceSizes)
    recording: RecordingSizes = field(default_factory=RecordingSizes)
    ecam: EcamSizes = field(default_factory=EcamSizes)
    machine: MachineSizes = field(default_factory=MachineSizes)
    cli: CliSizes = field(default_factory=CliSizes)
    studio: StudioSizes = field(default_factory=StudioSizes)


def run(sizes: Sizes, workdir: Path, config: Path = DEFAULT_CONFIG) -> list[Figure]:
    """Measure every figure on the design of config; ROS files and logs go to workdir."""
    design = build_design(load_config(config))
    figures = [*core_figures(design, sizes.core_counts, sizes.core_repeats),
               loop_figure(design, sizes.loop_count, sizes.loop_repeats),
               *geometry_figures(design, sizes.geometry_count, sizes.geometry_repeats),
               *evaluate_figures(design, sizes.evaluate_counts, sizes.core_repeats),
               memory_figure(design, sizes.memory_count),
               report_figure(design, sizes.geometry_repeats),
               evaluate_figure(config, design, sizes.geometry_count, sizes.geometry_repeats),
               vibration_figure(config, design, sizes.geometry_repeats)]
    with RosGraph(workdir) as graph:
        figures.extend(service_figures(graph, sizes.service))
        figures.extend(recording_figures(graph, workdir, sizes.recording))
        figures.extend(ecam_figures(graph, sizes.ecam))
        figures.extend(machine_figures(graph, sizes.machine))
        figures.extend(cli_figures(graph, sizes.cli))
    figures.extend(studio_figures(sizes.studio))  # in Debian's chromium
    return figures


def benchmark(sizes: Sizes, json_path: Path, markdown_path: Path) -> tuple[dict[str, Any], str]:
    """Run the benchmarks and write their results; return the JSON header and the table."""
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix='cam_ros_bench_') as workdir:
        figures = run(sizes, Path(workdir))
    header = {'date': datetime.now(timezone.utc).isoformat(timespec='seconds'),
              'machine': machine(), 'config': str(DEFAULT_CONFIG.relative_to(REPO)),
              'run_time_s': round(time.perf_counter() - start, 1)}
    return header, write_results(figures, header, json_path, markdown_path)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the published benchmark set and print the table."""
    parser = argparse.ArgumentParser(prog='python -m benchmarks', description=__doc__)
    parser.add_argument('--json', type=Path, default=BENCH_DIR / 'results.json',
                        help='where to write the results (default: %(default)s)')
    parser.add_argument('--markdown', type=Path, default=BENCH_DIR / 'results.md',
                        help='where to write the table (default: %(default)s)')
    options = parser.parse_args(argv)
    header, table = benchmark(Sizes(), options.json, options.markdown)
    cpu = header['machine']
    print(table)
    print(f'{header["date"]}; {cpu["cpu"]}, {cpu["cores"]} cores; Python {cpu["python"]}, '
          f'NumPy {cpu["numpy"]}; run time {header["run_time_s"]:g} s')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
