"""The rclpy internals cam_ros needs, in one place: rclpy (Jazzy) has no public API for them.

- A wait set over chosen entities: rclpy's own executors and `wait_for_message` build theirs
  from `rclpy.impl.implementation_singleton.rclpy_implementation.WaitSet`; no public class
  wraps it.
- RCLError, what rcl raises (e.g. for bad `--ros-args` in `rclpy.init`): it lives in the C
  extension and `rclpy.exceptions` does not re-export it.
"""
from typing import Any

from rclpy.context import Context
from rclpy.impl.implementation_singleton import rclpy_implementation as _implementation

RCLError: type[Exception] = _implementation.RCLError


def wait_set(context: Context, subscriptions: int, guard_conditions: int,
             services: int = 0) -> Any:
    """Return an empty rcl wait set with room for this many of each kind of entity."""
    return _implementation.WaitSet(subscriptions, guard_conditions, 0, 0, services, 0,
                                   context.handle)
