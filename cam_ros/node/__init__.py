"""cam_node: everything that runs the cam design on rclpy (node, parameters, recording, master)."""
from .node import main

__all__ = ['main']
