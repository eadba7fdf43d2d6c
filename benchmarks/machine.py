"""
A machine on one master: master-to-command latency and CPU of cam_node with N axes against the
single-axis node, in the same run.

The machines are config/default.yaml's cam N times (axes a0 .. a{N-1}, axis i at master.offset_deg
360 i / N), with the same master, speed filter and three cam switches as the single-axis node
(benchmarks/ecam.py's); every node runs as a subprocess and gets the same 1 kHz master, one node
at a time in alternating blocks (ecam.run), its commands matched to master messages by the stamps
of its joint states (ecam.Side). CPU per master message is each process's CPU time over the
measured messages. In process, SlaveAxes.command of the largest machine at a steady sample is
timed against its axes' exact paths one by one (what a machine costs without compiled tables);
the followers' noting of a tabled sample's commands, which the node does after sending them, is
not in it.
"""
from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from benchmarks.ecam import connect, run, Side, STEP_RAD, SWITCHES
from benchmarks.report import Figure, markdown_table, Target
from benchmarks.ros import DEFAULT_CONFIG, measured_alone, RosGraph, ServerProcess
from benchmarks.timing import cpu_seconds, interleaved_medians, percentile_ms
from cam_ros.core import read_parameters_file
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.follow import EngageConfig, Follower
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.machine.machine import build_machine
from cam_ros.core.machine.config import parse_machine
from cam_ros.core.machine.parameters import machine_wide
from cam_ros.recording.parameters import params_file

#: The issue's bounds: latency at 16 axes over the single axis's, CPU at 32 axes over its.
P50_TARGET, P99_TARGET, CPU_TARGET = Target('<=', 1.3), Target('<=', 1.5), Target('<=', 3.0)
#: Machine-wide overrides of every node under test (the single axis's too).
OVERRIDES = ('master.source:=topic', 'master.timeout:=30.0', *SWITCHES)
#: Master speed of the in-process timing (rad/s: 600 rpm, as the nodes'), samples it times.
OMEGA = STEP_RAD * 1000.0


@dataclass(frozen=True)
class MachineSizes:
    """Axes of the machines, which set the latency and CPU figures, and how long to measure."""

    axes: tuple[int, ...] = (1, 4, 16, 32)
    latency_axes: int = 16
    cpu_axes: int = 32
    rate_hz: float = 1000.0
    seconds: float = 10.0  # per node: the nodes take turns
    warmup_seconds: float = 1.0


def machine_values(count: int, config: Path = DEFAULT_CONFIG) -> dict[str, Any]:
    """Return the flat parameters of a machine of count copies of a single cam's axis."""
    values = read_parameters_file(config)
    names = [f'a{index}' for index in range(count)]
    machine: dict[str, Any] = {'axes': names}
    for name, value in values.items():
        if machine_wide(name):
            machine[name] = value
        if not machine_wide(name) or name == 'length_unit':
            machine.update({f'{axis}.{name}': value for axis in names})
    machine.update({f'{axis}.master.offset_deg': 360.0 * index / count
                    for index, axis in enumerate(names)})
    return machine


def write_machine(count: int, directory: Path) -> Path:
    """Write a machine of count axes as a params file in directory; return its path."""
    path = directory / f'machine_{count}_axes.yaml'
    path.write_text(params_file(machine_values(count), f'{count} axes of default.yaml'))
    return path


def command_us(count: int) -> tuple[float, float]:
    """Return the median us of SlaveAxes.command of a steady machine of count axes, and of its
    axes' exact paths one by one."""
    machine = build_machine(parse_machine(machine_values(count)))

    def followers() -> list[Follower]:
        return [Follower(axis.cam, EngageConfig(mode='immediate'), True) for axis in machine.axes]

    axes, alone = SlaveAxes(machine.config.names, followers(), ['position'] * count), followers()
    samples = iter(range(10 ** 9))

    def state() -> MasterState:
        k = next(samples)
        return MasterState(k * 10 ** 6, k * STEP_RAD, OMEGA, 0.0, STEP_RAD, k * STEP_RAD)

    medians = interleaved_medians(
        {'compiled': lambda: axes.command(state()),
         'exact': lambda: [follower.command(state()) for follower in alone]}, repeats=5)
    return medians['compiled'] * 1e-3, medians['exact'] * 1e-3


def machine_figures(graph: RosGraph, sizes: MachineSizes) -> list[Figure]:
    """Measure every machine and the single-axis node in one run; return the figures."""
    nodes: list[tuple[str, ServerProcess]] = [
        ('single', graph.start_cam_node('single', overrides=OVERRIDES))]
    for count in sizes.axes:
        name = f'machine{count}'
        nodes.append((name, graph.start_cam_node(name, write_machine(count, graph.workdir),
                                                 OVERRIDES)))
    sides = [Side(graph, process, name) for name, process in nodes]
    k = connect(sides)
    run(sides, k, round(sizes.warmup_seconds * sizes.rate_hz), sizes.rate_hz)
    first = k + round(sizes.warmup_seconds * sizes.rate_hz)
    count = round(sizes.seconds * sizes.rate_hz)
    before = [cpu_seconds(side.process.process.pid) for side in sides]
    run(sides, first, count, sizes.rate_hz)
    cpu = [(cpu_seconds(side.process.process.pid) - start) / count * 1e6
           for side, start in zip(sides, before)]
    load = os.getloadavg()[0]
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline and any(
            len(side.commands) < len(side.sent) for side in sides):
        time.sleep(0.05)
    curve: dict[str, dict[str, float]] = {}
    for (name, process), side, used in zip(nodes, sides, cpu):
        answered = side.answered()
        measured = [k for k in range(first, first + count) if k in answered]
        latencies = [answered[k] - side.sent[k] for k in measured]
        curve[name] = {'p50_ms': percentile_ms(latencies, 50),
                       'p99_ms': percentile_ms(latencies, 99),
                       'cpu_us_per_message': used, 'missing_commands': count - len(measured)}
        process.stop()
    compiled, exact = command_us(sizes.cpu_axes)
    single, latency, busy = (curve['single'], curve[f'machine{sizes.latency_axes}'],
                             curve[f'machine{sizes.cpu_axes}'])
    extra = {'messages': count, 'rate_hz': sizes.rate_hz, 'curve': curve,
             'load_average_1min': load, 'command_us_compiled': compiled,
             'command_us_exact_per_axis': exact}
    axes = ', '.join(str(each) for each in sizes.axes)
    note = (__doc__.split('\n\n')[0].strip().replace('\n', ' ') + f' Machines of {axes} axes '
            f'and the single-axis node, {len(nodes)} nodes in turn, blocks of 10 messages; '
            f'{sizes.warmup_seconds:g} s of warm-up, then {sizes.seconds:g} s for each. Curve '
            '(p50 / p99 ms, CPU us per message, missing): ' + '; '.join(
                f'{name} {row["p50_ms"]:.3f} / {row["p99_ms"]:.3f}, '
                f'{row["cpu_us_per_message"]:.0f} us, {row["missing_commands"]}'
                for name, row in curve.items())
            + f'. In process, SlaveAxes.command with {sizes.cpu_axes} axes steady: '
            f'{compiled:.0f} us, their exact paths one by one {exact:.0f} us. Load average '
            f'{load:.2f} on {os.cpu_count()} cores.')
    name = f'Machine of {sizes.latency_axes} axes, master to command, {sizes.rate_hz:g} Hz'
    return [
        Figure('machine_latency_p50_ms', f'{name}, p50 ({latency["missing_commands"]} without '
               'command)', latency['p50_ms'], 'ms', 'single axis p50', single['p50_ms'],
               P50_TARGET, extra=extra, note=note),
        Figure('machine_latency_p99_ms', f'{name}, p99', latency['p99_ms'], 'ms',
               'single axis p99', single['p99_ms'], P99_TARGET, extra=extra),
        Figure('machine_cpu_us_per_message', f'Machine of {sizes.cpu_axes} axes, CPU per master '
               f'message ({busy["missing_commands"]} without command)',
               busy['cpu_us_per_message'], 'us', 'single axis', single['cpu_us_per_message'],
               CPU_TARGET, extra=extra),
    ]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the machine benchmark alone and print its table (results.json is left alone)."""
    parser = argparse.ArgumentParser(prog='python -m benchmarks.machine', description=__doc__)
    parser.add_argument('--seconds', type=float, default=MachineSizes.seconds,
                        help='measured seconds per node (default: %(default)s)')
    options = parser.parse_args(argv)
    figures = measured_alone('cam_ros_machine_', lambda graph: machine_figures(
        graph, MachineSizes(seconds=options.seconds)))
    print(markdown_table(figure.as_json() for figure in figures))
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
