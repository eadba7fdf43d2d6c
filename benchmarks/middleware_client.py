"""
The client process of the middleware benchmark (``python -m benchmarks.middleware_client``).

Subscribes to /cam/joint_states (as a monitoring node would) and calls /cam/evaluate with one
angle through CamClient. Prints {"ready": true} after a first
answer; then for each line N on stdin makes N calls and prints their round trips (ns) as one
JSON list; exits at end of input. The Fast DDS profile comes from the environment.
"""
from __future__ import annotations

import json
import sys
import threading
import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from sensor_msgs.msg import JointState

from cam_ros.client import CamClient

FIRST_ANSWER_TIMEOUT_S = 1.0
FIRST_ANSWER_ATTEMPTS = 60
CALL_TIMEOUT_S = 10.0


def main() -> None:
    """Answer the benchmark's requests for timed calls until stdin closes."""
    rclpy.init()
    node = rclpy.create_node('middleware_bench_client')
    node.create_subscription(JointState, '/cam/joint_states', lambda _: None, 10)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    client = CamClient(node)
    try:
        client.evaluate([1.0], timeout=FIRST_ANSWER_TIMEOUT_S, retries=FIRST_ANSWER_ATTEMPTS)
        print(json.dumps({'ready': True}), flush=True)
        for line in sys.stdin:
            round_trips = []
            for _ in range(int(line)):
                start = time.perf_counter_ns()
                client.evaluate([1.0], timeout=CALL_TIMEOUT_S, retries=0)
                round_trips.append(time.perf_counter_ns() - start)
            print(json.dumps(round_trips), flush=True)
    finally:
        executor.shutdown()
        thread.join()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
