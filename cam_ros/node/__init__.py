"""cam_node: everything that runs the cam design on rclpy (node, parameters, recording, master)."""
from .process import main

__all__ = ['main']
