"""Warn, naming the topic, when a peer's QoS can never match one of the node's publishers.

rclpy's own default warning names the topic as written ('~/commands'); this one names the
resolved topic and the policy. LATCHED is the QoS of every latched topic of the node.
"""
from typing import Any, Callable

from rclpy.event_handler import PublisherEventCallbacks
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import (DurabilityPolicy, qos_policy_name_from_kind, QoSProfile,
                       ReliabilityPolicy)

#: Latched topics (profiles, ~/switches, ~/state, ...): a late subscriber gets the last message.
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)


def _warning(node: Node, topic: str, peer: str) -> Callable[[Any], None]:
    resolved = node.resolve_topic_name(topic)

    def warn(event: Any) -> None:
        policy = qos_policy_name_from_kind(event.last_policy_kind)
        node.get_logger().warning(
            f'incompatible QoS on {resolved}: a {peer} whose {policy} policy cannot match this '
            f'node\'s ({event.total_count} so far); no messages pass between them')
    return warn


def publisher(node: Node, msg_type: Any, topic: str, qos: QoSProfile) -> Publisher:
    """Create a publisher of the node whose incompatible subscriptions are warned about."""
    return node.create_publisher(msg_type, topic, qos, event_callbacks=PublisherEventCallbacks(
        incompatible_qos=_warning(node, topic, 'subscription')))
