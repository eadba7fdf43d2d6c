"""cam_node: serves a validated machine to ROS 2 (parameters, services, topics).

A params file without `axes` is a single cam, served as a machine of one axis (joint follower;
~/evaluate, ~/profile, ...); a machine file's axes each get ~/<axis>/evaluate, ~/<axis>/profile
and so on, and share one master (MasterFollower). The node only holds parameters, endpoints and
message conversions; every number comes from :mod:`cam_ros.core`. An invalid parameter update
is rejected with the core's reason and the node keeps serving what it served.

cam_node is a managed (lifecycle) node. Unconfigured it has the lifecycle and parameter
services and its ROS parameters (use_sim_time, autostart) only; configure reads the params
files, declares the cam parameters and makes every service and topic; inactive serves all but
motion; active commands the axes; cleanup destroys what configure made.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any, Callable

import numpy as np
from cam_ros_interfaces.srv import EvaluateCam
from geometry_msgs.msg import Vector3Stamped
from rcl_interfaces.msg import SetParametersResult
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from rclpy.task import Future
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, Trigger

from cam_ros.core import CamDesign, CamError, check_angles, InvalidParameter
from cam_ros.core.config.parameters import ParameterSpec
from cam_ros.core.errors import one_line
from cam_ros.core.machine import is_machine, Machine, parse_machine
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.machine.move_check import checked_moves
from cam_ros.core.machine.served import (collisions, machine_from_values, served_specs,
                                         update_refusal)
from cam_ros.node.clock_state import ClockState
from cam_ros.node.design_topics import as_float64, DesignTopics
from cam_ros.node.lifecycle import Configured, guard_change_state
from cam_ros.node.master_follower import MasterFollower
from cam_ros.node.own_thread import OwnThread
from cam_ros.node.qos_events import publisher
from cam_ros.node.parameters import (AUTOSTART, autostart_descriptor, declared_value, descriptor,
                                     parameter_sources, ParameterSources, plain,
                                     RECORDING_SWITCH, reload_parameters, ros_node_parameters)
from cam_ros.node.recording_switch import NodeRecording, Served
from cam_ros.paths import default_config_path

STATE_QOS = QoSProfile(depth=10)
SUCCESS, FAILURE = TransitionCallbackReturn.SUCCESS, TransitionCallbackReturn.FAILURE


class CamNode(LifecycleNode):
    """Serves a machine (a single cam: one axis): evaluate services, latched profiles, state.

    A managed node (see the module docstring). With the autostart parameter (default true) the
    constructor configures and activates it, as launch_ros's LifecycleNode(autostart=True) would.
    """

    def __init__(self, params: ParameterSources | Path | None = None, **kwargs: Any):
        """Take the params files (default config/default.yaml); with autostart, serve them.

        Raises InvalidParameter for a ROS node parameter (use_sim_time, autostart) of the wrong
        type and, with autostart, for the design configure refuses (the whole machine is
        checked before a cam parameter is declared, its interference pairs too).
        """
        self._sources = parameter_sources(params, default_config_path())
        try:
            values = self._sources.read()
        except CamError:  # configure will say why; the -p overrides' ROS parameters still count
            values = replace(self._sources, files=()).read()
        overrides = [*ros_node_parameters(values), *(kwargs.pop('parameter_overrides', ()) or ())]
        self._configured: Configured | None = None  # rclpy's own callbacks are no part of it
        super().__init__('cam', allow_undeclared_parameters=True, parameter_overrides=overrides,
                         **kwargs)
        self.declare_parameter(AUTOSTART, True, autostart_descriptor())
        self._pending: Machine | None = None
        self._unbuilt()
        self._failure: Exception | None = None  # why the last configure failed
        #: Done once the node is shut down (finalized): main() then ends the process.
        self.finished = Future()
        self.add_on_set_parameters_callback(self._validate_update)
        self.add_post_set_parameters_callback(self._apply_update)
        guard_change_state(self, self.get_logger().error, self._failed)
        if self.get_parameter(AUTOSTART).value:
            if self.trigger_configure() != SUCCESS:
                failure = self._failure or RuntimeError('configure failed')
                super().destroy_node()
                raise failure
            self.trigger_activate()

    def _unbuilt(self) -> None:
        """Forget what configure made (unconfigured)."""
        self.machine: Machine | None = None
        self._specs: dict[str, ParameterSpec] = {}
        self._single = True
        self._topics: list[DesignTopics] = []
        self._evaluators: list[OwnThread] = []
        self._ecam: MasterFollower | None = None
        self._clock_state: ClockState | None = None
        self._recording: NodeRecording | None = None

    # Lifecycle ------------------------------------------------------------------------------
    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Read and check the params files (again), then build what the machine serves.

        A refused design fails the transition with its one-line reason; the node stays
        unconfigured, as it was.
        """
        self._failure = None
        try:
            values = self._sources.read()
            problem = collisions(machine_from_values(values))  # also checks every value
            if problem:
                raise CamError(f'interference: {problem}')
            self._configured = Configured(self)
            self._build(values)
        except Exception as err:  # a bad design, or a bug: unconfigured all the same
            self._failure = err
            self._teardown('configure failed')
            return FAILURE
        return SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Command the axes: each engages in its engage mode from where it is held."""
        if self._ecam:
            self._ecam.activate()
        elif self._clock_state:
            self._clock_state.start()
        self.get_logger().info('active: ' + ('commanding the axes' if self._ecam
                                             else 'publishing the state'))
        return SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop commanding: one hold command for every axis, then nothing."""
        self._stop_motion()
        self.get_logger().info('inactive: ' + ('axes held, master followed' if self._ecam
                                               else 'state not published'))
        return SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Destroy what configure made: back to unconfigured."""
        self._teardown('cleanup')
        self.get_logger().info('unconfigured')
        return SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """End from any state: an active node holds its axes first."""
        if state.label == 'active':
            self._stop_motion()
        self._teardown('shutdown')
        self.get_logger().info('finalized')
        self.finished.set_result(True)
        return SUCCESS

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """A transition raised: destroy what configure made and go back to unconfigured."""
        self.get_logger().error(f'a transition from {state.label} failed by an internal '
                                'error: back to unconfigured')
        self._teardown('error')
        return SUCCESS

    def _failed(self, label: str) -> str:
        """Return why the transition of label failed, in one line."""
        failure = self._failure
        if label == 'configure' and failure is not None:
            return one_line(str(failure) if isinstance(failure, CamError)
                            else f'internal error: {failure!r}')
        return 'an internal error (see the line before)'

    def _stop_motion(self) -> None:
        if self._ecam:
            self._ecam.deactivate()
        elif self._clock_state:
            self._clock_state.stop()

    def add_on_set_parameters_callback(self, callback: Callable[..., Any]) -> None:
        """Add a parameter check; one that configure adds, cleanup removes."""
        super().add_on_set_parameters_callback(callback)
        if self._configured is not None:
            self._configured.callbacks.append(callback)

    def _build(self, values: dict[str, Any]) -> None:
        """Declare the cam parameters of values and make every endpoint (inactive)."""
        self._specs = served_specs(values)
        for name, spec in self._specs.items():  # undeclared names reach _validate_update
            self.declare_parameter(name, declared_value(spec, values, name),
                                   descriptor(spec, name))
        self.machine = machine_from_values(self._current_values())
        self._single = not is_machine(values)
        self._topics = [DesignTopics(self, axis.name, '~/' if self._single else f'~/{axis.name}/')
                        for axis in self.machine.axes]
        joint_pub = publisher(self, JointState, '~/joint_states', STATE_QOS)
        extras_pub = publisher(self, Vector3Stamped, '~/state_extras', STATE_QOS)
        # Inactive from the start: master messages tracked, nothing commanded.
        self._ecam = MasterFollower.attach(self, self._axes(), self.machine.config.parameters,
                                           not self._single, joint_pub,
                                           lambda: self._recording and self._recording.recorder,
                                           lambda moves, master: checked_moves(self.machine,
                                                                               moves, master),
                                           active=False)
        if not self._ecam:  # the clock drives the state, while active
            self._clock_state = ClockState(self, lambda: self.machine, self._single,
                                           joint_pub, extras_pub)
        self._recording = NodeRecording(
            self, self._sources.files[-1],
            (*(pub for topics in self._topics for pub in topics.publishers), joint_pub,
             extras_pub), self._ecam)
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
                               f'state {pace} while active')

    def _teardown(self, why: str) -> None:
        """Destroy what configure made (stopping its threads first) and undeclare the cam
        parameters; a running recording is closed. Nothing to do when unconfigured."""
        configured, self._configured = self._configured, None
        if configured is None:
            return
        for evaluator in self._evaluators:
            evaluator.stop()
        if self._recording:
            self._recording.stop(why)
        if self._ecam:
            self._ecam.stop()
        configured.destroy()
        for name in self._specs:
            if self.has_parameter(name):
                self.undeclare_parameter(name)
        self._unbuilt()

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
        if self.machine is None:  # unconfigured, or configure declaring the cam parameters
            for param in cam:
                if param.name not in self._specs:
                    return SetParametersResult(successful=False, reason=str(InvalidParameter(
                        param.name, plain(param.value), 'cannot be set while the node is '
                        'unconfigured (configure declares the cam parameters)')))
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
            if self._clock_state:
                self._clock_state.follow_rate()
            self._publish_design()
            self._log_design()
        if self._recording:
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
        """Destroy what configure made (its threads end first, a recording is closed), then go.

        The axes are not held (Ctrl-C and SIGTERM end the process; the shutdown transition
        holds them before).
        """
        self._teardown('node shutting down')
        super().destroy_node()

    # Topics -------------------------------------------------------------------------------
    def _publish_design(self) -> None:
        for topics, axis in zip(self._topics, self.machine.axes):
            topics.publish(axis.design)
