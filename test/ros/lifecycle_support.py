"""A managed cam_node as a real process, driven through its lifecycle services."""
from __future__ import annotations

import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from conftest import NodeProcess, SERVICE_TIMEOUT_S, wait_for_answer, wait_for_service
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetAvailableTransitions, GetState

CALL_TIMEOUT_S = 10.0
#: What `ros2 lifecycle` allows from each primary state (the ROS 2 managed-node design's
#: state machine, written out from lifecycle_msgs' ids, not read from the node).
ALLOWED = {
    State.PRIMARY_STATE_UNCONFIGURED: {
        Transition.TRANSITION_CONFIGURE: ('configure', State.TRANSITION_STATE_CONFIGURING),
        Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: ('shutdown',
                                                      State.TRANSITION_STATE_SHUTTINGDOWN)},
    State.PRIMARY_STATE_INACTIVE: {
        Transition.TRANSITION_CLEANUP: ('cleanup', State.TRANSITION_STATE_CLEANINGUP),
        Transition.TRANSITION_ACTIVATE: ('activate', State.TRANSITION_STATE_ACTIVATING),
        Transition.TRANSITION_INACTIVE_SHUTDOWN: ('shutdown',
                                                  State.TRANSITION_STATE_SHUTTINGDOWN)},
    State.PRIMARY_STATE_ACTIVE: {
        Transition.TRANSITION_DEACTIVATE: ('deactivate', State.TRANSITION_STATE_DEACTIVATING),
        Transition.TRANSITION_ACTIVE_SHUTDOWN: ('shutdown',
                                                State.TRANSITION_STATE_SHUTTINGDOWN)},
}


def call(client, request):
    """Call a service of the node and return its answer."""
    future = client.call_async(request)
    deadline = time.monotonic() + CALL_TIMEOUT_S
    while not future.done():
        assert time.monotonic() < deadline, f'{client.srv_name} did not answer'
        time.sleep(0.01)
    return future.result()


class Managed:
    """A cam_node process and clients of its lifecycle services."""

    def __init__(self, process: NodeProcess, node):
        self.process, self.node = process, node
        self._get = node.create_client(GetState, '/cam/get_state')
        self._change = node.create_client(ChangeState, '/cam/change_state')
        self._transitions = node.create_client(GetAvailableTransitions,
                                               '/cam/get_available_transitions')
        wait_for_service(self._get, process, SERVICE_TIMEOUT_S)
        wait_for_answer(self._get, GetState.Request(), process)
        for client in (self._change, self._transitions):
            wait_for_service(client, process, SERVICE_TIMEOUT_S)

    def state(self) -> tuple[int, str]:
        """Return the node's primary state (id, label)."""
        state = call(self._get, GetState.Request()).current_state
        return state.id, state.label

    def available(self) -> dict[int, tuple[str, int]]:
        """Return the transitions the node offers now: id -> (label, goal state id)."""
        answer = call(self._transitions, GetAvailableTransitions.Request())
        return {item.transition.id: (item.transition.label, item.goal_state.id)
                for item in answer.available_transitions}

    def change(self, label: str = '', number: int = 0) -> bool:
        """Ask for a transition by label (or by id alone); return the answer."""
        request = ChangeState.Request(transition=Transition(id=number, label=label))
        return call(self._change, request).success

    def services(self) -> set[str]:
        """Return the names of the node's services in the graph."""
        return {name for name, _ in self.node.get_service_names_and_types_by_node('cam', '/')}


@contextmanager
def managed_node(executor, folder: Path, params_file: Path, *ros_args: str) -> Iterator[Managed]:
    """Run cam_node with autostart false (in folder) and yield it once ~/get_state answers.

    The node serves nothing else yet; the process is killed on leaving if it still runs.
    """
    client = executor.node(f'lifecycle_client_{time.monotonic_ns()}')
    log_path = folder / f'cam-{time.monotonic_ns()}.log'
    command = [sys.executable, '-m', 'cam_ros.node', '--ros-args', '--params-file',
               str(params_file), '-p', 'autostart:=false', *ros_args]
    with open(log_path, 'wb') as log_file:
        process = NodeProcess(subprocess.Popen(command, stdout=log_file,
                                               stderr=subprocess.STDOUT, cwd=folder), log_path)
        try:
            yield Managed(process, client)
        finally:
            if process.process.poll() is None:
                process.process.kill()
                process.process.wait()
