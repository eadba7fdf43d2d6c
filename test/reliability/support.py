"""What the reliability tests share: calls to a live node, witnesses, child processes, figures."""
from __future__ import annotations

import json
import math
import os
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numpy as np
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR, matched_client, NodeProcess
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from cam_ros.core import CamDesign, build_design, parse_parameters, read_parameters_file

DEFAULT = CONFIG_DIR / 'default.yaml'
CHILD = Path(__file__).with_name('children.py')
CALL_TIMEOUT_S = 10.0
READY_TIMEOUT_S = 30.0
SAMPLE_ANGLES = np.radians([0.0, 95.0, 135.0, 175.0, 250.0, 330.0])
#: An independent witness: reliable and keeping every message, so it never drops one.
WITNESS_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
CDR_LITTLE_ENDIAN = b'\x00\x01'  # encapsulation of the CDR bytes ROS 2 sends on x86/ARM
CDR_HEADER_SIZE = 4
STAMP = struct.Struct('<iI')  # std_msgs/Header starts with builtin_interfaces/Time
RESPONSE_FIELDS = ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                   'radius_of_curvature')


def design_with(**updates: Any) -> CamDesign:
    """Return the default design with parameters changed, built by the core alone."""
    values = read_parameters_file(DEFAULT)
    values.update(updates)
    return build_design(parse_parameters(values))


def evaluate(client: Any, angles: Iterable[float],
             timeout: float = CALL_TIMEOUT_S) -> EvaluateCam.Response:
    """Call an EvaluateCam service and return its response (fail if none comes)."""
    response = client.call(EvaluateCam.Request(angles=list(angles)), timeout_sec=timeout)
    assert response is not None, f'no response from {client.srv_name} in {timeout} s'
    return response


def assert_serves(response: EvaluateCam.Response, design: CamDesign,
                  angles: Sequence[float] = SAMPLE_ANGLES) -> None:
    """Check a response equals the core's evaluation of design, bit for bit."""
    assert response.success, response.message
    expected = design.evaluate(np.asarray(angles, dtype=float))
    for field in RESPONSE_FIELDS:
        np.testing.assert_array_equal(getattr(response, field), getattr(expected, field),
                                      err_msg=field)


def timed_evaluate(client: Any, angles: Sequence[float]) -> float:
    """Return the round trip (s) of one successful evaluate call."""
    start = time.perf_counter()
    response = evaluate(client, angles)
    elapsed = time.perf_counter() - start
    assert response.success, response.message
    return elapsed


def wait_until(predicate: Callable[[], bool], timeout: float, what: str) -> None:
    """Poll until predicate() holds; fail naming what was awaited."""
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'timed out after {timeout} s waiting for {what}'
        time.sleep(0.01)


def wire_stamp_ns(data: bytes) -> int:
    """Return the header stamp (ns) of a stamped message's CDR bytes (little endian)."""
    assert data[:2] == CDR_LITTLE_ENDIAN, data[:4]
    sec, nanosec = STAMP.unpack_from(data, CDR_HEADER_SIZE)
    return sec * 10**9 + nanosec


class Witness:
    """An independent raw subscriber keeping the stamp (ns) and wire size of every message."""

    def __init__(self, node: Any, msg_type: type, topic: str, qos: QoSProfile = WITNESS_QOS):
        self.received: list[tuple[int, int]] = []
        self._lock = threading.Lock()
        self.subscription = node.create_subscription(msg_type, topic, self._receive, qos,
                                                     raw=True)

    def _receive(self, data: bytes) -> None:
        with self._lock:
            self.received.append((wire_stamp_ns(data), len(data)))

    def snapshot(self) -> list[tuple[int, int]]:
        """Return (stamp ns, size in bytes) of the messages received so far."""
        with self._lock:
            return list(self.received)

    def count(self) -> int:
        """Return how many messages arrived."""
        with self._lock:
            return len(self.received)


def rss_kib(pid: int) -> int:
    """Return a process's resident set size in KiB (VmRSS of /proc/PID/status)."""
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1])
    raise AssertionError(f'no VmRSS for process {pid}')


def callback_thread_cpu_s(pid: int) -> dict[int, float]:
    """
    Return the CPU time (s) of each thread of a process that runs Python on its own.

    Its threads but the main one (the executor's) and Fast DDS's (named dds.*): in cam_node,
    the OwnThread of each service and subscription, which take, handle and answer there.
    """
    times = {}
    for task in Path(f'/proc/{pid}/task').iterdir():
        try:
            name = (task / 'comm').read_text().strip()
            fields = (task / 'stat').read_text().rpartition(')')[2].split()
        except FileNotFoundError:  # the thread ended meanwhile
            continue
        if int(task.name) != pid and not name.startswith('dds.'):
            times[int(task.name)] = (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')
    return times


def percentiles(samples: Sequence[float], points: Sequence[float]) -> dict[str, float]:
    """Return the named percentiles (nearest rank) of samples, in ms."""
    ordered = sorted(samples)
    return {f'p{point:g}': 1e3 * ordered[max(0, math.ceil(point / 100 * len(ordered)) - 1)]
            for point in points}


class Child:
    """A helper process (children.py MODE ...) that talks in JSON lines on stdout."""

    def __init__(self, mode: str, *args: object, log_path: Path):
        self.log_path = log_path
        self._log = open(log_path, 'wb')
        self.process = subprocess.Popen(
            [sys.executable, str(CHILD), mode, *map(str, args)], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, stderr=self._log, text=True)

    def read(self, timeout: float = READY_TIMEOUT_S) -> dict:
        """Return the next JSON line the child prints (fail if it exits or stays silent)."""
        result: list[str] = []
        reader = threading.Thread(target=lambda: result.append(self.process.stdout.readline()),
                                  daemon=True)
        reader.start()
        reader.join(timeout)
        assert result and result[0], (f'child {self.process.args[2]} said nothing in {timeout} s '
                                      f'(exit {self.process.poll()}):\n{self.log()}')
        return json.loads(result[0])

    def tell(self, line: str) -> None:
        """Send one line to the child's stdin."""
        self.process.stdin.write(line + '\n')
        self.process.stdin.flush()

    def log(self) -> str:
        """Return what the child wrote on stderr."""
        return self.log_path.read_text(errors='replace')

    def kill(self) -> None:
        """SIGKILL the child and reap it."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        self._log.close()

    def finish(self, timeout: float) -> int:
        """Wait for the child to exit on its own and return its exit code."""
        try:
            return self.process.wait(timeout)
        finally:
            self._log.close()


def start_limited_node(params_file: Path, *ros_args: str, file_size_limit: int, cwd: Path,
                       client_node: Any) -> tuple[NodeProcess, Any]:
    """Start cam_node with RLIMIT_FSIZE = file_size_limit bytes and SIGXFSZ ignored.

    Like the start_cam_node fixture (same command, environment and matched client), but the
    limits are set by a tiny launcher that then execs the node, so no Python code runs between
    fork and exec of this threaded test process. The caller stops the process.
    """
    launcher = ('import os, resource, signal, sys; '
                'resource.setrlimit(resource.RLIMIT_FSIZE, (int(sys.argv[1]), int(sys.argv[1]))); '
                'signal.signal(signal.SIGXFSZ, signal.SIG_IGN); '
                'os.execv(sys.executable, [sys.executable, "-m", "cam_ros.node", *sys.argv[2:]])')
    log_path = cwd / f'cam-limited-{time.monotonic_ns()}.log'
    with open(log_path, 'wb') as log:
        process = subprocess.Popen(
            [sys.executable, '-c', launcher, str(file_size_limit), '--ros-args', '-r',
             '__node:=cam', '--params-file', str(params_file), *ros_args],
            stdout=log, stderr=subprocess.STDOUT, cwd=cwd, env=dict(os.environ))
    node = NodeProcess(process, log_path)
    try:
        client = matched_client(client_node, node)
    except BaseException:
        process.kill()
        process.wait()
        raise
    return node, client
