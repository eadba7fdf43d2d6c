"""ROS commands: call a cam node's evaluate service, echo any topic of the graph.

Each command runs in its own rclpy context (no signal handlers installed, so Ctrl-C is a plain
KeyboardInterrupt) and shuts it down before returning.
"""
from __future__ import annotations

import csv
import math
import os
import sys
import time
from contextlib import contextmanager
from typing import Any, Iterator, Sequence

import numpy as np
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from cam_ros.client import CamClient, CamClientError, GRAPH_POLL_S, missing, wait_for_service
from cam_ros.commands.common import dump_json, DYNAMICS_FIELDS, format_table, number, say
from cam_ros.commands.message_text import message_text, numeric_fields
from cam_ros.core import InvalidParameter
from cam_ros.core.config.schema import angular_positions
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK
from cam_ros.node.middleware import use_shipped_profile

DEFAULT_SERVICE = '/cam/evaluate'
DEFAULT_TIMEOUT_S = 5.0
UNIT_QUERY_TIMEOUT_S = 1.0  # most time spent asking the node for its follower type
POLL_S = 0.05  # spin slice of the echo loop
ECHO_DEPTH = 10


@contextmanager
def ros_node(kind: str) -> Iterator[tuple[Node, SingleThreadedExecutor]]:
    """Yield a node 'cam_ros_<kind>_<pid>' and an executor in a private context."""
    use_shipped_profile()
    context = Context()
    rclpy.init(args=[], context=context)
    try:
        node = rclpy.create_node(f'cam_ros_{kind}_{os.getpid()}', context=context,
                                 start_parameter_services=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        try:
            yield node, executor
        finally:
            executor.shutdown()
            node.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)


def _remaining(deadline: float) -> float:
    return max(0.0, deadline - time.monotonic())


def request_once(node: Node, executor: SingleThreadedExecutor, service_type: Any, name: str,
                 request: Any, deadline: float, timeout: float) -> tuple[Any, str]:
    """Call a service once before the deadline; return (response or None, why it failed).

    timeout is the seconds the caller allowed in all, for the message.
    """
    client = node.create_client(service_type, name)
    try:
        if not wait_for_service(client, deadline):
            return None, (f'service {client.srv_name} is not available within {timeout:g} s'
                          + missing(node, 'service', client.srv_name))
        future = client.call_async(request)
        executor.spin_until_future_complete(future, timeout_sec=_remaining(deadline))
        if not future.done():
            client.remove_pending_request(future)
            return None, f'service {client.srv_name} did not answer within {timeout:g} s'
        return future.result(), ''
    finally:
        node.destroy_client(client)


def _position_unit(node: Node, executor: SingleThreadedExecutor, service: str,
                   deadline: float) -> str:
    """Ask the serving node its follower's position unit: 'm', or 'rad' (an oscillating arm or
    a rotary slave, length_unit deg); a machine axis's service asks its node for the axis's."""
    from rcl_interfaces.srv import GetParameters

    node_name = node.resolve_service_name(service).rpartition('/')[0]
    if not node_name:
        return 'm|rad'
    prefix = ''
    machine, _, axis = node_name.rpartition('/')  # a machine axis's /<node>/<axis>/evaluate
    nodes = {f'{space.rstrip("/")}/{name}' for name, space in
             node.get_node_names_and_namespaces()}
    if node_name not in nodes and machine in nodes:
        node_name, prefix = machine, f'{axis}.'
    short = min(deadline, time.monotonic() + UNIT_QUERY_TIMEOUT_S)
    response, _ = request_once(node, executor, GetParameters, f'{node_name}/get_parameters',
                               GetParameters.Request(names=[f'{prefix}follower.type',
                                                            f'{prefix}length_unit']),
                               short, UNIT_QUERY_TIMEOUT_S)
    if response is None or len(response.values) != 2:
        return 'm|rad'
    kind, unit = (value.string_value for value in response.values)
    return 'rad' if angular_positions(kind, unit) else 'm'


def _call_units(unit: str, dynamics: bool) -> dict[str, str]:
    """Return the unit of each array of a call's answer (dynamics: it has the force arrays)."""
    return {'angle': 'rad', 'position': unit, 'velocity': f'{unit}/s',
            'acceleration': f'{unit}/s^2', 'jerk': f'{unit}/s^3', 'pressure_angle': 'rad',
            'radius_of_curvature': 'm',
            **{name: dimension for name, _, dimension in DYNAMICS_FIELDS if dynamics}}


def call(angles: Sequence[float], degrees: bool = False, json_output: bool = False,
         service: str = DEFAULT_SERVICE, timeout: float = DEFAULT_TIMEOUT_S) -> int:
    """Evaluate the served cam at angles (rad, or deg) and print the answer; 1 on failure."""
    values = np.radians(angles) if degrees else np.asarray(angles, dtype=float)
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise InvalidParameter('ANGLE', list(angles), 'give one or more finite cam angles')
    deadline = time.monotonic() + timeout
    with ros_node('call') as (node, executor):
        node.executor = None  # nobody spins it: the CamClient spins it while it waits
        client = CamClient(node, service)
        try:
            result = client.evaluate(values, timeout=timeout, retries=0)
        except CamClientError as err:
            say('call', str(err))
            return EXIT_FAILED
        executor.add_node(node)
        unit = _position_unit(node, executor, service, deadline)
    units = _call_units(unit, dynamics=result.contact_force.size > 0)  # empty: no dynamics
    columns = {name: values if name == 'angle' else getattr(result, name) for name in units}
    if json_output:
        print(dump_json({'service': service, 'units': units, **columns}))
        return EXIT_OK
    table = {'angle (deg)': np.degrees(values)}  # and the pressure angle in deg
    for name, array in columns.items():
        degree = name == 'pressure_angle'
        shown = f'{name.replace("_", " ")} ({"deg" if degree else units[name]})'
        table[shown] = np.degrees(array) if degree else array
    rows = [[f'{value:.4f}' if header.endswith('(deg)') else number(value)
             for header, value in zip(table, row)]
            for row in np.column_stack(list(table.values())).tolist()]
    print(format_table(list(table), rows))
    return EXIT_OK


# ------------------------------------------------------------------------------------ echo

def subscription_qos(publishers: Sequence[Any]) -> QoSProfile:
    """Return a QoS that matches every publisher: latched only if all publishers are latched."""
    profiles = [info.qos_profile for info in publishers]
    latched = bool(profiles) and all(
        p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
    best_effort = any(p.reliability == ReliabilityPolicy.BEST_EFFORT for p in profiles)
    return QoSProfile(
        depth=ECHO_DEPTH,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE)


def _subscribe(node: Node, name: str, callback: Any, deadline: float) -> bool:
    """Subscribe to topic name once it has a publisher (its type and QoS from the graph).

    Return False if no publisher appeared before the deadline.
    """
    from cam_ros.recording.schema import import_type

    while not (publishers := node.get_publishers_info_by_topic(name)):
        if time.monotonic() >= deadline:
            return False
        time.sleep(GRAPH_POLL_S)
    types = sorted({info.topic_type for info in publishers})
    if len(types) != 1:
        raise InvalidParameter('TOPIC', name, f'has several types ({", ".join(types)})')
    node.create_subscription(import_type(types[0]), name, callback, subscription_qos(publishers))
    return True


class _Printer:
    """Print each message as YAML-like text ('---' after each) or as a CSV row."""

    def __init__(self, csv_output: bool):
        self.count = 0
        self._writer = csv.writer(sys.stdout, lineterminator='\n') if csv_output else None

    def __call__(self, message: Any) -> None:
        if self._writer is None:
            print(message_text(message), '---', sep='\n', flush=True)
        else:
            fields = list(numeric_fields(message))
            if self.count == 0:
                self._writer.writerow(name for name, _ in fields)
            self._writer.writerow(value for _, value in fields)
            sys.stdout.flush()
        self.count += 1


def echo(topic: str, once: bool = False, csv_output: bool = False, count: int | None = None,
         timeout: float | None = None) -> int:
    """Print messages of a topic as they arrive; 1 if it or the messages asked for never came."""
    name = topic if topic.startswith('/') else f'/{topic}'
    wanted = 1 if once else count
    deadline = math.inf if timeout is None else time.monotonic() + timeout
    printer = _Printer(csv_output)
    try:
        with ros_node('echo') as (node, executor):
            if not _subscribe(node, name, printer, deadline):
                say('echo', f'no publisher of {name} within {timeout:g} s'
                    + missing(node, 'topic', name))
                return EXIT_FAILED
            while (wanted is None or printer.count < wanted) and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=min(POLL_S, _remaining(deadline)))
    except KeyboardInterrupt:  # Ctrl-C ends an echo normally
        return EXIT_OK
    if printer.count < (wanted or 1):  # only reached with a timeout
        say('echo', f'{printer.count} of {wanted or "at least 1"} messages on {name} within '
                    f'{timeout:g} s')
        return EXIT_FAILED
    return EXIT_OK
