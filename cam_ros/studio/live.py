"""The studio's link to a running cam_node (`cam_ros studio FILE --node /cam`).

One rclpy node of the studio's own (the CLI's `ros_node`: a private context, the shipped
middleware profile) spins in a background thread. It keeps the last message of the node's
`~/joint_states` (the master position and each axis's command), `~/controller_state` (each
axis's reported position), `~/state` and its `/diagnostics`, and calls `~/engage` and
`~/set_parameters_atomically` as `cam_ros param set` does: the node judges an update with the
core and refuses it (a collision too) with its reason, which the page shows.

The positions are put into what the page draws by the core's own functions (the master
position to each axis's cam angle by its MC_CamIn mapping, a rotary axis modulo a turn as the
checks take it, each axis's file unit); nothing here is computed that the core computes.
"""
from __future__ import annotations

import math
import threading
import time
from contextlib import ExitStack
from typing import Any, Mapping

from cam_ros_interfaces.msg import ControllerState
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rcl_interfaces.srv import SetParametersAtomically
from rclpy.executors import ExternalShutdownException
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool

from cam_ros.client import missing, wait_for_service
from cam_ros.commands.ros import ros_node
from cam_ros.core import InvalidParameter
from cam_ros.core.cam_angles import cam_angle
from cam_ros.core.machine import Axis
from cam_ros.core.machine.interference import as_checked
from cam_ros.core.machine.served import machine_from_values
from cam_ros.node.joints import joint_coordinates
from cam_ros.studio.document import same

#: Longest wait for the node's service to be found and to answer (s).
CALL_TIMEOUT_S = 10.0
#: The latest message is all the page shows: any publisher matches (reliable or not).
LATEST = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
#: ~/state is latched: its last message reaches a subscriber that comes later.
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
LEVELS = {DiagnosticStatus.OK: 'OK', DiagnosticStatus.WARN: 'WARN',
          DiagnosticStatus.ERROR: 'ERROR', DiagnosticStatus.STALE: 'STALE'}


def node_name(name: str) -> str:
    """Return the node's fully qualified name ('cam' -> '/cam')."""
    return name if name.startswith('/') else f'/{name}'


def ros_parameter(name: str, value: Any) -> Any:
    """Return an rcl_interfaces Parameter of a flat value, typed as the file types it."""
    try:
        return Parameter(name, value=value).to_parameter_msg()
    except TypeError as err:
        raise InvalidParameter(name, value, 'cannot be sent as a ROS parameter (a list must '
                               'hold values of one type: write 1.0, not 1)') from err


def cam_degrees(axis: Axis, master: float) -> float:
    """Return an axis's cam angle (deg) at the node's `cam` joint position.

    A master topic's position maps by the axis's MC_CamIn mapping; a clock-driven node's `cam`
    joint is the cam's rotation sigma theta (node/joints.py).
    """
    if axis.design.config.parameters['master.source'] == 'clock':
        return math.degrees(cam_angle(master * joint_coordinates(axis.design).cam_sign))
    return math.degrees(axis.cam.mapping.cam_angle(master))


def file_position(axis: Axis, position: float | None) -> float | None:
    """Return a joint position (SI) as the timing diagram draws it: the axis's file unit, a
    rotary axis modulo a turn (None stays None)."""
    if position is None:
        return None
    return float(as_checked(axis, position)) * axis.design.config.file_position_unit[1]


def status_text(status: DiagnosticStatus | None) -> dict[str, str] | None:
    """Return a status as the page shows it: its level's name and its message."""
    if status is None:
        return None
    return {'level': LEVELS.get(status.level, str(status.level)), 'message': status.message}


class LiveLink:
    """A running cam_node seen and driven from the studio: its last messages, engage, apply."""

    def __init__(self, name: str, values: Mapping[str, Any]):
        self.name = node_name(name)
        self.applied = dict(values)  # what the node is taken to serve: the file, then applied
        self.machine = machine_from_values(values)
        self.lock = threading.Lock()
        self.joints: JointState | None = None
        self.reported: dict[str, float] = {}
        self.state: DiagnosticStatus | None = None
        self.diagnostics: dict[str, DiagnosticStatus] = {}
        self.stack = ExitStack()
        self.node, executor = self.stack.enter_context(ros_node('studio'))
        subscribe = self.node.create_subscription
        subscribe(JointState, f'{self.name}/joint_states', self._joints, LATEST)
        subscribe(ControllerState, f'{self.name}/controller_state', self._report, LATEST)
        subscribe(DiagnosticStatus, f'{self.name}/state', self._state, LATCHED)
        subscribe(DiagnosticArray, '/diagnostics', self._diagnostics, LATEST)
        self.engage_client = self.node.create_client(SetBool, f'{self.name}/engage')
        self.set_client = self.node.create_client(
            SetParametersAtomically, f'{self.name}/set_parameters_atomically')
        self.thread = threading.Thread(target=self._spin, args=(executor,), daemon=True)
        self.thread.start()

    @staticmethod
    def _spin(executor: Any) -> None:
        try:
            executor.spin()
        except ExternalShutdownException:
            pass

    def close(self) -> None:
        """Stop spinning and leave the ROS graph."""
        self.stack.close()
        self.thread.join(timeout=CALL_TIMEOUT_S)

    def _joints(self, message: JointState) -> None:
        with self.lock:
            self.joints = message

    def _report(self, message: ControllerState) -> None:
        with self.lock:
            self.reported.update(zip(message.joint_names, message.feedback.positions))

    def _state(self, message: DiagnosticStatus) -> None:
        with self.lock:
            self.state = message

    def _diagnostics(self, message: DiagnosticArray) -> None:
        with self.lock:
            self.diagnostics.update((status.name, status) for status in message.status
                                    if status.hardware_id == self.name)

    def call(self, client: Any, request: Any) -> Any:
        """Call one of the node's services from any thread; return its answer."""
        deadline = time.monotonic() + CALL_TIMEOUT_S
        if not wait_for_service(client, deadline):
            raise InvalidParameter('--node', self.name, f'has no service {client.srv_name} '
                                   f'within {CALL_TIMEOUT_S:g} s'
                                   + missing(self.node, 'service', client.srv_name))
        future = client.call_async(request)
        done = threading.Event()
        future.add_done_callback(lambda _: done.set())
        if not done.wait(max(0.0, deadline - time.monotonic())):
            client.remove_pending_request(future)
            raise InvalidParameter('--node', self.name, f'did not answer {client.srv_name} '
                                   f'within {CALL_TIMEOUT_S:g} s')
        return future.result()

    def engage(self, on: bool) -> dict[str, Any]:
        """Engage (on) or disengage every axis through ~/engage; return its answer."""
        answer = self.call(self.engage_client, SetBool.Request(data=on))
        return {'success': answer.success, 'message': answer.message}

    def apply(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Send the values that differ from the node's in one atomic update.

        Return whether the node took them, the names sent and, refused, the node's reason.
        """
        changed = {name: value for name, value in values.items()
                   if name not in self.applied or not same(self.applied[name], value)}
        if not changed:
            return {'applied': True, 'sent': [], 'reason': 'nothing changed'}
        request = SetParametersAtomically.Request(
            parameters=[ros_parameter(name, value) for name, value in changed.items()])
        result = self.call(self.set_client, request).result
        if result.successful:
            self.applied.update(changed)
            self.machine = machine_from_values(self.applied)
        return {'applied': result.successful, 'sent': sorted(changed), 'reason': result.reason}

    def status(self) -> dict[str, Any]:
        """Return what the page shows of the node: master, axes, state, diagnostics.

        master_deg: the machine angle (the `cam` joint modulo a turn); each axis's cam_deg, its
        command and reported position in its file unit (a rotary axis modulo a turn), None
        until the node has sent them.
        """
        with self.lock:
            joints, reported = self.joints, dict(self.reported)
            state, diagnostics = self.state, list(self.diagnostics.values())
        machine = self.machine
        commands: dict[str, float] = {}
        master = None
        if joints is not None and joints.position:
            master = float(joints.position[0])
            commands = dict(zip(joints.name[1:], joints.position[1:]))
        axes = {axis.name: {
            'unit': axis.design.config.file_position_unit[0],
            'cam_deg': None if master is None else cam_degrees(axis, master),
            'command': file_position(axis, commands.get(axis.name)),
            'reported': file_position(axis, reported.get(axis.name))} for axis in machine.axes}
        return {'node': self.name,
                'master_deg': None if master is None else math.degrees(cam_angle(master)),
                'axes': axes, 'state': status_text(state),
                'diagnostics': [{'name': status.name, **status_text(status)}
                                for status in sorted(diagnostics, key=lambda s: s.name)]}
