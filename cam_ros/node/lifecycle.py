"""What cam_node's managed-node transitions need beyond rclpy.lifecycle.

- Configured: what `configure` made (entities, parameter callbacks), so that `cleanup` destroys
  exactly that and the node is as it was before configure.
- guard_change_state: rclpy (Jazzy) raises out of the executor when ~/change_state asks, by id,
  for a transition the current state does not have (rcl: 'Transition is not registered'),
  which would end the node, and refuses one asked by label without a word; guarded, both are
  answered false and the node says why.
- The state machine itself: rclpy keeps it private (rclpy_gaps.state_machine).
"""
from __future__ import annotations

from typing import Any, Callable

from lifecycle_msgs.srv import ChangeState
from rclpy.lifecycle import LifecycleNode
from rclpy.node import Node

from cam_ros.rclpy_gaps import change_state_service, state_machine

#: The node's entity kinds: (the node's attribute listing them, its method destroying one).
ENTITY_KINDS = (('timers', 'destroy_timer'), ('services', 'destroy_service'),
                ('subscriptions', 'destroy_subscription'), ('clients', 'destroy_client'),
                ('publishers', 'destroy_publisher'), ('guards', 'destroy_guard_condition'))


class Configured:
    """Note what a node has when configure starts; destroy what was added since."""

    def __init__(self, node: Node):
        """Take the node's entities as they are before configure makes any."""
        self._node = node
        self._before = {id(entity) for kind, _ in ENTITY_KINDS
                        for entity in getattr(node, kind)}
        self.callbacks: list[Callable[..., Any]] = []  # on-set-parameters callbacks added

    def destroy(self) -> None:
        """Destroy the entities and remove the callbacks added since (threads stopped first)."""
        node = self._node
        for callback in self.callbacks:
            node.remove_on_set_parameters_callback(callback)
        self.callbacks.clear()
        for kind, destroy in ENTITY_KINDS:
            for entity in [entity for entity in getattr(node, kind)
                           if id(entity) not in self._before]:
                getattr(node, destroy)(entity)


def current_state(node: LifecycleNode) -> str:
    """Return the label of the node's primary state (rclpy keeps it in its state machine)."""
    return state_machine(node).current_state[1]


def transition_labels(node: LifecycleNode) -> list[str]:
    """Return the labels of the transitions the node's current state has."""
    return [description[1] for description in state_machine(node).available_transitions]


def guard_change_state(node: LifecycleNode, refused: Callable[[str], None],
                       reason: Callable[[str], str]) -> None:
    """Make ~/change_state say why it answers false: refused(why) is called with the reason.

    A transition the current state lacks is refused without being tried; one that fails says
    reason(label) (why the node failed the transition of that label).
    """
    service = change_state_service(node)
    answer = service.callback

    def guarded(request: ChangeState.Request,
                response: ChangeState.Response) -> ChangeState.Response:
        asked = request.transition
        found = [label for number, label, *_ in state_machine(node).available_transitions
                 if (label == asked.label if asked.label else number == asked.id)]
        if not found:
            refused(f'transition {asked.label or asked.id} is not available from '
                    f'{current_state(node)} (available: {", ".join(transition_labels(node))})')
            response.success = False
            return response
        response = answer(request, response)
        if not response.success:
            refused(f'{found[0]} failed: {reason(found[0])}')
        return response

    service.callback = guarded
