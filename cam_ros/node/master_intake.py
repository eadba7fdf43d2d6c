"""
Take the master axis's messages on a thread of their own as they arrive, skipping a backlog.

Also the conversions every e-cam endpoint shares: stamps in ns, the WIRING parameters a running
node refuses to change.
"""
from __future__ import annotations

from typing import Any, Callable

from rcl_interfaces.msg import SetParametersResult
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.subscription import Subscription
from sensor_msgs.msg import JointState

from cam_ros.node.own_thread import OwnThread

#: Reliable, keep last 1000: a 1 kHz master loses nothing while the node is held up for 1 s.
#: Best effort: it matches a best-effort master (the sensor-data QoS many drivers publish with)
#: and a reliable one alike; a reliable subscription would never hear the former.
MASTER_QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.BEST_EFFORT)
#: A master message waiting this long behind a newer one is a backlog: skipped (s).
LATE_S = 0.01
#: Parameters that wire the node to the graph: fixed once the node runs (an axis's
#: <axis>.slave.state_topic too).
WIRING = ('master.source', 'master.topic', 'master.joint', 'slave.state_topic')


def stamp_ns(stamp: Any) -> int:
    """Return a builtin_interfaces/Time as integer nanoseconds."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def refuse_rewiring(node: Node) -> None:
    """Make the node refuse updates of the WIRING parameters (they need a restart)."""
    def check(updates: list[Parameter]) -> SetParametersResult:
        for param in updates:
            wiring = param.name in WIRING or param.name.endswith(
                tuple(f'.{name}' for name in WIRING))
            if wiring and param.value != node.get_parameter(param.name).value:
                return SetParametersResult(successful=False, reason=(
                    f'{param.name} = {param.value!r}: is fixed while the node runs (now '
                    f'{node.get_parameter(param.name).value!r}); restart the node to change it'))
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(check)


def master_intake(node: Node, topic: str, callback: Callable[[JointState, int, int], None]
                  ) -> OwnThread[Subscription]:
    """
    Take master messages on a thread of their own, skipping a backlog.

    The node's executor rebuilds a wait set of all its services, timers and subscriptions for
    every message; this thread waits on the master subscription alone, so a busy node adds no
    latency between master and command. A node held up skips the backlog: callback(message,
    arrival ns, skipped count) gets the newest message and those that arrived within LATE_S
    before it, so it never commands late. Callbacks run on this thread; OwnThread.stop() ends
    it.
    """
    # No QoS event handlers (see TakenByIntake): best effort, volatile, no deadline and
    # automatic liveliness, MASTER_QOS matches every publisher, so none would ever fire.
    return OwnThread.newest(
        node, JointState, topic, callback, MASTER_QOS, 'master', int(LATE_S * 1e9),
        event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False))
