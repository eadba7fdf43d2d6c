"""Make a recording's ~/engage calls again, each at the master message where its node took it.

An electronic cam node publishes every ~/engage call it answers on ~/engage_requests
(cam_ros_interfaces/msg/EngageRequest), stamped with the last master message it had followed.
The call is due before the next recorded master message of that node (its ~/state names the
master topic), as at_master_messages does for parameter changes; a call made before any master
message is due before the first one. The node's service is ~/engage beside the topic.
"""

from dataclasses import dataclass

from rclpy.time import Time

from cam_ros.recording.parameter_replay import master_topics
from cam_ros.recording.reader import Recording
from cam_ros.recording.schedule import master_stamps, next_master_message

ENGAGE_TYPE = 'cam_ros_interfaces/msg/EngageRequest'


@dataclass(frozen=True)
class EngageCall:
    """One recorded ~/engage call: when it is due, on which node, the request and the answer."""

    time_ns: int
    node: str
    engage: bool
    success: bool
    message: str

    @property
    def service(self) -> str:
        """Return the node's ~/engage service."""
        return f'{self.node}/engage'


def engage_topics(recording: Recording) -> list[str]:
    """Return the recorded ~/engage_requests topics (type EngageRequest)."""
    return [name for name, info in recording.topics.items() if info.type == ENGAGE_TYPE]


def engage_calls(recording: Recording, topics: list[str]) -> list[EngageCall]:
    """Return the calls recorded on topics (engage_topics), in due order."""
    masters = master_topics(recording)
    calls = []
    for topic in topics:
        node = topic.rpartition('/')[0]
        stamps = master_stamps(recording, masters[node]) if node in masters else []
        for recorded in recording.messages([topic]):
            request = recorded.message
            after = (Time.from_msg(request.header.stamp).nanoseconds
                     if request.master_followed else None)
            calls.append(EngageCall(next_master_message(stamps, after, recorded.log_time_ns),
                                    node, request.engage, request.success, request.message))
    return sorted(calls, key=lambda call: call.time_ns)
