"""
Serve one subscription or service of a node on a thread of its own, with a wait set of its own.

An rclpy executor rebuilds a wait set of all its nodes' entities (services, the six parameter
services, timers, the publishers' QoS event handlers) on every wake-up and runs each callback as
a task: with cam_node's many entities that costs more than answering a one-angle ~/evaluate.
OwnThread waits on its one entity and a guard condition alone and handles each message or
request as soon as it arrives; the node's executor never sees the entity (TakenByIntake).
"""
from __future__ import annotations

import threading
from typing import Any, Callable, Generic, TypeVar

from rclpy.exceptions import InvalidHandle
from rclpy.guard_condition import GuardCondition
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.service import Service
from rclpy.subscription import Subscription

from cam_ros.rclpy_gaps import wait_set
from cam_ros.recording.intake import TakenByIntake

Entity = TypeVar('Entity', Subscription, Service)


class OwnThread(Generic[Entity]):
    """
    One entity of a node (a subscription or a service) served on a thread of its own.

    Make one with OwnThread.subscription or OwnThread.service; callbacks run on its thread, one
    at a time, so whatever they share with the executor's callbacks must be safe to read there.
    A callback that raises is logged and the thread goes on (a request so refused gets no
    answer). stop() ends the thread and destroys the entity: call it before the node is
    destroyed (a thread still inside the entity when its node goes away ends quietly).
    """

    def __init__(self, node: Node, entity: Entity, handle_one: Callable[[], bool], name: str):
        """Serve entity: handle_one() takes and handles one message or request, False if none."""
        self.entity: Entity = entity
        self._node = node
        self._handle_one = handle_one
        self._name = name
        self._stop = threading.Event()
        self._wake = GuardCondition(None, None, context=node.context)
        is_service = isinstance(entity, Service)
        self._wait_set = wait_set(node.context, int(not is_service), 1, services=int(is_service))
        self._add = self._wait_set.add_service if is_service else self._wait_set.add_subscription
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    @staticmethod
    def subscription(node: Node, msg_type: Any, topic: str, callback: Callable[[Any], None],
                     qos: QoSProfile, name: str, **options: Any) -> OwnThread[Subscription]:
        """Subscribe node to topic (options: create_subscription's) and take it on a thread."""
        subscription = node.create_subscription(msg_type, topic, callback, qos,
                                                callback_group=TakenByIntake(), **options)

        def take_one() -> bool:
            taken = subscription.handle.take_message(msg_type, subscription.raw)
            if taken is None:
                return False
            callback(taken[0])
            return True
        return OwnThread(node, subscription, take_one, name)

    @staticmethod
    def newest(node: Node, msg_type: Any, topic: str,
               callback: Callable[[Any, int, int], None], qos: QoSProfile, name: str,
               late_ns: int, **options: Any) -> OwnThread[Subscription]:
        """Subscribe as subscription() does, but take every message waiting and hand on, in
        order, those that arrived within late_ns before the newest and the newest:
        callback(message, its arrival (ns, the middleware's reception stamp), how many older
        ones were skipped before it). A set-point stream so never goes stale behind a backlog."""
        subscription = node.create_subscription(msg_type, topic, lambda _: None, qos,
                                                callback_group=TakenByIntake(), **options)

        def take_newest() -> bool:
            waiting = []
            while (taken := subscription.handle.take_message(msg_type, subscription.raw)):
                waiting.append((taken[0], int(taken[1]['received_timestamp'])))
            if not waiting:
                return False
            newest = waiting[-1][1]
            fresh = [(message, arrived) for message, arrived in waiting
                     if newest - arrived <= late_ns]
            skipped = len(waiting) - len(fresh)
            for message, arrived in fresh:
                callback(message, arrived, skipped)
                skipped = 0
            return True
        return OwnThread(node, subscription, take_newest, name)

    @staticmethod
    def service(node: Node, srv_type: Any, service_name: str,
                callback: Callable[[Any, Any], Any]) -> OwnThread[Service]:
        """Create a service of node, callback(request, response) -> response, on a thread."""
        service = node.create_service(srv_type, service_name, callback,
                                      callback_group=TakenByIntake())

        def answer_one() -> bool:
            request, header = service.handle.service_take_request(srv_type.Request)
            if header is None:
                return False
            response = callback(request, srv_type.Response())
            service.send_response(response, header)
            return True
        return OwnThread(node, service, answer_one, service_name)

    def _run(self) -> None:
        entity, wake, waits = self.entity, self._wake, self._wait_set
        try:
            while not self._stop.is_set():
                with entity.handle, wake.handle:
                    try:
                        if self._handle_one():
                            continue
                    except InvalidHandle:
                        raise
                    except Exception as err:  # a bug in one callback must not end the thread
                        self._node.get_logger().error(f'{self._name}: {err!r}',
                                                      throttle_duration_sec=1.0)
                        continue
                    waits.clear_entities()
                    self._add(entity.handle)
                    waits.add_guard_condition(wake.handle)
                    waits.wait(-1)
        except InvalidHandle:
            pass  # the node went away under the thread

    def stop(self) -> None:
        """End the thread (waiting for a callback under way) and destroy the entity; idempotent."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._wake.trigger()
        self._thread.join()
        if isinstance(self.entity, Service):
            self._node.destroy_service(self.entity)
        else:
            self._node.destroy_subscription(self.entity)
        self._wake.destroy()
