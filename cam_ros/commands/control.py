"""Node commands: switch recording, reload the params file, get, set and list parameters.

They use the node's own services (`~/record`, `~/reload`, and the standard parameter services),
so an integrator needs no `ros2` CLI. A refusal prints the node's reason verbatim and exits 1.
"""
from __future__ import annotations

import json
import time
from typing import Any, Callable, Sequence

from cam_ros.commands.common import say
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK
from cam_ros.commands.ros import DEFAULT_TIMEOUT_S, request_once, ros_node
from cam_ros.core import InvalidParameter
from cam_ros.core.errors import did_you_mean

DEFAULT_NODE = '/cam'


class _Unanswered(Exception):
    """A service of the node was not available or did not answer (the message says which)."""


Ask = Callable[[Any, str, Any], Any]


def _session(command: str, timeout: float, work: Callable[[Ask], int]) -> int:
    """Run work(ask) with one private ROS node; ask(type, service, request) returns the answer.

    All requests share the timeout; one that is not answered ends the command with exit 1.
    """
    deadline = time.monotonic() + timeout
    with ros_node(command) as (node, executor):
        def ask(service_type: Any, service: str, request: Any) -> Any:
            response, problem = request_once(node, executor, service_type, service, request,
                                             deadline, timeout)
            if response is None:
                raise _Unanswered(problem)
            return response

        try:
            return work(ask)
        except _Unanswered as err:
            say(command, str(err))
            return EXIT_FAILED


def _node_name(node: str) -> str:
    """Return the node's fully qualified name ('cam' -> '/cam')."""
    return node if node.startswith('/') else f'/{node}'


def _trigger(command: str, service_type: Any, service: str, request: Any, timeout: float) -> int:
    """Call a service answering success and message; print the message, 1 if it failed."""
    def work(ask: Ask) -> int:
        response = ask(service_type, service, request)
        if not response.success:
            say(command, f'{service} refused: {response.message}')
            return EXIT_FAILED
        print(response.message)
        return EXIT_OK

    return _session(command, timeout, work)


def record(state: str, node: str = DEFAULT_NODE, timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Start (state 'on') or stop ('off') the node's recording through its ~/record service."""
    from std_srvs.srv import SetBool

    return _trigger('record', SetBool, f'{_node_name(node)}/record',
                    SetBool.Request(data=state == 'on'), timeout)


def reload(node: str = DEFAULT_NODE, timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Make the node re-read the params file it started with (its ~/reload service)."""
    from std_srvs.srv import Trigger

    return _trigger('reload', Trigger, f'{_node_name(node)}/reload', Trigger.Request(), timeout)


def value_text(value: Any) -> str:
    """Return a parameter value as YAML flow text (JSON is YAML): 4.0, "cm", [1, 2], null."""
    return json.dumps(value)


def _values(ask: Ask, node: str, names: Sequence[str]) -> dict[str, Any]:
    """Return {name: value} of the node's parameters (all when names is empty).

    A parameter declared by type but never given a value is None: the node's get_parameters
    service answers nothing at all when asked for one, so only the others are asked for.
    """
    from rcl_interfaces.msg import ParameterType
    from rcl_interfaces.srv import GetParameters, GetParameterTypes, ListParameters
    from rclpy.parameter import parameter_value_to_python

    known = sorted(ask(ListParameters, f'{node}/list_parameters',
                       ListParameters.Request()).result.names)
    for name in names:
        if name not in known:
            raise InvalidParameter('NAME', name,
                                   f'is not a parameter of {node}{did_you_mean(name, known)}')
    wanted = list(names) or known
    types = ask(GetParameterTypes, f'{node}/get_parameter_types',
                GetParameterTypes.Request(names=wanted)).types
    present = [name for name, kind in zip(wanted, types)
               if kind != ParameterType.PARAMETER_NOT_SET]
    answer = ask(GetParameters, f'{node}/get_parameters', GetParameters.Request(names=present))
    if len(answer.values) != len(present):
        raise _Unanswered(f'{node} answered {len(answer.values)} of {len(present)} values')
    values: dict[str, Any] = dict.fromkeys(wanted)
    values.update((name, parameter_value_to_python(value))
                  for name, value in zip(present, answer.values))
    return values


def param_get(names: Sequence[str], node: str = DEFAULT_NODE,
              timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Print 'name: value' for each parameter named (null: declared but unset)."""
    def work(ask: Ask) -> int:
        for name, value in _values(ask, _node_name(node), names).items():
            print(f'{name}: {value_text(value)}')
        return EXIT_OK

    return _session('param', timeout, work)


def param_list(node: str = DEFAULT_NODE, timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Print every parameter of the node as 'name: value', sorted by name."""
    return param_get([], node, timeout)


def param_set(assignments: Sequence[str], node: str = DEFAULT_NODE,
              timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Set parameters atomically: all of NAME VALUE pairs, or none; 1 with the node's reason."""
    from rcl_interfaces.msg import Parameter
    from rcl_interfaces.srv import SetParametersAtomically
    from rclpy.parameter import get_parameter_value, parameter_value_to_python

    if len(assignments) % 2:
        raise InvalidParameter('NAME VALUE', list(assignments), 'give a value for every name')
    parameters = [Parameter(name=name, value=get_parameter_value(text))
                  for name, text in zip(assignments[::2], assignments[1::2])]
    name = _node_name(node)

    def work(ask: Ask) -> int:
        result = ask(SetParametersAtomically, f'{name}/set_parameters_atomically',
                     SetParametersAtomically.Request(parameters=parameters)).result
        if not result.successful:
            say('param', f'{name} rejected the update: {result.reason}')
            return EXIT_FAILED
        for parameter in parameters:
            print(f'{parameter.name}: {value_text(parameter_value_to_python(parameter.value))}')
        return EXIT_OK

    return _session('param', timeout, work)
