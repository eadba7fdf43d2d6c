"""
Publish one serialized JointState as fast as possible: the recorder throughput benchmark's source.

Run as ``python flood_publisher.py TOPIC SECONDS --ros-args -r __node:=NAME``. Waits for one
subscriber, lets discovery settle, publishes back-to-back for SECONDS, then prints one JSON line
{"start": s, "end": s, "published": n} with CLOCK_MONOTONIC times (shared by all processes)
and lingers SETTLE_S so that reliable delivery completes.
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
from sensor_msgs.msg import JointState

#: Offered QoS: reliable, keep last 100 (the recorder's own minimum subscription depth).
QOS = QoSProfile(depth=100)
#: Longest wait for the subscriber (s), and the pause after it is matched (s).
MATCH_TIMEOUT_S = 30.0
SETTLE_S = 0.5
#: Messages published between clock reads.
BURST = 100


def sample_message() -> bytes:
    """Return the CDR bytes of a JointState shaped like cam_node's state message."""
    message = JointState(name=['cam', 'follower'], position=[1.0, 0.01], velocity=[6.28, 0.02])
    message.header.frame_id = 'cam'
    return serialize_message(message)


def main(args: Sequence[str] | None = None) -> int:
    """Flood the topic for the given seconds once a subscriber is matched."""
    argv = list(sys.argv if args is None else args)
    topic, seconds = argv[1], float(argv[2])
    rclpy.init(args=argv)
    node = Node('flood_publisher')
    publisher = node.create_publisher(JointState, topic, QOS)
    data = sample_message()
    try:
        deadline = time.monotonic() + MATCH_TIMEOUT_S
        while publisher.get_subscription_count() < 1:
            if time.monotonic() > deadline:
                print(f'no subscriber on {topic} after {MATCH_TIMEOUT_S} s', file=sys.stderr)
                return 1
            time.sleep(0.01)
        time.sleep(SETTLE_S)
        published, start = 0, time.monotonic()
        end = start
        while end - start < seconds:
            for _ in range(BURST):
                publisher.publish(data)
            published += BURST
            end = time.monotonic()
        print(json.dumps({'start': start, 'end': end, 'published': published}), flush=True)
        time.sleep(SETTLE_S)  # let reliable delivery finish before the writer goes away
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
