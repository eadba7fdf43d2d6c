"""Client library for other Python nodes: evaluate a served cam, safely, from any thread.

    from cam_ros.client import CamClient, CamClientError

    client = CamClient(node)                      # node: any rclpy node of yours
    result = client.evaluate([0.0, 1.5], timeout=1.0, retries=2)
    result.position, result.pressure_angle        # NumPy arrays, SI, one entry per angle
    result.contact_force, result.camshaft_torque  # with dynamics (empty arrays without)

What it takes care of:

- Its reply reader keeps up to REPLY_DEPTH replies. rmw_fastrtps sends every reply of a service
  to every client of it (ros2/rmw_fastrtps#559); with the default depth of 10, a client among
  several busy ones finds its own reply pushed out by the others' and waits in vain.
- A call that times out is withdrawn (``remove_pending_request``), so a late reply finds no
  future, and tried again up to ``retries`` times: evaluate is idempotent.
- Requests larger than ``chunk_size`` angles are sent as several calls, so one answer never
  grows big enough to hold other clients up (every client receives every answer).
- It works whether the node spins in an executor elsewhere (any thread may call evaluate) or
  not at all (evaluate then spins the node itself until its answer is in).
"""
from __future__ import annotations

import threading
import time
from dataclasses import make_dataclass
from typing import Any

import numpy as np
from cam_ros_interfaces.srv import EvaluateCam
from numpy.typing import ArrayLike
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from cam_ros.core.config.parameters import SPECS
from cam_ros.core.errors import similar_names

#: Replies kept by the client's reader until taken; see the module docstring and docs/client.md.
REPLY_DEPTH = 1000
CLIENT_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=REPLY_DEPTH,
                        reliability=ReliabilityPolicy.RELIABLE)
#: Angles per call: the node's default output.max_batch.
CHUNK_SIZE = SPECS['output.max_batch'].default
SPIN_SLICE_S = 0.05  # spin_once slice when the client spins the node itself
#: Between looks at the graph while waiting for a service (rclpy's wait_for_service: 0.25 s,
#: a quarter of a command line's round trip).
GRAPH_POLL_S = 0.005
SIMILAR_NAMES = 5  # most similar names an error lists
#: The per-angle arrays of an answer (kinematics, and dynamics when the design has them).
FIELDS = tuple(name for name, kind in EvaluateCam.Response.get_fields_and_field_types().items()
               if kind == 'sequence<double>')
CamResult = make_dataclass('CamResult', [('angles', np.ndarray)]
                           + [(name, np.ndarray) for name in FIELDS], frozen=True)
CamResult.__doc__ = 'Evaluated cam angles (rad) and one SI array per EvaluateCam response field.'


def missing(node: Node, kind: str, name: str) -> str:
    """Explain a service or topic the graph lacks: the domain searched, similar names it has.

    kind is 'service' or 'topic'; the result starts with a space, to follow the error text.
    """
    listed = (node.get_service_names_and_types() if kind == 'service'
              else node.get_topic_names_and_types())
    similar = similar_names(name, (found for found, _ in listed), SIMILAR_NAMES)
    domain = node.context.get_domain_id()
    return (f' (ROS_DOMAIN_ID={domain}; similar {kind}s available: '
            f'{", ".join(similar) or "none discovered yet"})')


def wait_for_service(client: Any, deadline: float) -> bool:
    """Wait until the rclpy client sees its service, or the time.monotonic() deadline passes."""
    while not client.service_is_ready():
        if time.monotonic() >= deadline:
            return False
        time.sleep(min(GRAPH_POLL_S, max(0.0, deadline - time.monotonic())))
    return True


class CamClientError(RuntimeError):
    """An evaluate call failed: refused by the node, or unanswered after every retry."""


class CamClient:
    """Call a cam node's ``~/evaluate`` service; see the module docstring."""

    def __init__(self, node: Node, service: str = '/cam/evaluate', *,
                 chunk_size: int = CHUNK_SIZE):
        if chunk_size < 1:
            raise ValueError(f'chunk_size = {chunk_size}: must be at least 1')
        self.node = node
        self.chunk_size = chunk_size
        self.client = node.create_client(EvaluateCam, service, qos_profile=CLIENT_QOS)
        self._spin_lock = threading.Lock()
        self._executor: SingleThreadedExecutor | None = None

    @property
    def service(self) -> str:
        """Return the fully resolved service name."""
        return self.client.srv_name

    def evaluate(self, angles: ArrayLike, timeout: float = 1.0,
                 retries: int = 2) -> Any:
        """Evaluate the served cam at angles (rad); return a CamResult of NumPy arrays.

        Each call (one per chunk) waits up to timeout seconds for its answer and is tried again
        up to retries times. Raise CamClientError with the reason when the node refuses the
        request or never answers.
        """
        values = np.ascontiguousarray(angles, dtype=np.float64).reshape(-1)
        if values.size == 0:
            raise CamClientError(f'{self.service}: no angles given')
        parts = [self._call(chunk, timeout, retries)
                 for chunk in np.array_split(values, -(-values.size // self.chunk_size))]
        return CamResult(values, **{name: np.concatenate(
            [np.frombuffer(getattr(part, name), dtype=np.float64) for part in parts])
            for name in FIELDS})

    def destroy(self) -> None:
        """Destroy the service client (the node stays yours)."""
        self.node.destroy_client(self.client)
        if self._executor is not None:
            self._executor.shutdown()

    def _call(self, angles: np.ndarray, timeout: float, retries: int) -> EvaluateCam.Response:
        request = EvaluateCam.Request(angles=angles.tolist())
        for _ in range(retries + 1):
            deadline = time.monotonic() + timeout
            if not wait_for_service(self.client, deadline):
                continue
            response = self._wait(self.client.call_async(request), deadline)
            if response is None:
                continue
            if not response.success:
                raise CamClientError(f'{self.service} refused: {response.message}')
            return response
        ready = self.client.service_is_ready()
        problem = 'did not answer' if ready else 'is not available'
        attempts = f' (each of {retries + 1} attempts)' if retries else ''
        hint = '' if ready else missing(self.node, 'service', self.service)
        raise CamClientError(f'service {self.service} {problem} within {timeout:g} s{attempts}'
                             f'{hint}')

    def _wait(self, future: Any, deadline: float) -> EvaluateCam.Response | None:
        """Return the future's response by the deadline, else withdraw the request."""
        if self.node.executor not in (None, self._executor):  # spun elsewhere
            done = threading.Event()
            future.add_done_callback(lambda _: done.set())
            done.wait(max(0.0, deadline - time.monotonic()))
        else:
            self._spin_until(future, deadline)
        if not future.done():
            self.client.remove_pending_request(future)
            return None
        return future.result()

    def _spin_until(self, future: Any, deadline: float) -> None:
        """Spin the node in a private executor (one thread at a time) until future is done."""
        with self._spin_lock:
            if self._executor is None:
                self._executor = SingleThreadedExecutor(context=self.node.context)
            self._executor.add_node(self.node)
            try:
                while not future.done() and (left := deadline - time.monotonic()) > 0:
                    self._executor.spin_once(timeout_sec=min(SPIN_SLICE_S, left))
            finally:
                self._executor.remove_node(self.node)
