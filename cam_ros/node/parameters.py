"""cam_node's command line and parameters: where they come from, how they reach ROS.

The node reads its parameters itself, with the core's code, before it declares any: every
``--params-file`` in order, then every ``-p NAME:=VALUE``, as rcl would apply them, so a bad
file or override gets exactly the one-line error that ``cam_ros report`` gives. rclpy is started
without them and the node declares the values read here.

Parameters are declared with dynamic typing: the node's own check (the same as the CLI's) judges
types, so a wrong type is refused with a reason that names the parameter.
"""
from __future__ import annotations

import array
import os
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, ParameterType
import rclpy
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions

from cam_ros.core import InvalidParameter
from cam_ros.core.config.parameters import (check_type, ParameterSpec, REQUIRED,
                                            ROS_NODE_PARAMETERS)
from cam_ros.core.config.params_file import parse_yaml, read_parameters_file
from cam_ros.rclpy_gaps import RCLError

NODE_NAME = 'cam'
ROS_TYPES = {
    'double': ParameterType.PARAMETER_DOUBLE, 'integer': ParameterType.PARAMETER_INTEGER,
    'string': ParameterType.PARAMETER_STRING, 'bool': ParameterType.PARAMETER_BOOL,
    'double_array': ParameterType.PARAMETER_DOUBLE_ARRAY,
    'integer_array': ParameterType.PARAMETER_INTEGER_ARRAY,
    'string_array': ParameterType.PARAMETER_STRING_ARRAY,
}
#: ROS arguments that take a value (rcl's list); the parameter ones are read here.
VALUED_ROS_FLAGS = {'-r', '--remap', '-p', '--param', '--params-file', '-e', '--enclave',
                    '--log-level', '--log-config-file', '--log-file-name'}
PARAMETER_FLAGS = {'-p', '--param', '--params-file'}
#: The recording's one switch: ~/record sets it, setting it starts or stops the recording.
RECORDING_SWITCH = 'recording.enabled'
#: The managed node's start-up switch: true configures and activates it at start-up.
AUTOSTART = 'autostart'


def descriptor(spec: ParameterSpec, name: str | None = None) -> ParameterDescriptor:
    """Turn a config-format parameter spec into a (dynamically typed) ROS descriptor.

    name: the parameter's full name (an axis's, prefixed), by default the spec's.
    """
    unit = f' [{spec.unit}]' if spec.unit else ''
    choices = f' One of: {", ".join(spec.choices)}.' if spec.choices else ''
    result = ParameterDescriptor(name=name or spec.name, type=ROS_TYPES[spec.type],
                                 description=f'{spec.description}{unit}. Type: {spec.type}.'
                                             f'{choices}',
                                 read_only=spec.read_only, dynamic_typing=True)
    if spec.minimum is not None and spec.maximum is not None:
        if spec.type == 'double':
            result.floating_point_range = [FloatingPointRange(
                from_value=float(spec.minimum), to_value=float(spec.maximum))]
        elif spec.type == 'integer':
            result.integer_range = [IntegerRange(
                from_value=int(spec.minimum), to_value=int(spec.maximum), step=1)]
    return result


def declared_value(spec: ParameterSpec, values: Mapping[str, Any],
                   name: str | None = None) -> Any:
    """Return the value to declare for name (by default the spec's): the one given, else the
    default.

    None (unset) where there is neither, or for an empty list, which rclpy would take for a
    byte array; the core reads an unset array as empty.
    """
    value = values.get(name or spec.name, spec.default)
    return None if value is REQUIRED or (isinstance(value, list) and not value) else value


def plain(value: Any) -> Any:
    """Return a ROS parameter value as the core takes it (arrays as lists)."""
    return list(value) if isinstance(value, (list, tuple, array.array)) else value


def reload_parameters(values: Mapping[str, Any], current: Mapping[str, Any],
                      specs: Mapping[str, ParameterSpec]) -> list[Parameter]:
    """Return the declared parameters (specs, by full name) a reload changes, typed as declared.

    values are the sources' (defaults for the rest), current the node's (absent where unset).
    Only real changes are returned: not a value equal to the current one, not an empty array for
    one that is unset, and not RECORDING_SWITCH, which a params file sets at start-up only (a
    reload leaves a running recording alone).
    """
    return [Parameter(name, Parameter.Type(ROS_TYPES[spec.type]), value)
            for name, spec, value in ((name, spec, values.get(name, spec.default))
                                      for name, spec in specs.items()
                                      if name in values or spec.default is not REQUIRED)
            if name != RECORDING_SWITCH
            and value != current.get(name, [] if isinstance(value, list) else None)]


def split_rule(rule: str) -> tuple[str, str, str]:
    """Split a ROS rule '[node:]name:=value' into node ('' if none), name and value."""
    left, assign, value = rule.partition(':=')
    node, _, name = left.rpartition(':')
    return (node, name, value) if assign else ('', '', rule)


def ros_node_parameters(values: Mapping[str, Any]) -> list[Parameter]:
    """Return the ROS node parameters (use_sim_time, autostart) values give, type-checked.

    Raises InvalidParameter for a value of the wrong type, as the core's check of a file does.
    """
    return [Parameter(name, value=check_type(spec, values[name]))
            for name, spec in ROS_NODE_PARAMETERS.items() if name in values]


def autostart_descriptor() -> ParameterDescriptor:
    """Return the descriptor of cam_node's read-only AUTOSTART parameter."""
    spec = ROS_NODE_PARAMETERS[AUTOSTART]
    return ParameterDescriptor(name=AUTOSTART, type=ROS_TYPES[spec.type], read_only=True,
                               description=f'{spec.description}. Type: {spec.type}.')


@dataclass(frozen=True)
class ParameterSources:
    """Where cam_node's parameters come from: params files in order, then -p overrides."""

    files: tuple[Path, ...]
    overrides: tuple[str, ...] = ()  # NAME:=VALUE, as given after -p
    node_name: str = NODE_NAME
    namespace: str = '/'

    @property
    def full_name(self) -> str:
        """Return the node's fully qualified name."""
        return f'{self.namespace.rstrip("/")}/{self.node_name}'

    def read(self) -> dict[str, Any]:
        """Read every source into one flat mapping of parameter values (raises InvalidParameter).

        A file's sections for ``/**``, the node name and its full name count, in file order.
        """
        names = tuple(dict.fromkeys((self.node_name, f'/{self.node_name}', self.full_name,
                                     '/**')))
        values: dict[str, Any] = {}
        for path in self.files:
            values.update(read_parameters_file(path, names))
        for override in self.overrides:
            node, name, text = split_rule(override)
            if not name:
                raise InvalidParameter('-p', override, 'must be NAME:=VALUE')
            if node in ('', NODE_NAME, self.node_name, self.full_name):
                values[name] = parse_yaml(text, name, text)
        return values


@dataclass(frozen=True)
class CommandLine:
    """cam_node's command line, split: parameter sources, rclpy's arguments, the user's."""

    sources: ParameterSources
    ros_args: list[str]
    user_args: list[str]


def parse_command_line(argv: Sequence[str], default_file: Path) -> CommandLine:
    """Split argv (with the program name) as rcl would; no params file means default_file."""
    files: list[Path] = []
    overrides: list[str] = []
    node_name, namespace = NODE_NAME, '/'
    ros_args: list[str] = []
    user_args: list[str] = []
    inside, position = False, 1
    while position < len(argv):
        flag = argv[position]
        position += 1
        if flag == '--ros-args':
            inside = True
        elif inside and flag == '--':
            inside = False
        elif not inside:
            user_args.append(flag)
        elif flag not in VALUED_ROS_FLAGS:
            ros_args.append(flag)
        elif position == len(argv):
            raise InvalidParameter(flag, None, 'needs a value after it')
        else:
            value = argv[position]
            position += 1
            if flag == '--params-file':
                files.append(Path(value))
            elif flag in PARAMETER_FLAGS:
                overrides.append(value)
            else:
                ros_args += [flag, value]
                node, key, target = split_rule(value)
                if flag in ('-r', '--remap') and node in ('', NODE_NAME):
                    node_name = target if key in ('__node', '__name') else node_name
                    namespace = target if key == '__ns' else namespace
    sources = ParameterSources(tuple(files) or (default_file,), tuple(overrides), node_name,
                               namespace)
    return CommandLine(sources, [argv[0], '--ros-args', *ros_args] if ros_args else [argv[0]],
                       user_args)


def start_rclpy(args: list[str]) -> str | None:
    """Initialise rclpy with args; return rcl's complaint in one line, or None if it started.

    rcl logs its complaint on stderr before it raises: that output is held back (and written out
    if rclpy starts after all), so a bad ROS argument costs one line like any bad input. rclpy
    installs no signal handlers: cam_node's process takes Ctrl-C and SIGTERM itself.
    """
    sys.stderr.flush()
    with tempfile.TemporaryFile() as held:
        saved = os.dup(2)
        os.dup2(held.fileno(), 2)
        try:
            rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
        except (RCLError, RuntimeError, ValueError) as err:
            return re.sub(r', at \S+:\d+', '', str(err))  # without rcl's source locations
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        held.seek(0)
        sys.stderr.buffer.write(held.read())
        sys.stderr.flush()
    return None


def parameter_sources(params: ParameterSources | Path | str | None,
                      default_file: Path) -> ParameterSources:
    """Return params as ParameterSources: a params file alone, or default_file if None."""
    if isinstance(params, ParameterSources):
        return params
    return ParameterSources((Path(params) if params is not None else default_file,))


USAGE = '''\
usage: cam_node [-h] [--ros-args [--params-file FILE]... [-p NAME:=VALUE]... [ROS_ARG]...]

Serve a cam design, or a machine of cam axes, to ROS 2 (SI units; docs/ros-interface.md
has the details). A machine file (with axes) serves each axis's services and latched topics
under its name (~/<axis>/evaluate, ~/<axis>/profile, ...) and one master path for all.

A managed (lifecycle) node: with autostart true (the default; -p autostart:=false to
wait) it configures and activates itself at start-up. Unconfigured it serves only
  ~/change_state      lifecycle_msgs/ChangeState: configure, activate, deactivate,
                      cleanup, shutdown (as `ros2 lifecycle set` or `cam_ros lifecycle set`)
  ~/get_state         lifecycle_msgs/GetState: unconfigured, inactive, active, finalized
  ~/get_available_states       lifecycle_msgs/GetAvailableStates
  ~/get_available_transitions  lifecycle_msgs/GetAvailableTransitions: from this state
  ~/get_transition_graph       lifecycle_msgs/GetAvailableTransitions: all of them
and its parameters use_sim_time and autostart; configure reads the params files and
declares the cam parameters. Inactive: all below, parameter updates too, but no motion:
nothing on ~/commands, ~/joint_trajectory, ~/switches, ~/switch_state, ~/joint_states,
~/state_extras (master messages are followed: the speed estimate stays warm). Activate:
each axis engages in master.engage_mode from where it is held; deactivate: one hold
command per axis. Cleanup: back to unconfigured. Shutdown ends the process (exit 0).

services:
  ~/evaluate          cam_ros_interfaces/EvaluateCam: motion, geometry, dynamics at angles
  ~/reload            std_srvs/Trigger: re-read the params files and -p overrides
  ~/record            std_srvs/SetBool: start/stop recording (= recording.enabled)

topics (published):
  ~/profile           trajectory_msgs/JointTrajectory, latched: one revolution
  ~/pressure_angle    std_msgs/Float64MultiArray, latched: cam and pressure angle
  ~/markers           visualization_msgs/MarkerArray, latched: the cam's outlines
  ~/dynamics          std_msgs/Float64MultiArray, latched: contact force, camshaft
                      torque, contact stress (empty without dynamics)
  ~/joint_states      sensor_msgs/JointState: joint cam and each axis's (follower for
                      a single cam) at state_rate_hz
  ~/state_extras      geometry_msgs/Vector3Stamped: acceleration, jerk, pressure angle

electronic cam (master.source: topic): the master drives ~/joint_states (one per
master message) instead of the clock, ~/state_extras stays silent, and
  ~/master            sensor_msgs/JointState, subscribed (name: master.topic): the master
  ~/commands          std_msgs/Float64MultiArray: each axis's position or velocity
  ~/joint_trajectory  trajectory_msgs/JointTrajectory: with command.trajectory_horizon > 0
  ~/engage            std_srvs/SetBool: engage the slave on the cam (false: hold)
  ~/switches          std_msgs/UInt32, latched: cam switch tracks, bit i = track i
  ~/switch_state      cam_ros_interfaces/SwitchState, latched: the same bits, stamped
                      with the master message's stamp and its position
  ~/engage_requests   cam_ros_interfaces/EngageRequest, latched: each answered ~/engage
  ~/state             diagnostic_msgs/DiagnosticStatus, latched: engaged, holding, end
                      of profile..., and the switch tracks
  ~/controller_state  cam_ros_interfaces/ControllerState: per axis report on
                      slave.state_topic: reference, feedback, following error
  /diagnostics        diagnostic_msgs/DiagnosticArray, about 1 Hz: design, master,
                      engagement, recording

The parameters come from the params files, in order (config/default.yaml if none is
given), then from the -p overrides. They are checked exactly as `cam_ros report` checks
a file, at configure (again at each configure: the files are read anew). Other ROS
arguments (remapping, logging) go to rclpy.

options:
  -h, --help  show this help and exit

exit codes:
  0  stopped by Ctrl-C, SIGTERM or the shutdown transition
  2  invalid params file, -p override or argument: one line "cam_node: <message>"
     (with autostart false a refused params file fails configure; the node lives on)
'''
