"""Re-apply a recording's parameter changes at their places in a replayed stream.

Each recorded /parameter_events message of a node becomes one event (one atomic set on that
node), due before the first replayed message whose log time is not earlier than its own: the
order in which the recorded node saw them. An electronic cam takes a design at a master message,
which its ~/state names (at_master_messages), so its events are due before that message instead.
Deletions and recording.* are left out (a replay must not switch the fresh node's recording).
"""

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import NamedTuple, Optional

from rcl_interfaces.msg import Parameter as ParameterMsg
from rclpy.parameter import Parameter

from cam_ros.core.config.parameters import SPECS
from cam_ros.recording.parameters import ParameterChange
from cam_ros.recording.reader import Recording
from cam_ros.recording.schedule import master_stamps, next_master_message

#: Parameters a replay leaves alone.
SKIPPED_PREFIX = 'recording.'
#: Keys of an e-cam node's ~/state (diagnostic_msgs/DiagnosticStatus, hardware_id the node's
#: full name): its master topic, the design changes it has taken, and the stamp (ns) of the
#: last master message it commanded before the latest change ('none': no master message yet).
MASTER_TOPIC_KEY = 'master_topic'
DESIGN_CHANGES_KEY = 'design_changes'
CHANGED_AFTER_KEY = 'design_changed_after_master_stamp_ns'
_STATE_TYPE = 'diagnostic_msgs/msg/DiagnosticStatus'
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


class _Mark(NamedTuple):
    """What one recorded ~/state says of the node's design changes."""

    log_time_ns: int
    changes: int
    after_stamp_ns: Optional[int]
    master_topic: str


def at_master_messages(events: Sequence[ParameterEvent],
                       recording: Recording) -> list[ParameterEvent]:
    """
    Make each event of an e-cam node due before the first master message of its new design.

    rclpy logs /parameter_events before the node's post-set callback hands the design to the
    e-cam (10-20 ms later), so master messages logged in between were commanded with the old
    design. The node's next ~/state names the last master stamp before the change: the event
    moves to the next recorded master message. Events with no such state (no e-cam, an older
    recording, a change before any master message) keep their time; order is kept.
    """
    marks = _design_marks(recording)
    masters: dict[str, list[tuple[int, int]]] = {}  # topic: (log time, stamp) of its messages
    moved: list[ParameterEvent] = []
    for index, event in enumerate(events):
        later = next((e.time_ns for e in events[index + 1:] if e.node == event.node), None)
        mark = _mark_of(marks.get(event.node, []), event.time_ns, later)
        time_ns = event.time_ns
        if mark is not None and mark.after_stamp_ns is not None:
            if mark.master_topic not in masters:
                masters[mark.master_topic] = master_stamps(recording, mark.master_topic)
            time_ns = next_master_message(masters[mark.master_topic], mark.after_stamp_ns,
                                          time_ns)
        floor = moved[-1].time_ns if moved else time_ns
        moved.append(replace(event, time_ns=max(floor, time_ns)))
    return moved


def master_topics(recording: Recording) -> dict[str, str]:
    """Return {node: its master topic} of the e-cam nodes whose ~/state the recording holds."""
    return {node: marks[0].master_topic for node, marks in _design_marks(recording).items()}


def _design_marks(recording: Recording) -> dict[str, list[_Mark]]:
    """Return {node: its ~/state design marks in log order}."""
    topics = [name for name, info in recording.topics.items() if info.type == _STATE_TYPE]
    marks: dict[str, list[_Mark]] = {}
    for recorded in recording.messages(topics):
        values = {pair.key: pair.value for pair in recorded.message.values}
        try:
            after = values[CHANGED_AFTER_KEY]
            mark = _Mark(recorded.log_time_ns, int(values[DESIGN_CHANGES_KEY]),
                         None if after == 'none' else int(after), values[MASTER_TOPIC_KEY])
        except (KeyError, ValueError):  # another node's status, or an older recording
            continue
        marks.setdefault(recorded.message.hardware_id, []).append(mark)
    return marks


def _mark_of(marks: list[_Mark], time_ns: int, later: Optional[int]) -> Optional[_Mark]:
    """Return the first mark of a new design change logged from time_ns (and before later)."""
    seen = max((mark.changes for mark in marks if mark.log_time_ns < time_ns), default=-1)
    return next((mark for mark in marks if mark.log_time_ns >= time_ns and mark.changes > seen
                 and (later is None or mark.log_time_ns < later)), None)


def _message(change: ParameterChange) -> ParameterMsg:
    spec = SPECS.get(change.name)
    if change.new == [] and spec is not None and spec.type in _ARRAYS:
        return Parameter(change.name, _ARRAYS[spec.type], []).to_parameter_msg()
    return Parameter(change.name, value=change.new).to_parameter_msg()
