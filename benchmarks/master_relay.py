"""
The floor of the electronic cam latency benchmark: a bare relay node.

Run as ``python -m benchmarks.master_relay --ros-args -r __node:=NAME``: subscribes to
``~/master`` (sensor_msgs/JointState, cam_node's master QoS) and publishes the first position as
``~/commands`` (std_msgs/Float64MultiArray), nothing else.
Served as cam_node is (serve_over_udp: UDP only), so the ratio measures the node, not the
transport.
"""
from __future__ import annotations

import sys
from typing import Sequence

import rclpy
from rclpy.node import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray

from benchmarks.spin import spin_until_shutdown
from cam_ros.node.command_topics import COMMAND_QOS
from cam_ros.node.master_intake import MASTER_QOS
from cam_ros.node.middleware import serve_over_udp


def main(args: Sequence[str] | None = None) -> int:
    """Relay master positions to commands until Ctrl-C."""
    serve_over_udp()
    rclpy.init(args=list(sys.argv if args is None else args))
    node = Node('master_relay')
    publisher = node.create_publisher(Float64MultiArray, '~/commands', COMMAND_QOS)
    node.create_subscription(
        JointState, '~/master',
        lambda message: publisher.publish(Float64MultiArray(data=[message.position[0]])),
        MASTER_QOS)
    return spin_until_shutdown(node)


if __name__ == '__main__':
    sys.exit(main())
