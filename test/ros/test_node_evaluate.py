"""~/evaluate served on its own thread (OwnThread): exact answers, one design each, clean stop."""
from __future__ import annotations

import math
import threading

import numpy as np
import pytest
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR
from rclpy.parameter import Parameter

from cam_ros.core import build_design, CamDesign, parse_parameters, read_parameters_file
from cam_ros.node.node import CamNode

CALL_TIMEOUT_S = 10.0
DEFAULT = CONFIG_DIR / 'default.yaml'
FIELDS = ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
          'radius_of_curvature')
#: Two designs a parameter update swaps between: every field of an answer tells them apart.
SWAPPED = {'cam_speed': (2 * math.pi, 3 * math.pi), 'follower.base_radius': (4.0, 5.0)}


def design_with(**updates):
    values = read_parameters_file(DEFAULT)
    values.update(updates)
    return build_design(parse_parameters(values))


@pytest.fixture
def served(executor):
    """An in-process cam_node spun by the test executor, and a client of its ~/evaluate."""
    node = CamNode(DEFAULT, context=executor.context)
    executor.executor.add_node(node)
    client = executor.node('evaluate_client').create_client(EvaluateCam, '/cam/evaluate')
    assert client.wait_for_service(timeout_sec=CALL_TIMEOUT_S)
    try:
        yield node, client
    finally:
        executor.executor.remove_node(node)
        node.destroy_node()


def call(client, angles) -> EvaluateCam.Response:
    response = client.call(EvaluateCam.Request(angles=list(angles)), timeout_sec=CALL_TIMEOUT_S)
    assert response is not None, 'no answer from ~/evaluate'
    return response


def assert_exact(response, design, angles):
    assert response.success, response.message
    expected = design.evaluate(np.asarray(angles, dtype=float))
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(response, field), getattr(expected, field), field)
    assert len(response.contact_force) == 0  # the default design has no dynamics


@pytest.mark.parametrize('angles', [
    [1.0], [0.0], [-7.5], [2 * math.pi], [1e6],
    [0.0, 1.2, 2.5, 4.0, 6.0], [6.0, -1.0, 3.0, 3.0, 100.0]])
def test_one_and_many_angles_are_the_cores_bitwise(served, angles):
    node, client = served
    assert_exact(call(client, angles), node.design, angles)


def test_bad_requests_are_refused_with_their_reason_and_serving_goes_on(served):
    node, client = served
    for angles, fragment in (([], 'empty'), ([math.nan], 'angles[0]'),
                             ([0.5, math.inf], 'angles[1]')):
        response = call(client, angles)
        assert not response.success and fragment in response.message
        assert len(response.position) == 0
    assert_exact(call(client, [1.0]), node.design, [1.0])


def test_an_internal_error_is_answered_and_serving_goes_on(served, monkeypatch):
    node, client = served
    evaluate = CamDesign.evaluate

    def broken(design, angles):  # at 123 rad only: the state timer evaluates too
        if np.array_equal(angles, [123.0]):
            raise ZeroDivisionError('a bug in the core')
        return evaluate(design, angles)

    monkeypatch.setattr(CamDesign, 'evaluate', broken)
    response = call(client, [123.0])
    assert not response.success
    assert response.message == "internal error: ZeroDivisionError('a bug in the core')"
    assert_exact(call(client, [1.0]), node.design, [1.0])


def test_each_answer_comes_from_one_design_while_updates_swap_it(served):
    node, client = served
    designs = [design_with(**{name: values[i] for name, values in SWAPPED.items()})
               for i in (0, 1)]
    angles = [0.3, 1.9, 2.6, 4.5]
    expected = [design.evaluate(np.array(angles)) for design in designs]
    done = threading.Event()
    answers: list[EvaluateCam.Response] = []

    def ask() -> None:
        while not done.is_set():
            answers.append(call(client, angles))

    asker = threading.Thread(target=ask)
    asker.start()
    try:
        for update in range(20):
            result = node.set_parameters_atomically([
                Parameter(name, value=values[(update + 1) % 2])
                for name, values in SWAPPED.items()])
            assert result.successful, result.reason
    finally:
        done.set()
        asker.join(timeout=2 * CALL_TIMEOUT_S)
    assert answers
    for response in answers:
        assert response.success, response.message
        which = [all(np.array_equal(getattr(response, field), getattr(state, field))
                     for field in FIELDS) for state in expected]
        assert any(which), 'an answer mixes two designs'


def test_destroying_the_node_ends_the_evaluate_thread(executor):
    node = CamNode(DEFAULT, context=executor.context)
    client = executor.node('evaluate_client').create_client(EvaluateCam, '/cam/evaluate')
    assert client.wait_for_service(timeout_sec=CALL_TIMEOUT_S)
    call(client, [1.0])  # spun by the node's own thread: no executor holds the node
    assert '~/evaluate' in [thread.name for thread in threading.enumerate()]
    node.destroy_node()
    assert '~/evaluate' not in [thread.name for thread in threading.enumerate()]
    assert client.call(EvaluateCam.Request(angles=[1.0]), timeout_sec=0.5) is None
