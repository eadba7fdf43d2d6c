"""A long-lived cam client process of the network tests (`python children.py CONFIG`).

Its node spins in a background thread; a CamClient calls /cam/evaluate from the main thread and
a subscription keeps the header stamp of every /cam/joint_states message. Once the service has
answered it prints {"ready": true, "first_answer_s": ...}; then it reads one JSON command per
line on stdin and answers each with one JSON line:

  {"do": "calls", "count": N, "timeout": T}  N one-angle calls (no retries): latencies of the
                                             answered ones, failures, answers that differ
                                             from the core's evaluation of CONFIG
  {"do": "first_answer", "within": S}        seconds until a call is answered (null: none)
  {"do": "stamps"}                           joint_states stamps (ns) received since last asked
  {"do": "set", "name": P, "value": V}       set a parameter of /cam; its result (reason)
  {"do": "record", "path": F, "seconds": S}  record /cam/joint_states and /cam/profile to F
                                             (cam_ros.recording) for S seconds; the stamps
                                             this subscription received meanwhile
  {"do": "exit"}
"""
from __future__ import annotations

import json
import sys
import threading
import time

import numpy as np
import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

from cam_ros.client import CamClient, CamClientError, FIELDS
from cam_ros.core import build_design, load_config
from cam_ros.node.middleware import use_shipped_profile
from cam_ros.recording import Recorder, TopicSpec

READY_WITHIN_S = 60.0
SET_TIMEOUT_S = 10.0
PROBE_TIMEOUT_S = 0.25
KEEP_ALL = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
RECORDED = (TopicSpec('/cam/joint_states', JointState, QoSProfile(depth=10)),
            TopicSpec('/cam/profile', JointTrajectory, QoSProfile(
                depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)))


def say(**fields: object) -> None:
    """Print one JSON line."""
    print(json.dumps(fields), flush=True)


class Probe:
    """The client's node, its CamClient and its joint_states stamps."""

    def __init__(self, config: str):
        self.design = build_design(load_config(config))
        self.node = rclpy.create_node(f'net_client_{threading.get_native_id()}')
        self.client = CamClient(self.node)
        self.rng = np.random.default_rng()
        self._stamps: list[int] = []
        self._lock = threading.Lock()
        self.node.create_subscription(JointState, '/cam/joint_states', self._stamp, KEEP_ALL)

    def _stamp(self, message: JointState) -> None:
        with self._lock:
            self._stamps.append(message.header.stamp.sec * 10**9 + message.header.stamp.nanosec)

    def stamps(self) -> dict:
        with self._lock:
            stamps, self._stamps = self._stamps, []
        return {'stamps_ns': stamps}

    def calls(self, count: int, timeout: float) -> dict:
        latencies, failures, wrong = [], [], 0
        for angle in self.rng.uniform(0.0, 2 * np.pi, count):
            start = time.perf_counter()
            try:
                result = self.client.evaluate([angle], timeout=timeout, retries=0)
            except CamClientError as err:
                failures.append(str(err))
                continue
            latencies.append(time.perf_counter() - start)
            expected = self.design.evaluate(np.array([angle]))
            wrong += any(not np.array_equal(getattr(result, name), getattr(expected, name))
                         for name in FIELDS if hasattr(expected, name))
        return {'latencies_s': latencies, 'failures': failures, 'wrong': wrong}

    def set(self, name: str, value: object) -> dict:
        parameters = AsyncParameterClient(self.node, '/cam')
        if not parameters.wait_for_services(SET_TIMEOUT_S):
            return {'successful': None, 'reason': 'no parameter services'}
        future = parameters.set_parameters([Parameter(name, value=value)])
        done = threading.Event()
        future.add_done_callback(lambda _: done.set())
        if not done.wait(SET_TIMEOUT_S):
            return {'successful': None, 'reason': 'no answer'}
        result = future.result().results[0]
        return {'successful': result.successful, 'reason': result.reason}

    def record(self, path: str, seconds: float) -> dict:
        self.stamps()
        with Recorder(self.node, path, RECORDED):
            time.sleep(seconds)
        return self.stamps()

    def first_answer(self, within: float) -> dict:
        start = time.monotonic()
        while time.monotonic() - start < within:
            try:
                self.client.evaluate([0.0], timeout=PROBE_TIMEOUT_S, retries=0)
            except CamClientError:
                continue
            return {'seconds': time.monotonic() - start}
        return {'seconds': None}


def main(config: str) -> None:
    """Serve the test's commands until told to exit."""
    use_shipped_profile()
    rclpy.init()
    probe = Probe(config)
    executor = SingleThreadedExecutor()
    executor.add_node(probe.node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        say(ready=True, first_answer_s=probe.first_answer(READY_WITHIN_S)['seconds'])
        for line in sys.stdin:
            command = json.loads(line)
            action = command.pop('do')
            if action == 'exit':
                break
            say(**getattr(probe, action)(**command))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown()
        thread.join()
        probe.node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main(sys.argv[1])
