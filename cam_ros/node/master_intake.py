"""
Take the master axis's messages on a thread of their own, each as soon as it arrives.

Also the conversions every e-cam endpoint shares: stamps in ns, the WIRING parameters a running
node refuses to change.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

from rcl_interfaces.msg import SetParametersResult
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.exceptions import InvalidHandle
from rclpy.guard_condition import GuardCondition
# rclpy has no public wait set; its executors and wait_for_message use this one.
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from cam_ros.rclpy_gaps import wait_set
from cam_ros.recording.intake import TakenByIntake

#: Reliable, keep last 1000: a 1 kHz master loses nothing while the node is held up for 1 s.
#: Best effort: it matches a best-effort master (the sensor-data QoS many drivers publish with)
#: and a reliable one alike; a reliable subscription would never hear the former.
MASTER_QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.BEST_EFFORT)
#: Parameters that wire the node to the graph: fixed once the node runs.
WIRING = ('master.source', 'master.topic', 'master.joint', 'slave.state_topic')


def stamp_ns(stamp: Any) -> int:
    """Return a builtin_interfaces/Time as integer nanoseconds."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def refuse_rewiring(node: Node) -> None:
    """Make the node refuse updates of the WIRING parameters (they need a restart)."""
    def check(updates: list[Parameter]) -> SetParametersResult:
        for param in updates:
            if param.name in WIRING and param.value != node.get_parameter(param.name).value:
                return SetParametersResult(successful=False, reason=(
                    f'{param.name} = {param.value!r}: is fixed while the node runs (now '
                    f'{node.get_parameter(param.name).value!r}); restart the node to change it'))
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(check)


class MasterIntake:
    """
    Take master messages on a thread of their own, each as soon as it arrives.

    The node's executor rebuilds a wait set of all its services, timers and subscriptions for
    every message; this thread waits on the master subscription alone, so a busy node adds no
    latency between master and command. Callbacks run on this thread.
    """

    def __init__(self, node: Node, topic: str, callback: Callable[[JointState], None]):
        self._callback = callback
        self._stop = threading.Event()
        # No QoS event handlers (see TakenByIntake): best effort, volatile, no deadline and
        # automatic liveliness, MASTER_QOS matches every publisher, so none would ever fire.
        self.subscription = node.create_subscription(
            JointState, topic, callback, MASTER_QOS, callback_group=TakenByIntake(),
            event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False))
        self._wake = GuardCondition(None, None, context=node.context)
        self._wait_set = wait_set(node.context, 1, 1)
        self._node = node
        self._thread = threading.Thread(target=self._run, name='master', daemon=True)
        self._thread.start()

    def _run(self) -> None:
        subscription, wait_set = self.subscription, self._wait_set
        try:
            while not self._stop.is_set():
                with subscription.handle, self._wake.handle:
                    taken = subscription.handle.take_message(JointState, False)
                    if taken is not None:
                        self._callback(taken[0])
                        continue
                    wait_set.clear_entities()
                    wait_set.add_subscription(subscription.handle)
                    wait_set.add_guard_condition(self._wake.handle)
                    wait_set.wait(-1)
        except InvalidHandle:
            pass  # the node went away under the thread

    def stop(self) -> None:
        """End the thread and destroy the subscription."""
        self._stop.set()
        self._wake.trigger()
        self._thread.join()
        self._node.destroy_subscription(self.subscription)
        self._wake.destroy()
