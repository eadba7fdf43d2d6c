"""
Publish one serialized JointState at a fixed rate: the source of the recorder throughput benchmark.

Run as ``python -m benchmarks.paced_publisher TOPIC RATE_HZ SECONDS --ros-args -r __node:=NAME``.
Prints {"matched": true} once a subscriber is matched, then waits for a line on stdin (the
benchmark checks that the subscriber has matched this publisher too: a reliable keep-last-10
writer loses what it sends before), publishes RATE_HZ * SECONDS messages on a 1 ms schedule
(cam_node's state QoS), prints {"published": n, "seconds": s} and lingers so that reliable
delivery completes.
"""
from __future__ import annotations

import json
import sys
import time
from typing import Sequence

import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.serialization import serialize_message
from rclpy.utilities import remove_ros_args
from sensor_msgs.msg import JointState

#: cam_node's state topic QoS (node.py STATE_QOS).
QOS = QoSProfile(depth=10)
#: Longest wait for the subscriber (s); pause before exiting (s).
MATCH_TIMEOUT_S = 30.0
LINGER_S = 0.25
#: The schedule's step (s): every step publishes the messages that have fallen due.
STEP_S = 0.001


def sample_message() -> bytes:
    """Return the CDR bytes of a JointState shaped like cam_node's state message."""
    message = JointState(name=['cam', 'follower'], position=[1.0, 0.01], velocity=[6.28, 0.02])
    message.header.frame_id = 'cam'
    return serialize_message(message)


def publish_paced(publisher: object, data: bytes, rate_hz: float, count: int) -> float:
    """Publish count messages at rate_hz; return the seconds it took."""
    published, start = 0, time.monotonic()
    while published < count:
        due = min(count, int((time.monotonic() - start) * rate_hz) + 1)
        while published < due:
            publisher.publish(data)  # type: ignore[attr-defined]
            published += 1
        time.sleep(STEP_S)
    return time.monotonic() - start


def main(args: Sequence[str] | None = None) -> int:
    """Publish at the given rate when told to, once a subscriber is matched; report it."""
    argv = list(sys.argv if args is None else args)
    topic, rate_hz, seconds = remove_ros_args(argv)[1:4]
    rclpy.init(args=argv)
    node = Node('paced_publisher')
    publisher = node.create_publisher(JointState, topic, QOS)
    try:
        deadline = time.monotonic() + MATCH_TIMEOUT_S
        while publisher.get_subscription_count() < 1:
            if time.monotonic() > deadline:
                print(f'no subscriber on {topic} after {MATCH_TIMEOUT_S} s', file=sys.stderr)
                return 1
            time.sleep(0.01)
        print(json.dumps({'matched': True}), flush=True)
        if not sys.stdin.readline():
            return 1
        count = max(1, round(float(rate_hz) * float(seconds)))
        elapsed = publish_paced(publisher, sample_message(), float(rate_hz), count)
        print(json.dumps({'published': count, 'seconds': elapsed}), flush=True)
        time.sleep(LINGER_S)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
