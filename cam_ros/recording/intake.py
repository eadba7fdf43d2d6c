"""Take the raw messages of subscriptions in batches, in a thread of their own."""

from collections.abc import Callable, Sequence
from contextlib import ExitStack
import math
import threading
import time
from typing import Any, Optional

from rclpy.callback_groups import CallbackGroup
from rclpy.exceptions import InvalidHandle
from rclpy.guard_condition import GuardCondition
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.subscription import Subscription

from cam_ros.rclpy_gaps import wait_set

#: One message as taken: its wire bytes and rclpy's message info (timestamps, sequence numbers).
Taken = tuple[bytes, dict[str, Any]]
#: Seconds between two takes while messages keep coming: the wake-up an executor pays for every
#: message is paid once per batch instead.
POLL_PERIOD = 0.005
#: Most messages taken from one subscription at a time, so that no busy topic starves the others.
MAX_BATCH = 1000


class TakenByIntake(CallbackGroup):
    """A callback group that no executor runs: only an intake thread serves its subscriptions.

    Their QoS event handlers stay out of every wait set: on rmw_fastrtps a subscription's events
    and its data share one DDS status condition, so a wait set holding the events (an executor's
    or the intake's own) turns the data wake-up off for the others: an executor then spins while
    the intake is never woken, and an intake of its own events takes 4-8x fewer messages/s.
    """

    def can_execute(self, entity: object) -> bool:
        """Return False, which keeps these subscriptions and their events out of executors."""
        return False

    def beginning_execution(self, entity: object) -> bool:
        """Refuse to run a callback."""
        return False

    def ending_execution(self, entity: object) -> None:
        """Do nothing: nothing ever began."""


class RawIntake:
    """
    Raw subscriptions of a node whose messages a background thread takes in batches.

    An rclpy executor rebuilds its wait set and runs one callback per message, which costs far
    more than taking the message; the node's executor never sees these subscriptions. While
    messages keep coming the thread takes them every POLL_PERIOD (the subscription queues hold
    them meanwhile) and hands each subscription's batch to `deliver(index, batch)`, in arrival
    order; when a take finds nothing it sleeps in a wait set until a message arrives. With
    `every` = (seconds, function) it also calls the function that often. stop() takes what is
    left and ends the thread, which destroys the subscriptions; a raising hand-over ends it too.
    """

    def __init__(self, node: Node, topics: Sequence[tuple[str, type, QoSProfile]],
                 deliver: Callable[[int, list[Taken]], None], *,
                 every: Optional[tuple[float, Callable[[], None]]] = None, name: str = 'intake'):
        """Subscribe the node to `topics` (name, message class, QoS) and start taking."""
        self._node = node
        self._deliver = deliver
        self._period, self._periodic = every or (math.inf, _nothing)
        self._stop = threading.Event()
        self._subscriptions: list[Subscription] = []
        self._wake = GuardCondition(None, None, context=node.context)
        group = TakenByIntake()
        try:
            for topic, msg_type, qos in topics:
                self._subscriptions.append(node.create_subscription(
                    msg_type, topic, _never_called, qos, callback_group=group, raw=True))
            self._wait_set = wait_set(node.context, len(self._subscriptions), 1)
        except BaseException:
            self._release()
            raise
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    @property
    def subscriptions(self) -> tuple[Subscription, ...]:
        """Return the subscriptions taken from (none once the thread has ended)."""
        return tuple(self._subscriptions)

    def stop(self) -> None:
        """Take what is left and end the thread (at once when called from a hand-over)."""
        self._stop.set()
        if threading.current_thread() is not self._thread:
            try:
                self._wake.trigger()
            except InvalidHandle:
                pass  # the thread has ended already
            self._thread.join()

    def _run(self) -> None:
        """Take batches until stopped (then once more), the node is gone or a hand-over raises."""
        next_call = time.monotonic() + self._period
        try:
            while True:
                started, stopping = time.monotonic(), self._stop.is_set()
                largest = self._take_all()
                if started >= next_call:
                    self._periodic()
                    next_call = time.monotonic() + self._period
                if stopping:
                    return
                if not largest:
                    self._wait(next_call - time.monotonic())
                elif largest < MAX_BATCH:
                    time.sleep(max(0.0, started + POLL_PERIOD - time.monotonic()))
        except InvalidHandle:
            pass  # the node was destroyed under the intake
        finally:
            self._stop.set()
            self._release()

    def _take_all(self) -> int:
        """Hand each subscription's waiting messages over; return the largest batch's size."""
        largest = 0
        for index, subscription in enumerate(self._subscriptions):
            handle, msg_type = subscription.handle, subscription.msg_type
            batch: list[Taken] = []
            with handle:
                for _ in range(MAX_BATCH):
                    taken = handle.take_message(msg_type, True)
                    if taken is None:
                        break
                    batch.append(taken)
            if batch:
                largest = max(largest, len(batch))
                self._deliver(index, batch)
        return largest

    def _wait(self, timeout: float) -> None:
        """Sleep until a message arrives, stop() is called or `timeout` seconds have passed."""
        with ExitStack() as stack:
            wait_set = self._wait_set
            wait_set.clear_entities()
            for subscription in self._subscriptions:
                stack.enter_context(subscription.handle)
                wait_set.add_subscription(subscription.handle)
            stack.enter_context(self._wake.handle)
            wait_set.add_guard_condition(self._wake.handle)
            wait_set.wait(-1 if math.isinf(timeout) else max(0, round(timeout * 1e9)))

    def _release(self) -> None:
        """Destroy the subscriptions and the wake-up condition (once)."""
        subscriptions, self._subscriptions = self._subscriptions, []
        for subscription in subscriptions:
            self._node.destroy_subscription(subscription)
        self._wake.destroy()


def _never_called(data: bytes) -> None:
    """Stand in for the callback that executors never run (see TakenByIntake)."""


def _nothing() -> None:
    """Do nothing (no periodic function)."""
