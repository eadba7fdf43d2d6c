"""Re-apply a recording's parameter changes at their places in a replayed stream.

Each recorded /parameter_events message of a node becomes one event (one atomic set on that
node), due before the first replayed message whose log time is not earlier than its own: the
order in which the recorded node saw them. Deletions and recording.* are left out (a replay
must not switch the fresh node's recording).
"""

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

from rcl_interfaces.msg import Parameter as ParameterMsg
from rclpy.parameter import Parameter

from cam_ros.core.config.parameters import SPECS
from cam_ros.recording.parameters import ParameterChange

#: Parameters a replay leaves alone.
SKIPPED_PREFIX = 'recording.'
_ARRAYS = {'double_array': Parameter.Type.DOUBLE_ARRAY,
           'integer_array': Parameter.Type.INTEGER_ARRAY,
           'string_array': Parameter.Type.STRING_ARRAY, 'bool_array': Parameter.Type.BOOL_ARRAY}


@dataclass(frozen=True)
class ParameterEvent:
    """The changes one node made at one log time, to be set at once."""

    time_ns: int
    node: str
    changes: tuple[ParameterChange, ...]

    def messages(self) -> list[ParameterMsg]:
        """Return the changes as rcl_interfaces Parameters (an empty list typed by the schema)."""
        return [_message(change) for change in self.changes]


def parameter_events(changes: Iterable[ParameterChange]) -> list[ParameterEvent]:
    """Group changes (as parameter_changes lists them) per node and log time, in order."""
    events: list[ParameterEvent] = []
    for change in changes:
        if change.kind == 'deleted' or change.name.startswith(SKIPPED_PREFIX):
            continue
        last = events[-1] if events else None
        if last is not None and (last.time_ns, last.node) == (change.time_ns, change.node):
            events[-1] = ParameterEvent(last.time_ns, last.node, last.changes + (change,))
        else:
            events.append(ParameterEvent(change.time_ns, change.node, (change,)))
    return events


class ParameterSchedule:
    """Call apply(event) for every event due before a message of a given log time (once each)."""

    def __init__(self, events: Sequence[ParameterEvent],
                 apply: Callable[[ParameterEvent], None]) -> None:
        self._events = list(events)
        self._apply = apply
        self._next = 0

    def __call__(self, log_time_ns: int) -> None:
        while self._next < len(self._events) and self._events[self._next].time_ns <= log_time_ns:
            self._next += 1
            self._apply(self._events[self._next - 1])


def _message(change: ParameterChange) -> ParameterMsg:
    spec = SPECS.get(change.name)
    if change.new == [] and spec is not None and spec.type in _ARRAYS:
        return Parameter(change.name, _ARRAYS[spec.type], []).to_parameter_msg()
    return Parameter(change.name, value=change.new).to_parameter_msg()
