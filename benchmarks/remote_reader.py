"""
A reader of one topic in a process of its own, as `ros2 bag record` is: for the publish loop.

Run as ``python -m benchmarks.remote_reader TOPIC``: subscribes to TOPIC (sensor_msgs/JointState,
the Recorder's QoS for cam_node's state) with a raw subscription that drops every message, prints
{"matched": b} once it has matched a publisher (or after WAIT_S) and reads until stdin closes
(its host ends it so, or by dying), Ctrl-C or SIGTERM. Served as cam_node is (UDP alone), so
publish() pays what an out-of-process recorder would cost it.
"""
from __future__ import annotations

import json
import os
import signal
import sys
import threading
import time
from typing import Sequence

import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.utilities import remove_ros_args
from sensor_msgs.msg import JointState

from benchmarks.spin import spin_until_shutdown
from cam_ros.node.middleware import serve_over_udp
from cam_ros.node.node import STATE_QOS
from cam_ros.recording.writer import MIN_SUBSCRIPTION_DEPTH

#: The Recorder's QoS for STATE_QOS: every reader of the publish loop subscribes with it.
BARE_QOS = QoSProfile(depth=max(STATE_QOS.depth, MIN_SUBSCRIPTION_DEPTH))
#: Longest wait for the subscription to match the publisher (s).
WAIT_S = 10.0


def main(args: Sequence[str] | None = None) -> int:
    """Read TOPIC until stdin closes, Ctrl-C or SIGTERM."""
    argv = list(sys.argv if args is None else args)
    topic = remove_ros_args(argv)[1]
    serve_over_udp()
    rclpy.init(args=argv)
    node = Node('remote_reader')
    subscription = node.create_subscription(JointState, topic, lambda data: None, BARE_QOS,
                                            raw=True)
    deadline = time.monotonic() + WAIT_S
    while subscription.get_publisher_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    try:
        print(json.dumps({'matched': subscription.get_publisher_count() > 0}), flush=True)
    except BrokenPipeError:  # the host is gone already; no second error when stdout closes
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        node.destroy_node()
        rclpy.try_shutdown()
        return 0
    threading.Thread(target=_end_with_stdin, daemon=True).start()
    return spin_until_shutdown(node)


def _end_with_stdin() -> None:
    """Stop the reader as Ctrl-C would once stdin closes (its host closed it or died)."""
    sys.stdin.read()
    os.kill(os.getpid(), signal.SIGINT)


if __name__ == '__main__':
    sys.exit(main())
