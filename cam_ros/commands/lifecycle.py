"""`cam_ros lifecycle get|set`: a managed cam node's state, as `ros2 lifecycle` gives it.

Through the node's lifecycle services (~/get_state, ~/get_available_transitions,
~/change_state), so a machine without the ROS CLI can bring cam_node up and down. ChangeState
answers only true or false; a refused transition's reason is the error line the node logs for
it, read from /rosout.
"""
from __future__ import annotations

import time
from typing import Any

from cam_ros.commands.common import say
from cam_ros.commands.ros import DEFAULT_TIMEOUT_S, request_once, ros_node
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

DEFAULT_NODE = '/cam'
#: The transitions `set` takes and the primary state each one ends in.
ENDS_IN = {'configure': 'inactive', 'activate': 'active', 'deactivate': 'inactive',
           'cleanup': 'unconfigured', 'shutdown': 'finalized'}
#: Longest wait for the node's log line saying why it refused, after its answer.
REASON_WAIT_S = 1.0
SPIN_S = 0.05
#: A refusal logged this long before the request is still ours (clocks of two processes).
CLOCK_SLACK_NS = 1_000_000_000


class _Session:
    """One private ROS node asking a cam node's lifecycle services before one deadline."""

    def __init__(self, ros: tuple[Any, Any], node: str, timeout: float):
        self.node, self.executor = ros
        self.name = self.node.resolve_service_name(node)  # 'cam' -> '/cam'
        self.timeout = timeout
        self.deadline = time.monotonic() + timeout

    def ask(self, service_type: Any, service: str, request: Any) -> Any:
        """Return the node's answer; None after saying why there was none."""
        response, problem = request_once(self.node, self.executor, service_type,
                                         f'{self.name}/{service}', request, self.deadline,
                                         self.timeout)
        if response is None:
            say('lifecycle', problem)
        return response


def get(node: str = DEFAULT_NODE, timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Print the node's state as `ros2 lifecycle get` does: 'active [3]'; 1 if unanswered."""
    from lifecycle_msgs.srv import GetState

    with ros_node('lifecycle') as ros:
        answer = _Session(ros, node, timeout).ask(GetState, 'get_state', GetState.Request())
    if answer is None:
        return EXIT_FAILED
    print(f'{answer.current_state.label} [{answer.current_state.id}]')
    return EXIT_OK


def set_state(transition: str, node: str = DEFAULT_NODE,
              timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Make the node take a transition; print 'from -> to', or exit 1 with why it did not."""
    from lifecycle_msgs.srv import ChangeState, GetAvailableTransitions

    with ros_node('lifecycle') as ros:
        session = _Session(ros, node, timeout)
        reasons = _RefusalLog(session, transition)
        available = session.ask(GetAvailableTransitions, 'get_available_transitions',
                                GetAvailableTransitions.Request())
        if available is None:
            return EXIT_FAILED
        found = [item for item in available.available_transitions
                 if item.transition.label == transition]
        if not found:
            labels = [item.transition.label for item in available.available_transitions]
            start = (available.available_transitions[0].start_state.label if labels
                     else 'a state without transitions')
            say('lifecycle', f'{session.name}: {transition} is not available from {start} '
                             f'(available: {", ".join(labels) or "none"})')
            return EXIT_FAILED
        start = found[0].start_state.label
        sent_ns = time.time_ns()
        answer = session.ask(ChangeState, 'change_state',
                             ChangeState.Request(transition=found[0].transition))
        if answer is None:
            return EXIT_FAILED
        if not answer.success:
            say('lifecycle', f'{session.name} refused {transition} (still {start}): '
                             f'{reasons.wait(sent_ns)}')
            return EXIT_FAILED
    print(f'{start} -> {ENDS_IN[transition]}')
    return EXIT_OK


class _RefusalLog:
    """The node's '<transition> failed: ...' lines on /rosout, from the start of the session."""

    def __init__(self, session: _Session, transition: str):
        from rcl_interfaces.msg import Log
        from rclpy.qos import DurabilityPolicy, QoSProfile

        self._session = session
        self._logger = session.name.lstrip('/').replace('/', '.')  # the node's logger name
        self._prefix = f'{transition} failed: '
        self.lines: list[tuple[int, str]] = []  # (stamp ns, reason)
        # Transient local, as rcl's /rosout publisher: a line logged before the match counts.
        session.node.create_subscription(
            Log, '/rosout', self._take,
            QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def _take(self, message: Any) -> None:
        if message.name == self._logger and message.msg.startswith(self._prefix):
            stamp = message.stamp.sec * 1_000_000_000 + message.stamp.nanosec
            self.lines.append((stamp, message.msg[len(self._prefix):]))

    def wait(self, sent_ns: int) -> str:
        """Return the reason logged for the request sent at sent_ns (wall clock)."""
        session = self._session
        until = min(session.deadline, time.monotonic() + REASON_WAIT_S)
        while True:
            ours = [line for line in self.lines if line[0] >= sent_ns - CLOCK_SLACK_NS]
            if ours:
                return max(ours)[1]
            if time.monotonic() >= until:
                return 'no reason heard on /rosout (see the node\'s log)'
            session.executor.spin_once(timeout_sec=SPIN_S)
