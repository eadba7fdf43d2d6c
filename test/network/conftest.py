"""Fixtures of the network tests: two hosts (namespaces + veth), nodes and clients on them.

They need root, iproute2 (`ip`) and, for packet loss and dropped multicast, nftables (`nft`);
without them the tests skip, saying which is missing, and fail so under CI=true (prerequisites).
"""
from __future__ import annotations

import itertools
import json
import os
import queue
import subprocess
import sys
import threading
from contextlib import ExitStack
from pathlib import Path
from typing import Iterator

import pytest
from conftest import CONFIG_DIR, NodeProcess
from prerequisites import require

from benchmarks.netns import Host, Link

CHILD = Path(__file__).with_name('children.py')
DEFAULT = CONFIG_DIR / 'default.yaml'
READY_TIMEOUT_S = 90.0  # the child's own first-answer wait (60 s) and its start-up
ANSWER_TIMEOUT_S = 120.0


class Client:
    """A long-lived client process (children.py) on a host; JSON commands in, JSON lines out."""

    def __init__(self, command: list[str], env: dict[str, str], log_path: Path):
        self.log_path = log_path
        self._log = open(log_path, 'wb')
        self.process = subprocess.Popen(command, env=env, stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=self._log, text=True)
        self._lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        self.ready: dict = {}

    def wait_ready(self) -> Client:
        """Wait until the child's first call was answered; return self."""
        self.ready = self.read(READY_TIMEOUT_S)
        assert self.ready['first_answer_s'] is not None, f'never answered:\n{self.log()}'
        return self

    def _read(self) -> None:
        for line in self.process.stdout:
            self._lines.put(line)

    def read(self, timeout: float) -> dict:
        """Return the next JSON line (fail if the child stays silent)."""
        try:
            return json.loads(self._lines.get(timeout=timeout))
        except queue.Empty:
            raise AssertionError(f'client said nothing in {timeout} s (exit '
                                 f'{self.process.poll()}):\n{self.log()}') from None

    def send(self, do: str, **arguments: object) -> None:
        """Send one command."""
        self.process.stdin.write(json.dumps({'do': do, **arguments}) + '\n')
        self.process.stdin.flush()

    def ask(self, do: str, wait: float = ANSWER_TIMEOUT_S, **arguments: object) -> dict:
        """Send one command and return the answer."""
        self.send(do, **arguments)
        return self.read(wait)

    def log(self) -> str:
        """Return what the child wrote on stderr."""
        return self.log_path.read_text(errors='replace')

    def close(self) -> None:
        """Kill the child if it still runs."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        self._log.close()


class Network:
    """Start cam nodes, clients and cam_ros commands on the two hosts; stop them all at the end."""

    def __init__(self, link: Link, domain: int, folder: Path, stack: ExitStack):
        self.a, self.b = link.a, link.b
        self.link = link
        self.folder = folder
        self._stack = stack
        self._serial = itertools.count()
        self.env = dict(os.environ, ROS_DOMAIN_ID=str(domain),
                        ROS_AUTOMATIC_DISCOVERY_RANGE='SUBNET')

    def _log_path(self, what: str) -> Path:
        return self.folder / f'{what}-{next(self._serial)}.log'

    def start_node(self, host: Host, *ros_args: str, env: dict | None = None) -> NodeProcess:
        """Start cam_node on host (default design), as the start_cam_node fixture does."""
        log_path = self._log_path('cam_node')
        with open(log_path, 'wb') as log:
            process = subprocess.Popen(
                host.command(sys.executable, '-m', 'cam_ros.node', '--ros-args', '--params-file',
                             str(DEFAULT), *ros_args),
                stdout=log, stderr=subprocess.STDOUT, cwd=self.folder, env=env or self.env)
        node = NodeProcess(process, log_path)
        self._stack.callback(_stop, node)
        return node

    def client(self, host: Host, env: dict | None = None) -> Client:
        """Start a long-lived client on host and wait until the node answered it once."""
        client = Client(host.command(sys.executable, str(CHILD), str(DEFAULT)), env or self.env,
                        self._log_path('client'))
        self._stack.callback(client.close)
        return client.wait_ready()

    def cam_ros(self, host: Host, *args: str, timeout: float = ANSWER_TIMEOUT_S,
                env: dict | None = None) -> subprocess.CompletedProcess:
        """Run a cam_ros command on host and return its result."""
        return subprocess.run(host.command(sys.executable, '-m', 'cam_ros.cli', *args),
                              capture_output=True, text=True, timeout=timeout,
                              env=env or self.env, cwd=self.folder)


def _stop(node: NodeProcess) -> None:
    if node.process.poll() is None:
        node.stop()


@pytest.fixture
def heavy(pytestconfig: pytest.Config) -> None:
    """Skip unless --heavy: the load, loss, partition and multicast tests take minutes."""
    if not pytestconfig.getoption('--heavy'):
        pytest.skip('a heavy network test: runs with --heavy')


@pytest.fixture
def link() -> Iterator[Link]:
    """Two fresh network namespaces joined by a veth link; always removed."""
    require('root', 'network namespaces need it', present=os.geteuid() == 0)
    require('ip', 'network namespaces and veth links (apt-get install iproute2)')
    try:
        created = Link()
    except OSError as err:
        require('network namespaces', f'cannot create them: {err}', present=False)
    try:
        yield created
    finally:
        created.remove()


@pytest.fixture
def nft() -> None:
    """Require nftables (packet loss and dropped multicast need it)."""
    require('nft', 'packet loss and dropped multicast (apt-get install nftables)')


@pytest.fixture
def network(link: Link, ros_domain: int, tmp_path: Path) -> Iterator[Network]:
    """Two hosts with processes on them; every process is stopped before the link goes."""
    with ExitStack() as stack:
        yield Network(link, ros_domain, tmp_path, stack)
