"""The line shaft's clock: a thread of its own that steps the line shaft every PERIOD_S while the
master is silent or the line shaft stops, so a busy executor cannot hold a stop up."""
from __future__ import annotations

import threading
from typing import Callable

from rclpy.node import Node

#: How often the clock looks (s).
PERIOD_S = 0.005


class ShaftClock:
    """Call step() every PERIOD_S with the lock held, from start until end() or the ROS
    context's shutdown (before rclpy finalizes its logging); a failed step is logged, not
    fatal."""

    def __init__(self, node: Node, lock: threading.Lock, step: Callable[[], None]):
        self._node, self._lock, self._step = node, lock, step
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name='line shaft clock', daemon=True)
        self._thread.start()
        node.context.on_shutdown(self.end)

    def end(self, wait_s: float = 1.0) -> None:
        """End the thread, waiting for a step under way (at most wait_s: a shutdown may come
        while this thread holds the lock the step waits for)."""
        self._stop.set()
        if self._thread is not threading.current_thread():
            self._thread.join(wait_s)

    def _run(self) -> None:
        while not self._stop.wait(PERIOD_S):
            with self._lock:
                try:
                    self._step()
                except Exception as err:  # a bug must cost one step, not the clock
                    if self._node.context.ok():
                        self._node.get_logger().error(f'line shaft step failed: {err!r}',
                                                      throttle_duration_sec=5.0)
