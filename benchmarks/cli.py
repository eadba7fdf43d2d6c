"""
The `cam_ros` command line's round trips to a running cam_node (issue 47: each <= 1 s).

A cam_node named /cam runs in the benchmark's private domain; each command is started as a
user starts it (the `cam_ros` executable beside the interpreter) and timed from its start to
its exit, in turns, so that drift on a shared machine hits every command alike. The reference,
measured in the same turns: a bare rclpy process (no cam_ros) making the same one-angle call,
which is what any Python program pays for one call from a new process: the interpreter, rclpy,
a DDS participant, discovery, the call. `python -c pass` is kept too (the interpreter alone).

``python -m benchmarks.cli`` runs it alone; ``--write`` puts its figures into
benchmarks/results.json and results.md (the rest of the file stays as `make bench` wrote it;
the figures carry the date of their own run), then ``python tools/docs_tables.py``.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Sequence

from cam_ros_interfaces.srv import EvaluateCam

from benchmarks.report import Figure, markdown_table, Target
from benchmarks.ros import BENCH_DIR, measured_alone, RosGraph

#: The issue's bound on every round trip (a quiet machine), in s.
TARGET = Target('<=', 1.0, on='value')
NODE = 'cam'
#: Longest a command may take before the benchmark gives up on it (s).
COMMAND_TIMEOUT_S = 60.0
#: The commands timed: figure key, what the table calls it, arguments. `lifecycle set` takes
#: the node down and up again in turn (deactivate, then activate), so the others find it active.
COMMANDS = (
    ('cli_call_s', 'cam_ros call 100 --deg', ('call', '100', '--deg')),
    ('cli_param_get_s', 'cam_ros param get', ('param', 'get', 'follower.offset')),
    ('cli_param_set_s', 'cam_ros param set', ('param', 'set', 'follower.offset', '0.5')),
    ('cli_lifecycle_get_s', 'cam_ros lifecycle get', ('lifecycle', 'get')),
    ('cli_lifecycle_set_s', 'cam_ros lifecycle set', ('lifecycle', 'set', 'deactivate')),
    ('cli_lifecycle_set_s', 'cam_ros lifecycle set', ('lifecycle', 'set', 'activate')),
    ('cli_echo_once_s', 'cam_ros echo --once', ('echo', '/cam/joint_states', '--once')),
)
#: The reference: the same call from a bare rclpy process (what a new process pays for a call).
BARE_CALL = f'''
import time
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from cam_ros_interfaces.srv import EvaluateCam
context = Context()
rclpy.init(context=context)
node = rclpy.create_node('bare_call', context=context, start_parameter_services=False)
client = node.create_client(EvaluateCam, '/{NODE}/evaluate')
while not client.service_is_ready():
    time.sleep(0.005)
future = client.call_async(EvaluateCam.Request(angles=[1.745]))
executor = SingleThreadedExecutor(context=context)
executor.add_node(node)
executor.spin_until_future_complete(future, timeout_sec={COMMAND_TIMEOUT_S})
assert future.result().success
'''


@dataclass(frozen=True)
class CliSizes:
    """How many times each command runs (the defaults are the published run's)."""

    rounds: int = 10


def cam_ros_command() -> list[str]:
    """Return how a user starts `cam_ros`: the executable beside this interpreter."""
    executable = Path(sys.executable).with_name('cam_ros')
    return [str(executable)] if executable.exists() else [sys.executable, '-m', 'cam_ros.cli']


def timed(command: Sequence[str], graph: RosGraph) -> float:
    """Run a command to its end in the graph's domain; return its wall time in s."""
    start = time.perf_counter()
    result = subprocess.run(command, env=graph.env, cwd=graph.workdir, capture_output=True,
                            text=True, timeout=COMMAND_TIMEOUT_S)
    elapsed = time.perf_counter() - start
    if result.returncode:
        raise RuntimeError(f'{" ".join(command)}: exit {result.returncode}\n{result.stderr}')
    return elapsed


def round_trips(graph: RosGraph, rounds: int) -> dict[str, list[float]]:
    """Time every command, the bare call and `python -c pass` once per round, in turns."""
    cam_ros = cam_ros_command()
    runs: dict[str, list[float]] = {'bare_call': [], 'python': []}
    for _ in range(rounds):
        runs['python'].append(timed([sys.executable, '-c', 'pass'], graph))
        runs['bare_call'].append(timed([sys.executable, '-c', BARE_CALL], graph))
        for key, _, arguments in COMMANDS:
            runs.setdefault(key, []).append(timed([*cam_ros, *arguments], graph))
    return runs


def cli_figures(graph: RosGraph, sizes: CliSizes) -> list[Figure]:
    """One figure per command: its median round trip against the bare call's, in s."""
    node = graph.start_cam_node(NODE)
    client = graph.client_node.create_client(EvaluateCam, f'/{NODE}/evaluate')
    graph.wait_for_service(client, node)
    try:
        runs = round_trips(graph, sizes.rounds)
    finally:
        node.stop()
        graph.client_node.destroy_client(client)
    median = {key: statistics.median(values) for key, values in runs.items()}
    names = {key: name for key, name, _ in COMMANDS}
    date = datetime.now(timezone.utc).isoformat(timespec='seconds')
    note = (f'From the start of the `cam_ros` process to its exit, against a running cam_node '
            f'(default design), median of {len(runs["bare_call"])} runs each (a `lifecycle '
            f'set`: deactivate and activate in turn, {len(runs["cli_lifecycle_set_s"])} runs), '
            f'all in turns; reference: a bare rclpy process making one call to /cam/evaluate; '
            f'`python -c pass` took {median["python"]:.3f} s. Run of {date[:16]}.')
    return [Figure(key, names[key], median[key], 's', 'bare rclpy call', median['bare_call'],
                   TARGET, note=note if index == 0 else '',
                   extra={'runs_s': runs[key], 'max_s': max(runs[key]),
                          'bare_call_runs_s': runs['bare_call'], 'python_s': median['python'],
                          'date': date})
            for index, key in enumerate(names)]


def write_into(results: Path, markdown: Path, figures: list[Figure]) -> str:
    """Put the figures into a results file `make bench` wrote (replacing their earlier run)."""
    run = json.loads(results.read_text())
    run['figures'].update((figure.key, figure.as_json()) for figure in figures)
    results.write_text(json.dumps(run, indent=2, allow_nan=False) + '\n')
    table = markdown_table(run['figures'].values())
    markdown.write_text(table)
    return table


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command-line benchmark alone; print its table (with --write, keep it)."""
    parser = argparse.ArgumentParser(prog='python -m benchmarks.cli', description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--rounds', type=int, default=CliSizes.rounds,
                        help='runs of each command (default: %(default)s)')
    parser.add_argument('--write', action='store_true',
                        help='put the figures into benchmarks/results.json and results.md')
    options = parser.parse_args(argv)
    figures = measured_alone('cam_ros_cli_',
                             lambda graph: cli_figures(graph, CliSizes(rounds=options.rounds)))
    print(markdown_table(figure.as_json() for figure in figures))
    for figure in figures:
        runs = ', '.join(f'{value:.2f}' for value in figure.extra['runs_s'])
        print(f'{figure.key}: {runs} s')
    if options.write:
        write_into(BENCH_DIR / 'results.json', BENCH_DIR / 'results.md', figures)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
