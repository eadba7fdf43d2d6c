"""cam_node: serves one validated cam design to ROS 2 (parameters, services, topics).

The node only holds parameters, endpoints and message conversions; every number comes from
:mod:`cam_ros.core`. An invalid parameter update is rejected with the core's reason and the node
keeps serving its previous design.
"""
from __future__ import annotations

import array
import math
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import rclpy
from builtin_interfaces.msg import Duration
from cam_ros_interfaces.srv import EvaluateCam
from geometry_msgs.msg import Point, Vector3Stamped
from rcl_interfaces.msg import SetParametersResult
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray, MultiArrayDimension
from std_srvs.srv import SetBool, Trigger
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from cam_ros.exit_codes import EXIT_INVALID
from cam_ros.core import (CamDesign, CamError, InvalidParameter, build_design, check_angles,
                          parse_parameters)
from cam_ros.core.config.parameters import PARAMETERS, SPECS
from cam_ros.core.errors import one_line
from cam_ros.node.master_follower import MasterFollower
from cam_ros.node.joints import FOLLOWER_JOINT, joint_coordinates, JOINT_NAMES
from cam_ros.node.middleware import serve_over_udp
from cam_ros.node.own_thread import OwnThread
from cam_ros.node.qos_events import publisher
from cam_ros.node.parameters import (declared_value, descriptor, parameter_sources,
                                     ParameterSources, parse_command_line, plain, RECORDING_SWITCH,
                                     reload_parameters, ros_node_parameters, start_rclpy, USAGE)
from cam_ros.node.recording_switch import NodeRecording
from cam_ros.paths import default_config_path
from cam_ros.rclpy_gaps import RCLError

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
STATE_QOS = QoSProfile(depth=10)
CAM_FRAME = 'cam'
#: Rows of the latched ~/dynamics array (empty for a design without dynamics).
DYNAMICS_ROWS = ('cam_angle_rad', 'contact_force_N', 'camshaft_torque_Nm', 'contact_stress_Pa')


def as_float64(values: np.ndarray) -> array.array:
    """Convert a float64 array to the message field type without a per-element loop."""
    return array.array('d', np.ascontiguousarray(values, dtype=np.float64).tobytes())


def labelled_rows(labels: Sequence[str], rows: Sequence[np.ndarray]) -> Float64MultiArray:
    """Return rows of equal length as a Float64MultiArray whose first dim names them."""
    count = rows[0].size if rows else 0
    message = Float64MultiArray()
    message.layout.dim = [
        MultiArrayDimension(label=','.join(labels), size=len(rows), stride=len(rows) * count),
        MultiArrayDimension(label='sample', size=count, stride=count)]
    message.data = as_float64(np.concatenate(rows) if rows else np.empty(0))
    return message


def duration(seconds: float) -> Duration:
    """Build a builtin_interfaces/Duration from seconds."""
    nanoseconds = int(round(seconds * 1e9))
    return Duration(sec=nanoseconds // 1_000_000_000, nanosec=nanoseconds % 1_000_000_000)


class CamNode(Node):
    """Holds one cam design and serves it: evaluate service, latched profile, live state."""

    def __init__(self, params: ParameterSources | Path | None = None, **kwargs: Any):
        """Check the parameters of params (a params file, default config/default.yaml), then serve.

        The whole design is checked before a parameter is declared (raises InvalidParameter).
        """
        self._sources = parameter_sources(params, default_config_path())
        values = self._sources.read()
        build_design(parse_parameters(values))
        overrides = [*ros_node_parameters(values), *(kwargs.pop('parameter_overrides', ()) or ())]
        super().__init__('cam', allow_undeclared_parameters=True, parameter_overrides=overrides,
                         **kwargs)
        for spec in PARAMETERS:  # undeclared names reach _validate_update, which names them
            self.declare_parameter(spec.name, declared_value(spec, values), descriptor(spec))
        self.design: CamDesign = build_design(parse_parameters(self._current_values()))
        self._pending: CamDesign | None = None
        self.add_on_set_parameters_callback(self._validate_update)
        self.add_post_set_parameters_callback(self._apply_update)

        self._profile_pub = publisher(self, JointTrajectory, '~/profile', LATCHED)
        self._pressure_pub = publisher(self, Float64MultiArray, '~/pressure_angle', LATCHED)
        self._markers_pub = publisher(self, MarkerArray, '~/markers', LATCHED)
        self._joint_pub = publisher(self, JointState, '~/joint_states', STATE_QOS)
        self._extras_pub = publisher(self, Vector3Stamped, '~/state_extras', STATE_QOS)
        self._dynamics_pub = publisher(self, Float64MultiArray, '~/dynamics', LATCHED)
        self._ecam = MasterFollower.attach(self, [(FOLLOWER_JOINT, self.design)],
                                           self.design.config.parameters, False,
                                           self._joint_pub, lambda: self._recording.recorder)
        self._start_ns = self.get_clock().now().nanoseconds
        self._state_timer = self.create_timer(1.0 / self.design.config.state_rate_hz,
                                              self._publish_state)
        if self._ecam:  # the master axis drives the state instead
            self._state_timer.cancel()
        self._recording = NodeRecording(
            self, self._sources.files[-1], (self._profile_pub, self._pressure_pub,
                                            self._markers_pub, self._joint_pub,
                                            self._extras_pub, self._dynamics_pub), self._ecam)
        self._recording.start_up(self.design)
        self._publish_design()
        self._log_design()
        # Services last: once ~/evaluate is visible the node is fully built.
        self.create_service(Trigger, '~/reload', self._reload)
        self.create_service(SetBool, '~/record', self._record)
        # On a thread of its own: the executor's wake-up over all the node's entities costs
        # more than a one-angle answer. Thread safety: see _evaluate.
        self._evaluator = OwnThread.service(self, EvaluateCam, '~/evaluate', self._evaluate)
        topics = sorted(pub.topic_name for pub in self.publishers
                        if pub.topic_name not in ('/rosout', '/parameter_events'))
        pace = ('per master message' if self._ecam is not None
                else f'at {self.design.config.state_rate_hz:g} Hz')
        self.get_logger().info(f'serving {self.get_fully_qualified_name()}/evaluate; topics '
                               f'{", ".join(topics)}; state {pace}')

    # Parameters ---------------------------------------------------------------------------
    def _current_values(self) -> dict[str, Any]:
        """Return the flat cam parameter values that are set, for the core."""
        values = {spec.name: plain(self.get_parameter_or(spec.name).value) for spec in PARAMETERS}
        return {name: value for name, value in values.items() if value is not None}

    def _validate_update(self, updates: list[Parameter]) -> SetParametersResult:
        """Check an update as the CLI checks a file: names, types, ranges, the whole design."""
        cam = [param for param in updates
               if param.name in SPECS or not self.has_parameter(param.name)]
        self._pending = None
        if not cam:  # ROS's own parameters (use_sim_time)
            return SetParametersResult(successful=True)
        try:
            values = self._current_values()
            for param in cam:
                if param.type_ == Parameter.Type.NOT_SET and param.name in SPECS:
                    raise InvalidParameter(param.name, None, 'cannot be undeclared (cam '
                                           'parameters stay declared; set a value instead)')
                values[param.name] = plain(param.value)
            self._pending = build_design(parse_parameters(values))
        except CamError as err:
            return SetParametersResult(successful=False, reason=str(err))
        except Exception as err:  # a core bug must reject the update, not stop the node
            self.get_logger().error(f'update rejected by an internal error: {err!r}')
            return SetParametersResult(successful=False, reason=f'internal error: {err!r}')
        return SetParametersResult(successful=True)

    def _apply_update(self, updates: list[Parameter]) -> None:
        if self._pending is None:
            return
        self.design, self._pending = self._pending, None
        if any(param.name != RECORDING_SWITCH for param in updates):  # not the switch alone
            if self._ecam:
                self._ecam.change([(FOLLOWER_JOINT, self.design)], self.design.config.parameters)
            self._state_timer.timer_period_ns = int(1e9 / self.design.config.state_rate_hz)
            self._publish_design()
            self._log_design()
        self._recording.follow(updates, self.design)

    def _log_design(self) -> None:
        self.get_logger().info(self.design.summary())
        for warning in self.design.warnings():
            self.get_logger().warning(warning)

    # Services -----------------------------------------------------------------------------
    def _evaluate(self, request: EvaluateCam.Request,
                  response: EvaluateCam.Response) -> EvaluateCam.Response:
        """Answer ~/evaluate, on the service's own thread (OwnThread), not the executor's.

        A parameter update (on the executor's thread) replaces self.design with a new CamDesign
        and never changes one: the single read below gives this request one consistent design
        (a frozen dataclass; its cached properties compute the same values on any thread).
        """
        angles = np.frombuffer(request.angles, dtype=np.float64)
        design = self.design  # the one read of self.design: see above
        problem = check_angles(angles, design.config.max_batch)
        if problem:
            response.success, response.message = False, problem
            return response
        try:
            state = design.evaluate(angles)
        except Exception as err:  # a core bug: answer and keep serving, as updates do
            self.get_logger().error(f'evaluate failed by an internal error: {err!r}')
            response.success, response.message = False, f'internal error: {err!r}'
            return response
        response.position = as_float64(state.position)
        response.velocity = as_float64(state.velocity)
        response.acceleration = as_float64(state.acceleration)
        response.jerk = as_float64(state.jerk)
        response.pressure_angle = as_float64(state.pressure_angle)
        response.radius_of_curvature = as_float64(state.radius_of_curvature)
        if state.dynamics is not None:  # no dynamics: the arrays stay empty
            response.contact_force = as_float64(state.dynamics.contact_force)
            response.camshaft_torque = as_float64(state.dynamics.camshaft_torque)
            response.contact_stress = as_float64(state.dynamics.contact_stress)
        response.success, response.message = True, f'{angles.size} angles evaluated'
        return response

    def _reload(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        """Re-read the start-up params files and -p overrides; set what changed, if they are good.

        A running recording is left alone: the files' recording.enabled applies at start-up.
        """
        try:
            values = self._sources.read()
            parse_parameters(values)  # names and types first: only cam parameters are set
        except CamError as err:
            response.success, response.message = False, one_line(str(err))
            return response
        changes = reload_parameters(values, self._current_values())
        result = (self.set_parameters_atomically(changes) if changes
                  else SetParametersResult(successful=True))
        response.success = result.successful
        files = ', '.join(map(str, self._sources.files))
        response.message = f'reloaded {files}' if result.successful else result.reason
        return response

    def _record(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        response.success, response.message = self._recording.switch(
            request.data, 'asked on ~/record', self.design)
        return response

    def destroy_node(self) -> None:
        """Stop the ~/evaluate thread, close a running recording (writing its summary), then go.

        The evaluate and master threads end before the node and its entities are destroyed.
        """
        self._evaluator.stop()
        self._recording.stop('node shutting down')
        if self._ecam:
            self._ecam.stop()
        super().destroy_node()

    # Topics -------------------------------------------------------------------------------
    def _publish_design(self) -> None:
        design = self.design
        profile = design.profile(design.config.sample_count)
        stamp = self.get_clock().now().to_msg()
        trajectory = JointTrajectory(joint_names=[FOLLOWER_JOINT])
        trajectory.header.stamp = stamp
        trajectory.header.frame_id = CAM_FRAME
        omega = design.config.cam_speed
        _, offset, sign = joint_coordinates(design)
        trajectory.points = [
            JointTrajectoryPoint(positions=[offset + sign * s], velocities=[sign * v],
                                 accelerations=[sign * a], time_from_start=duration(theta / omega))
            for theta, s, v, a in zip(profile.angle.tolist(), profile.position.tolist(),
                                      profile.velocity.tolist(), profile.acceleration.tolist())]
        self._profile_pub.publish(trajectory)
        self._pressure_pub.publish(labelled_rows(('cam_angle_rad', 'pressure_angle_rad'),
                                                 (profile.angle, profile.pressure_angle)))
        forces = profile.dynamics  # none: an empty array, so a previous design's is not kept
        self._dynamics_pub.publish(labelled_rows(
            DYNAMICS_ROWS, () if forces is None else (
                profile.angle, forces.contact_force, forces.camshaft_torque,
                forces.contact_stress)))
        self._markers_pub.publish(self._markers(stamp))

    def _markers(self, stamp: Any) -> MarkerArray:
        if self.design.follower is None:  # motion only: no cam to draw, clear an earlier one's
            return MarkerArray(markers=[Marker(action=Marker.DELETEALL)])
        shape = self.design.geometry(self.design.config.sample_count)
        circle = self.design.follower.base_radius * np.stack(
            (np.cos(shape.theta), np.sin(shape.theta)))
        curves = (('cam_surface', shape.surface_x, shape.surface_y, (0.2, 0.4, 0.9)),
                  ('pitch_curve', shape.pitch_x, shape.pitch_y, (0.9, 0.5, 0.1)),
                  ('base_circle', circle[0], circle[1], (0.5, 0.5, 0.5)))
        markers = MarkerArray()
        for index, (namespace, x, y, rgb) in enumerate(curves):
            marker = Marker(ns=namespace, id=index, type=Marker.LINE_STRIP, action=Marker.ADD)
            marker.header.stamp = stamp
            marker.header.frame_id = CAM_FRAME
            marker.pose.orientation.w = 1.0
            marker.scale.x = 0.0005
            marker.color.r, marker.color.g, marker.color.b = rgb
            marker.color.a = 1.0
            marker.points = [Point(x=px, y=py) for px, py in zip(x.tolist(), y.tolist())]
            marker.points.append(marker.points[0])
            markers.markers.append(marker)
        return markers

    def _publish_state(self) -> None:
        now = self.get_clock().now()
        design = self.design
        turned = design.config.cam_speed * (now.nanoseconds - self._start_ns) * 1e-9
        theta = math.fmod(turned, 2 * math.pi)
        state = design.evaluate(np.array([turned]))  # an advancing program counts the turns
        stamp = now.to_msg()
        sigma, offset, sign = joint_coordinates(design)
        joints = JointState(
            name=list(JOINT_NAMES),
            position=[sigma * theta, offset + sign * float(state.position[0])],
            velocity=[sigma * design.config.cam_speed, sign * float(state.velocity[0])])
        joints.header.stamp = stamp
        joints.header.frame_id = CAM_FRAME
        if state.dynamics is not None:  # camshaft torque about +z; normal contact force
            torque = float(state.dynamics.camshaft_torque[0])
            joints.effort = [-torque if design.clockwise else torque,
                             float(state.dynamics.contact_force[0])]
        self._joint_pub.publish(joints)
        extras = Vector3Stamped()
        extras.header = joints.header
        extras.vector.x = float(state.acceleration[0])
        extras.vector.y = float(state.jerk[0])
        extras.vector.z = float(state.pressure_angle[0])
        self._extras_pub.publish(extras)


def _invalid(message: str) -> int:
    """Print one line 'cam_node: message' on stderr and return the exit code of bad input."""
    print(f'cam_node: {one_line(message)}', file=sys.stderr)
    return EXIT_INVALID


def main(args: Sequence[str] | None = None) -> int:
    """Run cam_node until Ctrl-C or SIGTERM; exit 2 with one line on invalid input."""
    argv = list(sys.argv if args is None else args)
    try:
        command = parse_command_line(argv, default_config_path())
    except CamError as err:
        return _invalid(str(err))
    if {'-h', '--help'} & set(command.user_args):
        print(USAGE, end='')
        return 0
    if command.user_args:
        return _invalid(f'unrecognized arguments: {" ".join(command.user_args)} '
                        '(see cam_node --help)')
    try:
        serve_over_udp()
    except CamError as err:
        return _invalid(str(err))
    problem = start_rclpy(command.ros_args)
    if problem:  # a bad remapping or logging argument
        return _invalid(f'invalid ROS arguments: {problem}')
    executor = SingleThreadedExecutor()  # made first, so a signal never lands inside its set-up
    node = None
    code = 0
    try:
        node = CamNode(command.sources)
        executor.add_node(node)
        executor.spin()
    except CamError as err:
        code = _invalid(str(err))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except RCLError:
        if rclpy.ok():
            raise  # a real failure; otherwise SIGTERM's shutdown raced the executor's wait
    finally:
        executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code
