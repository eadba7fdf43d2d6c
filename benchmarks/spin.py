"""Spin a floor node of the benchmarks until Ctrl-C or SIGTERM, the Jazzy shutdown idiom."""
from __future__ import annotations

import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node


def spin_until_shutdown(node: Node) -> int:
    """Spin node in a SingleThreadedExecutor until shutdown; destroy it and return 0."""
    executor = SingleThreadedExecutor()
    try:
        executor.add_node(node)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0
