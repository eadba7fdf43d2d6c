"""
What an electronic cam node publishes beside its commands, for recordings and for PLC logic.

~/engage_requests (cam_ros_interfaces/msg/EngageRequest): every ~/engage call answered, stamped
with the last master message followed before it, so that `cam_ros replay` makes the call again
at the same place of the master stream (cam_ros.recording.engage_replay). ~/switch_state
(cam_ros_interfaces/msg/SwitchState): every ~/switches word with the stamp and the position of
the master message it was found at. Both are latched (a late recorder gets the last call, which
says whether the slave was to be engaged when it started). The recorder also takes the slave's
reported state (slave.state_topic): where a first engagement starts.
"""
from __future__ import annotations

from typing import Sequence

from cam_ros_interfaces.msg import EngageRequest, SwitchState
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.time import Time
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool

from cam_ros.node.qos_events import publisher
from cam_ros.recording import TopicSpec


class EcamLog:
    """Publish the node's answered ~/engage calls and its stamped switch words."""

    def __init__(self, node: Node, latched: QoSProfile, slave_topics: Sequence[str],
                 slave_qos: QoSProfile):
        """Create ~/engage_requests and ~/switch_state with the latched QoS of ~/switches."""
        self._engage_pub = publisher(node, EngageRequest, '~/engage_requests', latched)
        self._switch_pub = publisher(node, SwitchState, '~/switch_state', latched)
        self._slave = [TopicSpec(topic, JointState, slave_qos) for topic in slave_topics]

    def topics(self) -> list[TopicSpec]:
        """Return the slave's state and both topics, for the recorder."""
        return self._slave + [TopicSpec(pub.topic_name, pub.msg_type, pub.qos_profile)
                              for pub in (self._engage_pub, self._switch_pub)]

    def engaged(self, request: SetBool.Request, response: SetBool.Response,
                last_stamp_ns: int | None) -> None:
        """Publish an answered ~/engage call after the master message stamped last_stamp_ns.

        None: the node had followed no master message yet.
        """
        message = EngageRequest(master_followed=last_stamp_ns is not None, engage=request.data,
                                success=response.success, message=response.message)
        if last_stamp_ns is not None:
            message.header.stamp = Time(nanoseconds=last_stamp_ns).to_msg()
        self._engage_pub.publish(message)

    def switched(self, stamp_ns: int, master_position: float, word: int) -> None:
        """Publish a switch word found at the line shaft's step stamped stamp_ns."""
        message = SwitchState(master_position=master_position, bits=word)
        message.header.stamp = Time(nanoseconds=stamp_ns).to_msg()
        self._switch_pub.publish(message)
