"""cam_node: serves a validated machine to ROS 2 (parameters, services, topics).

A params file without `axes` is a single cam, served as a machine of one axis (joint follower;
~/evaluate, ~/profile, ...); a machine file's axes each get ~/<axis>/evaluate, ~/<axis>/profile
and so on, and share one master (MasterFollower). The node only holds parameters, endpoints and
message conversions; every number comes from :mod:`cam_ros.core`. An invalid parameter update
is rejected with the core's reason and the node keeps serving what it served.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import rclpy
from cam_ros_interfaces.srv import EvaluateCam
from geometry_msgs.msg import Vector3Stamped
from rcl_interfaces.msg import SetParametersResult
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, Trigger

from cam_ros.exit_codes import EXIT_INVALID
from cam_ros.core import CamDesign, CamError, check_angles, InvalidParameter
from cam_ros.core.errors import one_line
from cam_ros.core.machine import is_machine, Machine, parse_machine
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.machine.served import (collisions, machine_from_values, served_specs,
                                         update_refusal)
from cam_ros.node.design_topics import as_float64, CAM_FRAME, DesignTopics
from cam_ros.node.master_follower import MasterFollower
from cam_ros.node.joints import CAM_JOINT, joint_coordinates
from cam_ros.node.middleware import serve_over_udp
from cam_ros.node.own_thread import OwnThread
from cam_ros.node.qos_events import publisher
from cam_ros.node.parameters import (declared_value, descriptor, parameter_sources,
                                     ParameterSources, parse_command_line, plain, RECORDING_SWITCH,
                                     reload_parameters, ros_node_parameters, start_rclpy, USAGE)
from cam_ros.node.recording_switch import NodeRecording, Served
from cam_ros.paths import default_config_path
from cam_ros.rclpy_gaps import RCLError

STATE_QOS = QoSProfile(depth=10)


class CamNode(Node):
    """Serves a machine (a single cam: one axis): evaluate services, latched profiles, state."""

    def __init__(self, params: ParameterSources | Path | None = None, **kwargs: Any):
        """Check the parameters of params (a params file, default config/default.yaml), then serve.

        The whole machine is checked before a parameter is declared (raises InvalidParameter),
        its interference pairs too.
        """
        self._sources = parameter_sources(params, default_config_path())
        values = self._sources.read()
        problem = collisions(machine_from_values(values))
        if problem:
            raise InvalidParameter('interference', None, f'collides: {problem}')
        overrides = [*ros_node_parameters(values), *(kwargs.pop('parameter_overrides', ()) or ())]
        super().__init__('cam', allow_undeclared_parameters=True, parameter_overrides=overrides,
                         **kwargs)
        self._specs = served_specs(values)
        for name, spec in self._specs.items():  # undeclared names reach _validate_update
            self.declare_parameter(name, declared_value(spec, values, name),
                                   descriptor(spec, name))
        self.machine: Machine = machine_from_values(self._current_values())
        self._single = not is_machine(values)
        self._pending: Machine | None = None
        self.add_on_set_parameters_callback(self._validate_update)
        self.add_post_set_parameters_callback(self._apply_update)

        self._topics = [DesignTopics(self, axis.name, '~/' if self._single else f'~/{axis.name}/')
                        for axis in self.machine.axes]
        self._joint_pub = publisher(self, JointState, '~/joint_states', STATE_QOS)
        self._extras_pub = publisher(self, Vector3Stamped, '~/state_extras', STATE_QOS)
        self._ecam = MasterFollower.attach(self, self._axes(), self.machine.config.parameters,
                                           not self._single, self._joint_pub,
                                           lambda: self._recording.recorder)
        self._start_ns = self.get_clock().now().nanoseconds
        self._state_timer = self.create_timer(1.0 / self.design.config.state_rate_hz,
                                              self._publish_state)
        if self._ecam:  # the master axis drives the state instead
            self._state_timer.cancel()
        self._recording = NodeRecording(
            self, self._sources.files[-1],
            (*(pub for topics in self._topics for pub in topics.publishers), self._joint_pub,
             self._extras_pub), self._ecam)
        self._recording.start_up(self._served())
        self._publish_design()
        self._log_design()
        # Services last: once ~/evaluate is visible the node is fully built.
        self.create_service(Trigger, '~/reload', self._reload)
        self.create_service(SetBool, '~/record', self._record)
        # On threads of their own: the executor's wake-up over all the node's entities costs
        # more than a one-angle answer. Thread safety: see _evaluate.
        self._evaluators = [
            OwnThread.service(self, EvaluateCam, '~/evaluate' if self._single
                              else f'~/{axis.name}/evaluate',
                              lambda request, response, index=index: self._evaluate(
                                  index, request, response))
            for index, axis in enumerate(self.machine.axes)]
        topics = sorted(pub.topic_name for pub in self.publishers
                        if pub.topic_name not in ('/rosout', '/parameter_events'))
        pace = ('per master message' if self._ecam is not None
                else f'at {self.design.config.state_rate_hz:g} Hz')
        services = ', '.join(self.resolve_service_name(evaluator.entity.srv_name)
                             for evaluator in self._evaluators)
        self.get_logger().info(f'serving {services}; topics {", ".join(topics)}; '
                               f'state {pace}')

    @property
    def design(self) -> CamDesign:
        """Return the first axis's design: a single cam's design."""
        return self.machine.axes[0].design

    def _axes(self) -> list[tuple[str, CamDesign]]:
        """Return (joint name, design) per axis, in axes order."""
        return [(axis.name, axis.design) for axis in self.machine.axes]

    def _served(self) -> Served:
        """Return what a recording carries of the machine: settings, parameters, summary."""
        return Served(self.design.config, self._current_values(), '; '.join(
            axis.design.summary() if self._single else f'{axis.name}: {axis.design.summary()}'
            for axis in self.machine.axes))

    # Parameters ---------------------------------------------------------------------------
    def _current_values(self) -> dict[str, Any]:
        """Return the flat parameter values that are set, for the core."""
        values = {name: plain(self.get_parameter_or(name).value) for name in self._specs}
        return {name: value for name, value in values.items() if value is not None}

    def _validate_update(self, updates: list[Parameter]) -> SetParametersResult:
        """Check an update as the CLI checks a file: names, types, ranges, the whole machine.

        A machine also refuses an update that would make an interference pair collide, in the
        new machine or on the way to it (core.machine.served.update_refusal).
        """
        cam = [param for param in updates
               if param.name in self._specs or not self.has_parameter(param.name)]
        self._pending = None
        if not cam:  # ROS's own parameters (use_sim_time)
            return SetParametersResult(successful=True)
        try:
            values = self._current_values()
            for param in cam:
                if param.type_ == Parameter.Type.NOT_SET and param.name in self._specs:
                    raise InvalidParameter(param.name, None, 'cannot be undeclared (cam '
                                           'parameters stay declared; set a value instead)')
                if param.name == 'axes' and list(param.value) != values['axes']:
                    raise InvalidParameter('axes', plain(param.value), 'is fixed while the '
                                           'node runs (restart the node to change the axes)')
                values[param.name] = plain(param.value)
            machine = machine_from_values(values)
            refusal = update_refusal(self.machine, machine)
            if refusal:
                return SetParametersResult(successful=False, reason=f'refused: {refusal}')
            self._pending = machine
        except CamError as err:
            return SetParametersResult(successful=False, reason=str(err))
        except Exception as err:  # a core bug must reject the update, not stop the node
            self.get_logger().error(f'update rejected by an internal error: {err!r}')
            return SetParametersResult(successful=False, reason=f'internal error: {err!r}')
        return SetParametersResult(successful=True)

    def _apply_update(self, updates: list[Parameter]) -> None:
        if self._pending is None:
            return
        self.machine, self._pending = self._pending, None
        if any(param.name != RECORDING_SWITCH for param in updates):  # not the switch alone
            if self._ecam:
                self._ecam.change(self._axes(), self.machine.config.parameters)
            self._state_timer.timer_period_ns = int(1e9 / self.design.config.state_rate_hz)
            self._publish_design()
            self._log_design()
        self._recording.follow(updates, self._served())

    def _log_design(self) -> None:
        for axis in self.machine.axes:
            named = '' if self._single else f'{axis.name}: '
            self.get_logger().info(named + axis.design.summary())
            for warning in axis.design.warnings():
                self.get_logger().warning(named + warning)

    # Services -----------------------------------------------------------------------------
    def _evaluate(self, index: int, request: EvaluateCam.Request,
                  response: EvaluateCam.Response) -> EvaluateCam.Response:
        """Answer an axis's ~/evaluate, on the service's own thread (OwnThread).

        A parameter update (on the executor's thread) replaces self.machine with a new Machine
        and never changes one: the single read below gives this request one consistent design
        (frozen dataclasses; their cached properties compute the same values on any thread).
        """
        angles = np.frombuffer(request.angles, dtype=np.float64)
        design = self.machine.axes[index].design  # the one read of self.machine: see above
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
            # names and types first: only declared parameters are set
            parse_machine(values) if not self._single else parse_parameters(values)
        except CamError as err:
            response.success, response.message = False, one_line(str(err))
            return response
        changes = reload_parameters(values, self._current_values(), self._specs)
        result = (self.set_parameters_atomically(changes) if changes
                  else SetParametersResult(successful=True))
        response.success = result.successful
        files = ', '.join(map(str, self._sources.files))
        response.message = f'reloaded {files}' if result.successful else result.reason
        return response

    def _record(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        response.success, response.message = self._recording.switch(
            request.data, 'asked on ~/record', self._served())
        return response

    def destroy_node(self) -> None:
        """Stop the ~/evaluate threads, close a running recording (writing its summary), then go.

        The evaluate and master threads end before the node and its entities are destroyed.
        """
        for evaluator in self._evaluators:
            evaluator.stop()
        self._recording.stop('node shutting down')
        if self._ecam:
            self._ecam.stop()
        super().destroy_node()

    # Topics -------------------------------------------------------------------------------
    def _publish_design(self) -> None:
        for topics, axis in zip(self._topics, self.machine.axes):
            topics.publish(axis.design)

    def _publish_state(self) -> None:
        """Publish every axis's state at the machine angle the clock says (master.source clock).

        The master turns at the speed of cam_speed; each axis's cam angle follows through its
        master offset and scaling (a single cam's, with neither, turns at cam_speed from 0).
        """
        now = self.get_clock().now()
        master = self.machine.axes[0].cam.mapping
        speed = self.design.config.cam_speed * master.master_scaling  # master speed
        machine_angle = master.master_offset + speed * (now.nanoseconds - self._start_ns) * 1e-9
        stamp = now.to_msg()
        positions, velocities, efforts = [], [], []
        states = []
        for axis in self.machine.axes:
            turned = float(axis.cam.mapping.turns(machine_angle))
            state = axis.design.evaluate(np.array([turned]))  # an advancing one counts turns
            _, offset, sign = joint_coordinates(axis.design)
            positions.append(offset + sign * float(state.position[0]))
            velocities.append(sign * float(state.velocity[0]))
            states.append(state)
            if state.dynamics is not None:  # camshaft torque about +z; normal contact force
                torque = float(state.dynamics.camshaft_torque[0])
                efforts.append(float(state.dynamics.contact_force[0]))
        sigma = joint_coordinates(self.design)[0] if self._single else 1.0
        cam = math.fmod(float(master.turns(machine_angle)) if self._single else machine_angle,
                        2 * math.pi)
        joints = JointState(name=[CAM_JOINT, *self.machine.config.names],
                            position=[sigma * cam, *positions],
                            velocity=[sigma * (self.design.config.cam_speed if self._single
                                               else speed), *velocities])
        joints.header.stamp = stamp
        joints.header.frame_id = CAM_FRAME
        if self._single and states[0].dynamics is not None:
            torque = float(states[0].dynamics.camshaft_torque[0])
            joints.effort = [-torque if self.design.clockwise else torque, efforts[0]]
        self._joint_pub.publish(joints)
        if self._single:  # one axis's acceleration, jerk and pressure angle
            extras = Vector3Stamped()
            extras.header = joints.header
            extras.vector.x = float(states[0].acceleration[0])
            extras.vector.y = float(states[0].jerk[0])
            extras.vector.z = float(states[0].pressure_angle[0])
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
