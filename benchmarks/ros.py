"""
The benchmarks' ROS side: a private DDS domain, an in-process client node, server subprocesses.

Like test/conftest.py, the run reserves its own domain id (domain_coordinator) and keeps discovery
on localhost; subprocesses get both through their environment (os.environ's ROS_DOMAIN_ID is left
alone). The in-process nodes are spun by a SingleThreadedExecutor in a background thread, so
`Client.call()` can be used from the main thread (repeated spin_until_future_complete leaks).
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence, TypeVar

import rclpy
from domain_coordinator import domain_id
from rclpy.client import Client
from rclpy.context import Context
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node

REPO = Path(__file__).resolve().parents[1]
BENCH_DIR = Path(__file__).resolve().parent
DEFAULT_CONFIG = REPO / 'config' / 'default.yaml'
#: Longest wait for a subprocess's service to appear (s).
SERVICE_TIMEOUT_S = 60.0
#: Longest wait for a subprocess to exit after SIGINT (s).
STOP_TIMEOUT_S = 10.0
#: Poll period of the service discovery check (s); rclpy's wait_for_service sleeps 0.25 s.
POLL_S = 0.002
Result = TypeVar('Result')


@dataclass
class ServerProcess:
    """A node subprocess started by the benchmarks, with its log file."""

    name: str
    process: subprocess.Popen
    log_path: Path

    def log(self) -> str:
        """Return what the process printed so far."""
        return self.log_path.read_text(errors='replace')

    def ask(self, line: str | None = None) -> dict[str, Any]:
        """Send a line to a piped process (if given) and return its next JSON line."""
        assert self.process.stdin is not None and self.process.stdout is not None
        if line is not None:
            self.process.stdin.write(line + '\n')
            self.process.stdin.flush()
        for answer in self.process.stdout:
            if answer.startswith('{'):
                return json.loads(answer)
        self.process.wait(timeout=STOP_TIMEOUT_S)
        raise RuntimeError(f'{self.name} exited with {self.process.returncode}:\n{self.log()}')

    def peak_rss_bytes(self) -> int:
        """Return the process's peak resident set size (VmHWM) in bytes."""
        for line in Path(f'/proc/{self.process.pid}/status').read_text().splitlines():
            if line.startswith('VmHWM:'):
                return int(line.split()[1]) * 1024
        raise RuntimeError(f'no VmHWM in /proc/{self.process.pid}/status')

    def stop(self) -> None:
        """Stop the process: end a piped one's input, else SIGINT; SIGKILL if it hangs."""
        if self.process.stdin is not None and not self.process.stdin.closed:
            self.process.stdin.close()
            try:
                self.process.wait(timeout=STOP_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                pass
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(timeout=STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


class RosGraph:
    """A private ROS graph: reserved domain, a client node spun in a thread, subprocesses."""

    def __init__(self, workdir: Path):
        """Keep logs and files of this graph under workdir."""
        self.workdir = workdir
        self._stack = ExitStack()
        self._processes: list[ServerProcess] = []
        self._nodes: list[Node] = []
        self.env: dict[str, str] = {}

    def __enter__(self) -> RosGraph:
        """Reserve a domain, initialise a context and start spinning the client node."""
        with ExitStack() as stack:
            domain = stack.enter_context(domain_id())
            os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
            python_path = os.pathsep.join(filter(None, [str(REPO), os.environ.get('PYTHONPATH')]))
            self.env = dict(os.environ, ROS_DOMAIN_ID=str(domain),
                            ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
                            ROS_LOG_DIR=str(self.workdir / 'ros_log'), PYTHONPATH=python_path)
            self.context = Context()
            rclpy.init(context=self.context, domain_id=domain)
            stack.callback(rclpy.try_shutdown, context=self.context)
            self.executor = SingleThreadedExecutor(context=self.context)
            self._thread = threading.Thread(target=self._spin, daemon=True)
            self._thread.start()
            stack.callback(self._stop_spinning)
            stack.callback(self._stop_processes)
            self.client_node = self.node('bench_client')
            self._stack = stack.pop_all()
        return self

    def __exit__(self, *exc_info: object) -> None:
        """Stop every subprocess, stop spinning, shut the context down, free the domain."""
        self._stack.close()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except ExternalShutdownException:
            pass

    def _stop_spinning(self) -> None:
        self.executor.shutdown()
        self._thread.join(timeout=STOP_TIMEOUT_S)
        for node in self._nodes:
            node.destroy_node()

    def _stop_processes(self) -> None:
        for process in self._processes:
            process.stop()

    def node(self, name: str, **options: Any) -> Node:
        """Create a node in this graph's context, spun by its executor."""
        node = Node(name, context=self.context, **options)
        self._nodes.append(node)
        self.executor.add_node(node)
        return node

    def start(self, module: str, name: str, *args: str, ros_args: Sequence[str] = (),
              pipe: bool = False) -> ServerProcess:
        """
        Start `python -m module args... --ros-args -r __node:=name ros_args...` on this domain.

        Its output goes to a log file; with `pipe`, stdin and stdout are text pipes instead
        (JSON lines, see ServerProcess.ask) and only stderr goes to the log.
        """
        log_path = self.workdir / f'{name}.log'
        with open(log_path, 'wb') as log:
            popen = subprocess.Popen(
                [sys.executable, '-m', module, *args, '--ros-args', '-r', f'__node:={name}',
                 *ros_args],
                stdin=subprocess.PIPE if pipe else subprocess.DEVNULL,
                stdout=subprocess.PIPE if pipe else log, stderr=log, text=pipe,
                env=self.env, cwd=self.workdir)
        process = ServerProcess(name, popen, log_path)
        self._processes.append(process)
        return process

    def start_cam_node(self, name: str, config: Path = DEFAULT_CONFIG,
                       overrides: Sequence[str] = ()) -> ServerProcess:
        """Start cam_node (`python -m cam_ros.node`) on a params file and NAME:=VALUE overrides."""
        options = [arg for override in overrides for arg in ('-p', override)]
        return self.start('cam_ros.node', name, ros_args=('--params-file', str(config), *options))

    def start_setbool_server(self, name: str) -> ServerProcess:
        """Start the trivial SetBool server (benchmarks/setbool_server.py)."""
        return self.start('benchmarks.setbool_server', name)

    def wait_for_service(self, client: Client, process: ServerProcess,
                         timeout: float = SERVICE_TIMEOUT_S) -> None:
        """Wait until the client sees its service; raise if the process dies or time runs out."""
        deadline = time.monotonic() + timeout
        while not client.service_is_ready():
            if process.process.poll() is not None:
                raise RuntimeError(f'{process.name} exited with {process.process.returncode}:\n'
                                   f'{process.log()}')
            if time.monotonic() > deadline:
                raise RuntimeError(f'{client.srv_name} not up after {timeout} s:\n'
                                   f'{process.log()}')
            time.sleep(POLL_S)


def measured_alone(prefix: str, measure: Callable[[RosGraph], Result]) -> Result:
    """Run measure in a graph of its own, its files in a temporary folder (a benchmark alone)."""
    with tempfile.TemporaryDirectory(prefix=prefix) as workdir:
        with RosGraph(Path(workdir)) as graph:
            return measure(graph)
