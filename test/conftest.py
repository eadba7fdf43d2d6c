"""Shared pytest harness: DDS isolation, rclpy contexts, background executors, node processes.

Each test process reserves its own ROS domain id (domain_coordinator) and keeps discovery on
localhost, so parallel runs on one machine never see each other. Subprocesses inherit both.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

REPO = Path(__file__).resolve().parents[1]
CONFIG_DIR = REPO / 'config'
SERVICE_TIMEOUT_S = 20.0
STOP_TIMEOUT_S = 10.0
FIRST_ANSWER_TIMEOUT_S = 2.0


@pytest.fixture
def report(record_property: Callable[[str, object], None]) -> Callable[[str, object], None]:
    """Return a function that records a measured figure (JUnit XML and the terminal summary)."""
    return record_property


def pytest_terminal_summary(terminalreporter: Any) -> None:
    """List the figures tests measured with `report`, per test folder, whatever -q says."""
    sections: dict[str, list[str]] = {}
    for outcome in ('passed', 'failed'):
        for entry in terminalreporter.stats.get(outcome, []):
            if entry.when == 'call':
                path, _, test = entry.nodeid.partition('::')
                sections.setdefault(Path(path).parent.name, []).extend(
                    f'{test}: {name} = {value}' for name, value in entry.user_properties)
    for folder, lines in sections.items():
        if lines:
            terminalreporter.section(f'{folder} figures')
            for line in lines:
                terminalreporter.write_line(line)


def pytest_addoption(parser: pytest.Parser) -> None:
    """Add --heavy: longer loads, more fault repetitions, every bad config through a subprocess."""
    parser.addoption('--heavy', action='store_true', default=False,
                     help='reliability tests: run the full (minutes) instead of the short version')


@pytest.fixture(autouse=True)
def middleware_environment_kept() -> Iterator[None]:
    """
    Undo what an in-process cam_ros command writes to os.environ: the Fast DDS profile.

    A command run by a test (cam_ros.commands.ros) points FASTRTPS_DEFAULT_PROFILES_FILE at the
    shipped profile, as it would in its own process; left set, every node a later test starts
    would take it for the user's choice and keep shared memory (cam_ros.node.middleware).
    """
    from cam_ros.node.middleware import PROFILE_VARIABLES

    saved = {name: os.environ.get(name) for name in PROFILE_VARIABLES}
    yield
    for name, value in saved.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value


@pytest.fixture(scope='session')
def ros_domain() -> Iterator[int]:
    """Reserve a DDS domain id for this test process and export it to subprocesses."""
    from domain_coordinator import domain_id

    with domain_id() as reserved:
        os.environ['ROS_DOMAIN_ID'] = str(reserved)
        os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
        yield reserved


@pytest.fixture
def ros_context(ros_domain: int) -> Iterator[object]:
    """Give the test its own initialised rclpy context on the reserved domain."""
    import rclpy

    context = rclpy.Context()
    rclpy.init(context=context, domain_id=ros_domain)
    try:
        yield context
    finally:
        rclpy.try_shutdown(context=context)


class BackgroundExecutor:
    """A SingleThreadedExecutor spinning in a thread; add nodes, it tears down cleanly."""

    def __init__(self, context: object):
        from rclpy.executors import SingleThreadedExecutor

        self.context = context
        self.executor = SingleThreadedExecutor(context=context)
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._nodes: list = []
        self._thread.start()

    def _spin(self) -> None:
        from rclpy.executors import ExternalShutdownException

        try:
            self.executor.spin()
        except ExternalShutdownException:
            pass

    def node(self, name: str, **kwargs: object):
        """Create a node in this context and spin it."""
        from rclpy.node import Node

        node = Node(name, context=self.context, **kwargs)
        self._nodes.append(node)
        self.executor.add_node(node)
        return node

    def close(self) -> None:
        """Stop spinning, join the thread and destroy the nodes."""
        self.executor.shutdown()
        self._thread.join(timeout=STOP_TIMEOUT_S)
        for node in self._nodes:
            node.destroy_node()


@pytest.fixture
def executor(ros_context: object) -> Iterator[BackgroundExecutor]:
    """Spin test nodes in a background executor that is always shut down and joined."""
    spinner = BackgroundExecutor(ros_context)
    try:
        yield spinner
    finally:
        spinner.close()


@dataclass
class NodeProcess:
    """A `cam_node` started as a real subprocess."""

    process: subprocess.Popen
    log_path: Path

    def log(self) -> str:
        """Return what the node printed so far."""
        return self.log_path.read_text(errors='replace')

    def stop(self, sig: int = signal.SIGINT) -> int:
        """Send a signal and wait for the exit code."""
        if self.process.poll() is None:
            self.process.send_signal(sig)
        try:
            return self.process.wait(timeout=STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            raise AssertionError(f'cam_node ignored signal {sig}:\n{self.log()}')


def wait_for_service(client: object, process: NodeProcess, timeout: float) -> None:
    """Wait until a client sees its service, failing early if the node process died."""
    deadline = time.monotonic() + timeout
    while not client.wait_for_service(timeout_sec=0.1):
        if process.process.poll() is not None:
            raise AssertionError(f'cam_node exited with {process.process.returncode}:\n'
                                 f'{process.log()}')
        if time.monotonic() > deadline:
            raise AssertionError(f'service {client.srv_name} not up in {timeout} s:\n'
                                 f'{process.log()}')


def wait_for_answer(client: object, request: object, process: NodeProcess) -> None:
    """Call until an answer arrives: a service just discovered may not have matched us yet.

    DDS can show the server's request reader before the server sees our response reader; a
    request sent in that window is answered into the void, so a first answer proves the match.
    """
    deadline = time.monotonic() + SERVICE_TIMEOUT_S
    while True:
        future = client.call_async(request)
        settle = time.monotonic() + FIRST_ANSWER_TIMEOUT_S
        while not future.done() and time.monotonic() < settle:
            time.sleep(0.01)
        if future.done():
            return
        client.remove_pending_request(future)
        if process.process.poll() is not None or time.monotonic() > deadline:
            raise AssertionError(f'no answer from {client.srv_name}:\n{process.log()}')


def matched_client(node: object, process: NodeProcess, name: str = 'cam',
                   evaluate: str = 'evaluate') -> object:
    """Return a new EvaluateCam client of node that the cam node has answered once."""
    from cam_ros_interfaces.srv import EvaluateCam

    client = node.create_client(EvaluateCam, f'/{name}/{evaluate}')
    wait_for_service(client, process, SERVICE_TIMEOUT_S)
    wait_for_answer(client, EvaluateCam.Request(angles=[0.0]), process)
    return client


@pytest.fixture
def start_cam_node(ros_domain: int, tmp_path: Path, executor: BackgroundExecutor):
    """Start `cam_node` as a subprocess on a params file and wait for its evaluate service.

    Returns a function ``start(params_file, *ros_args, name='cam', evaluate='evaluate') ->
    (NodeProcess, client)``, the client of /<name>/<evaluate> (a machine's: '<axis>/evaluate');
    every process it started is stopped at teardown.
    """
    with ExitStack() as stack:
        client_node = executor.node('test_client')

        def start(params_file: Path | str = CONFIG_DIR / 'default.yaml', *ros_args: str,
                  name: str = 'cam', evaluate: str = 'evaluate'):
            log_path = tmp_path / f'{name}-{time.monotonic_ns()}.log'
            log_file = stack.enter_context(open(log_path, 'wb'))
            command = [sys.executable, '-m', 'cam_ros.node', '--ros-args', '-r', f'__node:={name}',
                       '--params-file', str(params_file), *ros_args]
            process = NodeProcess(
                subprocess.Popen(command, stdout=log_file, stderr=subprocess.STDOUT, cwd=tmp_path),
                log_path)
            stack.callback(_reap, process)
            return process, matched_client(client_node, process, name, evaluate)

        yield start


def _reap(process: NodeProcess) -> None:
    """Make sure no node process outlives its test."""
    if process.process.poll() is None:
        process.process.kill()
        process.process.wait()
