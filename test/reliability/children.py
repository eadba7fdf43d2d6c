"""Helper processes of the reliability tests (run as `python children.py MODE ...`, not by pytest).

Modes (each prints JSON lines on stdout; ROS_DOMAIN_ID comes from the test's environment):

  load SECONDS SEED CONFIG   after a warm-up prints {"ready": true}, waits for a line on stdin,
                             then calls /cam/evaluate with batches of random size for SECONDS,
                             checks every answer against the core's evaluation of CONFIG and
                             prints {"calls", "failures", "missing", "latencies_s"}.
  vanish COUNT               prints {"ready": true} once the service is up, waits for a line on
                             stdin, sends one request of COUNT angles, prints {"sent": true} and
                             waits for ever: the test kills it before the answer arrives.
  lazy                       subscribes to the node's state topics twice, with a node that is never
                             spun (messages pile up in DDS) and with a callback that blocks for
                             ever; prints {"ready": true} once both see the publisher.
"""
from __future__ import annotations

import json
import sys
import threading
import time

import numpy as np
import rclpy
from cam_ros_interfaces.srv import EvaluateCam
from geometry_msgs.msg import Vector3Stamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from cam_ros.client import CLIENT_QOS

SERVICE = '/cam/evaluate'
#: An answer later than this counts as missing. Long: on a loaded machine a call can wait
#: seconds for the CPU, and a lost answer never arrives however long one waits.
CALL_TIMEOUT_S = 60.0
WAIT_S = 30.0
WARM_UP_CALLS = 20
BATCH_SIZES = (1, 10, 100, 1000)
ANGLE_RANGE_RAD = 50.0  # angles drawn from [-50, 50] rad: several turns both ways
RESPONSE_FIELDS = ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                   'radius_of_curvature')
KEEP_ALL = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)


def say(**fields: object) -> None:
    """Print one JSON line."""
    print(json.dumps(fields), flush=True)


def spinning(node: rclpy.node.Node) -> tuple[SingleThreadedExecutor, threading.Thread]:
    """Spin node in a daemon thread; return the executor and the thread."""
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    return executor, thread


def service_client(node: rclpy.node.Node) -> rclpy.client.Client:
    """
    Return an EvaluateCam client whose service is up.

    Its reply reader is CamClient's (CLIENT_QOS): rmw_fastrtps sends every reply to every
    client (ros2/rmw_fastrtps#559), and with ROS's default depth of 10 a client of several busy
    ones, slowed by a loaded machine, finds its own reply pushed out and waits in vain.
    """
    client = node.create_client(EvaluateCam, SERVICE, qos_profile=CLIENT_QOS)
    if not client.wait_for_service(timeout_sec=WAIT_S):
        raise SystemExit(f'{SERVICE} not available')
    return client


def load(seconds: float, seed: int, config: str) -> None:
    """Call the service for a while, checking each answer; report counts and latencies."""
    from cam_ros.core import build_design, load_config

    design = build_design(load_config(config))
    node = rclpy.create_node(f'load_client_{seed}')
    executor, thread = spinning(node)
    client = service_client(node)
    rng = np.random.default_rng(seed)
    calls = failures = missing = 0
    latencies: list[float] = []
    problems: list[str] = []

    def call() -> None:
        nonlocal calls, failures, missing
        angles = rng.uniform(-ANGLE_RANGE_RAD, ANGLE_RANGE_RAD, rng.choice(BATCH_SIZES))
        start = time.perf_counter()
        response = client.call(EvaluateCam.Request(angles=angles.tolist()),
                               timeout_sec=CALL_TIMEOUT_S)
        latencies.append(time.perf_counter() - start)
        calls += 1
        if response is None:
            missing += 1
            return
        expected = design.evaluate(angles)
        wrong = [field for field in RESPONSE_FIELDS
                 if not np.array_equal(getattr(response, field), getattr(expected, field))]
        if not response.success or wrong:
            failures += 1
            problems.append(f'{response.message}; wrong fields {wrong}')

    for _ in range(WARM_UP_CALLS):
        call()
    say(ready=True, warm_up_failures=failures + missing)
    sys.stdin.readline()
    calls = failures = missing = 0
    latencies.clear()
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        call()
    say(calls=calls, failures=failures, missing=missing, latencies_s=latencies,
        problems=problems[:5])
    executor.shutdown()
    thread.join()
    node.destroy_node()


def vanish(count: int) -> None:
    """Send one big request and never collect the answer."""
    node = rclpy.create_node('vanishing_client')
    spinning(node)
    client = service_client(node)
    request = EvaluateCam.Request(angles=np.linspace(0.0, 2.0 * np.pi, count, endpoint=False))
    say(ready=True)
    sys.stdin.readline()
    client.call_async(request)
    say(sent=True)
    time.sleep(3600.0)


def lazy() -> None:
    """Subscribe and never read: one node never spun, one whose callback blocks for ever."""
    never_spun = rclpy.create_node('never_spun_listener')
    blocked = rclpy.create_node('blocked_listener')
    subscriptions = [never_spun.create_subscription(JointState, '/cam/joint_states',
                                                    lambda message: None, KEEP_ALL),
                     never_spun.create_subscription(Vector3Stamped, '/cam/state_extras',
                                                    lambda message: None, KEEP_ALL)]
    started = threading.Event()

    def block(message: JointState) -> None:
        started.set()
        time.sleep(3600.0)

    subscriptions.append(blocked.create_subscription(JointState, '/cam/joint_states', block,
                                                     KEEP_ALL))
    spinning(blocked)
    deadline = time.monotonic() + WAIT_S
    while not (started.is_set() and all(s.get_publisher_count() for s in subscriptions)):
        if time.monotonic() > deadline:
            raise SystemExit('the node\'s topics never matched')
        time.sleep(0.01)
    say(ready=True)
    time.sleep(3600.0)


def main(argv: list[str]) -> None:
    """Run one mode."""
    rclpy.init()
    mode, args = argv[0], argv[1:]
    if mode == 'load':
        load(float(args[0]), int(args[1]), args[2])
    elif mode == 'vanish':
        vanish(int(args[0]))
    elif mode == 'lazy':
        lazy()
    else:
        raise SystemExit(f'unknown mode {mode}')
    rclpy.try_shutdown()


if __name__ == '__main__':
    main(sys.argv[1:])
