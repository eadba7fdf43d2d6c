"""
A reader of one topic in a process of its own, as `ros2 bag record` is: for the publish loop.

Run as ``python -m benchmarks.remote_reader TOPIC``: subscribes to TOPIC (sensor_msgs/JointState,
the Recorder's QoS for cam_node's state) with a raw subscription that drops every message, until
Ctrl-C or SIGTERM. Served as cam_node is (UDP alone), so publish() pays what an out-of-process
recorder would cost it.
"""
from __future__ import annotations

import sys
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


def main(args: Sequence[str] | None = None) -> int:
    """Read TOPIC until Ctrl-C or SIGTERM."""
    argv = list(sys.argv if args is None else args)
    topic = remove_ros_args(argv)[1]
    serve_over_udp()
    rclpy.init(args=argv)
    node = Node('remote_reader')
    node.create_subscription(JointState, topic, lambda data: None, BARE_QOS, raw=True)
    return spin_until_shutdown(node)


if __name__ == '__main__':
    sys.exit(main())
