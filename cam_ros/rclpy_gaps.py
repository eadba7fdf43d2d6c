"""The rclpy internals cam_ros needs, in one place: rclpy (Jazzy) has no public API for them.

- A wait set over chosen entities: rclpy's own executors and `wait_for_message` build theirs
  from `rclpy.impl.implementation_singleton.rclpy_implementation.WaitSet`; no public class
  wraps it.
- RCLError, what rcl raises (e.g. for bad `--ros-args` in `rclpy.init`): it lives in the C
  extension and `rclpy.exceptions` does not re-export it.
- A LifecycleNode's state machine and its ~/change_state service: rclpy keeps both private (no
  public getter for the current state's transitions, none to guard the service's callback).
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


def state_machine(node: Any) -> Any:
    """Return a LifecycleNode's state machine (current_state, available_transitions)."""
    return node._state_machine


def change_state_service(node: Any) -> Any:
    """Return a LifecycleNode's ~/change_state service (its callback may be replaced)."""
    return node._service_change_state
