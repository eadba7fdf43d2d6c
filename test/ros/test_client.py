"""cam_ros.client: CamClient against a real cam_node, and against a test server that stalls."""
from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR

from cam_ros.client import CamClient, CamClientError, FIELDS, REPLY_DEPTH
from cam_ros.core import build_design, load_config

DEFAULT = CONFIG_DIR / 'default.yaml'
DYNAMICS = CONFIG_DIR / 'machine_dynamics.yaml'
THREADS = 4
CALLS_PER_THREAD = 25
STALL_S = 0.6  # the stalling server answers its first requests this late ...
ATTEMPT_TIMEOUT_S = 0.2  # ... after the client gave up on them


def expected(config, angles) -> dict[str, np.ndarray]:
    """Return the core's answer for every response array (empty dynamics without dynamics)."""
    state = build_design(load_config(config)).evaluate(np.asarray(angles, dtype=float))
    dynamics = state.dynamics
    return {name: np.asarray(getattr(state, name)) if hasattr(state, name) else
            np.asarray(getattr(dynamics, name)) if dynamics is not None else np.empty(0)
            for name in FIELDS}


def assert_equal(result, config, angles) -> None:
    np.testing.assert_array_equal(result.angles, angles)
    for name, values in expected(config, angles).items():
        np.testing.assert_array_equal(getattr(result, name), values, err_msg=name)


def test_reply_reader_keeps_other_clients_replies(executor):
    client = CamClient(executor.node('depth_probe'))
    assert client.client.qos_profile.depth == REPLY_DEPTH >= 100


def test_calls_from_many_threads_while_the_node_spins_elsewhere(start_cam_node, executor):
    start_cam_node(DYNAMICS)
    client = CamClient(executor.node('threaded_user'))
    rng = np.random.default_rng(7)
    batches = [rng.uniform(-20.0, 20.0, rng.integers(1, 50)) for _ in range(THREADS)]
    problems: list[BaseException] = []

    def work(angles: np.ndarray) -> None:
        try:
            for _ in range(CALLS_PER_THREAD):
                assert_equal(client.evaluate(angles), DYNAMICS, angles)
        except BaseException as err:  # reported by the main thread
            problems.append(err)

    threads = [threading.Thread(target=work, args=(angles,)) for angles in batches]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert problems == []
    assert expected(DYNAMICS, [1.0])['contact_force'].size == 1  # the dynamics were compared
    assert client.client._pending_requests == {}


def test_without_an_executor_the_client_spins_the_node_itself(start_cam_node, ros_context):
    import rclpy

    start_cam_node(DEFAULT)
    node = rclpy.create_node('unspun_user', context=ros_context)
    try:
        client = CamClient(node)
        angles = np.radians([0.0, 100.0, 200.0, 300.0])
        results = []
        threads = [threading.Thread(target=lambda: results.append(client.evaluate(angles)))
                   for _ in range(2)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        assert len(results) == 2
        for result in results:
            assert_equal(result, DEFAULT, angles)
        assert node.executor is not None and node.executor is client._executor
        client.destroy()
    finally:
        node.destroy_node()


def test_large_requests_go_in_chunks_the_node_accepts(start_cam_node, executor):
    start_cam_node(DEFAULT, '-p', 'output.max_batch:=1000')
    angles = np.linspace(-7.0, 7.0, 2501)
    assert_equal(CamClient(executor.node('bulk_user'), chunk_size=1000).evaluate(angles),
                 DEFAULT, angles)
    with pytest.raises(CamClientError, match=r'^/cam/evaluate refused: angles has 1251 '
                                             r'entries: more than output\.max_batch = 1000'):
        CamClient(executor.node('greedy_user'), chunk_size=2000).evaluate(angles)


def test_refusals_raise_with_the_nodes_reason(start_cam_node, executor):
    start_cam_node(DEFAULT)
    client = CamClient(executor.node('careless_user'))
    with pytest.raises(CamClientError, match=r'refused: angles\[1\] = nan'):
        client.evaluate([0.0, math.nan])
    with pytest.raises(CamClientError, match='no angles given'):
        client.evaluate([])
    with pytest.raises(ValueError, match='chunk_size = 0: must be at least 1'):
        CamClient(executor.node('odd_user'), chunk_size=0)


def test_a_missing_service_raises_after_every_attempt(executor, ros_domain):
    client = CamClient(executor.node('lonely_user'), '/nobody/evaluate')
    with pytest.raises(CamClientError) as raised:
        client.evaluate([0.0], timeout=0.1, retries=2)
    assert str(raised.value).startswith('service /nobody/evaluate is not available within 0.1 s '
                                        f'(each of 3 attempts) (ROS_DOMAIN_ID={ros_domain}; '
                                        'similar services available: ')


def test_a_misspelt_service_is_named_with_the_similar_ones(start_cam_node, executor):
    start_cam_node(DEFAULT)
    client = CamClient(executor.node('typing_user'), '/cams/evaluate')
    with pytest.raises(CamClientError) as raised:
        client.evaluate([0.0], timeout=1.0, retries=0)
    assert 'is not available within 1 s' in str(raised.value)
    assert 'similar services available: /cam/evaluate' in str(raised.value)


class StallingServer:
    """An EvaluateCam server that answers its first `late` requests STALL_S late.

    Its callbacks run in parallel (reentrant group, several threads), so a stalled request does
    not hold up the next one.
    """

    def __init__(self, context: object, late: int):
        from rclpy.callback_groups import ReentrantCallbackGroup
        from rclpy.executors import MultiThreadedExecutor
        from rclpy.node import Node

        self.late = late
        self.requests = 0
        self._lock = threading.Lock()
        self.node = Node('stalling_server', context=context)
        self.node.create_service(EvaluateCam, '/stalling/evaluate', self.answer,
                                 callback_group=ReentrantCallbackGroup())
        self.executor = MultiThreadedExecutor(num_threads=THREADS, context=context)
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self.executor.spin, daemon=True)
        self._thread.start()

    def answer(self, request: EvaluateCam.Request,
               response: EvaluateCam.Response) -> EvaluateCam.Response:
        with self._lock:
            self.requests += 1
            number = self.requests
        if number <= self.late:
            time.sleep(STALL_S)
        response.position = [float(number)] * len(request.angles)
        response.success = True
        return response

    def close(self) -> None:
        self.executor.shutdown()
        self._thread.join()
        self.node.destroy_node()


@pytest.mark.parametrize('late, retries, answered_by', [(2, 2, 3), (2, 1, None)])
def test_unanswered_calls_are_withdrawn_and_retried(ros_context, executor, late, retries,
                                                    answered_by):
    server = StallingServer(ros_context, late)
    try:
        client = CamClient(executor.node('patient_user'), '/stalling/evaluate')
        if answered_by is None:
            with pytest.raises(CamClientError, match='did not answer within 0.2 s '
                                                     r'\(each of 2 attempts\)'):
                client.evaluate([1.0, 2.0], timeout=ATTEMPT_TIMEOUT_S, retries=retries)
        else:
            result = client.evaluate([1.0, 2.0], timeout=ATTEMPT_TIMEOUT_S, retries=retries)
            np.testing.assert_array_equal(result.position, [answered_by, answered_by])
        time.sleep(late * STALL_S)  # the late answers arrive and find no future
        assert server.requests == min(late + 1, retries + 1)
        assert client.client._pending_requests == {}
    finally:
        server.close()
