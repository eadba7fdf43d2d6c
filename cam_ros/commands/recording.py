"""Recording commands: summarise, recover and replay MCAP recordings."""
from __future__ import annotations

import signal
import threading
import time
from pathlib import Path
from typing import Any, Sequence, TYPE_CHECKING

from cam_ros.commands.common import dump_json, end_progress, progress, say, writing
from cam_ros.core import InvalidParameter
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK
from cam_ros.commands.ros import DEFAULT_TIMEOUT_S, request_once, ros_node

if TYPE_CHECKING:
    from cam_ros.recording import Recording
    from cam_ros.recording.engage_replay import EngageCall
    from cam_ros.recording.parameter_replay import ParameterEvent

#: Seconds replay waits by default for every topic to have a subscriber (fresh ones need time
#: to discover the replaying node).
DEFAULT_WAIT_S = 3.0


def info(path: str, json_output: bool = False) -> int:
    """Print what a recording holds, laid out like `ros2 bag info` (or as JSON)."""
    from cam_ros.recording import format_info, info as recording_info

    data = recording_info(path)
    print(dump_json(data) if json_output else format_info(data))
    return EXIT_OK


class _Rejected(Exception):
    """A node did not take a recorded parameter change (the message says why)."""


def replay(path: str, rate: float = 1.0, topics: Sequence[str] | None = None,
           loop: bool = False, wait: float = DEFAULT_WAIT_S,
           apply_parameters: bool = False, outputs: bool = False) -> int:
    """
    Publish a recording back with its recorded QoS and timing; Ctrl-C stops it.

    Without --topics: the recording node's inputs (its outputs too with --outputs), and its
    ~/engage calls made again at their master messages; what is left out is said on stderr.
    """
    from cam_ros.recording import open_recording, parameter_changes, replay as replay_recording
    from cam_ros.recording.engage_replay import EngageCall, engage_calls, engage_topics
    from cam_ros.recording.parameter_replay import at_master_messages, parameter_events
    from cam_ros.recording.replay import default_topics
    from cam_ros.recording.schedule import Schedule

    if apply_parameters and loop:
        raise InvalidParameter('--apply-parameters', True, 'cannot go with --loop: the '
                               'changes are made once, in recorded order')
    if outputs and topics is not None:
        raise InvalidParameter('--outputs', True, 'cannot go with --topics, which names '
                               'exactly the topics to publish')
    recording = open_recording(path)
    calling = engage_topics(recording)
    if topics is None:
        published = default_topics(recording, outputs)
    else:
        published = [name for name in topics if name not in calling]
        calling = [name for name in calling if name in topics]
    calls = engage_calls(recording, calling)
    events = parameter_events(parameter_changes(recording))
    _say_plan(recording, published, calls, len(events), topics is not None, apply_parameters)
    total = sum(recording.topics[name].count for name in published if name in recording.topics)
    shown = 0

    def show(message: object) -> None:
        nonlocal shown
        shown += 1
        progress('replay', f'{shown} of {total} messages' + (' (looping)' if loop else ''))

    stop = threading.Event()
    with ros_node('replay') as (node, executor):
        def apply(item: ParameterEvent | EngageCall) -> None:
            if isinstance(item, EngageCall):
                _call_engage(node, executor, item)
            else:
                _set_atomically(node, executor, item)

        due = at_master_messages(events, recording) if apply_parameters else []
        schedule = Schedule(sorted([*due, *calls], key=lambda item: item.time_ns), apply)
        # Ctrl-C sets stop: a KeyboardInterrupt inside publish() could leave its handle held.
        previous = signal.signal(signal.SIGINT, lambda signum, frame: stop.set())
        try:
            count = replay_recording(recording, node, rate=rate, topics=published, loop=loop,
                                     on_message=show, wait_for_subscribers=wait, stop=stop,
                                     before_message=schedule)
            if not (loop or stop.is_set()):
                schedule.finish()
        except _Rejected as err:
            end_progress()
            say('replay', str(err))
            return EXIT_FAILED
        finally:
            signal.signal(signal.SIGINT, previous)
            end_progress()
    print(f'published {count} messages from {path}')
    return EXIT_OK


def _say_plan(recording: Recording, published: Sequence[str], calls: Sequence[EngageCall],
              changes: int, chosen: bool, apply_parameters: bool) -> None:
    """
    Say on stderr what the replay publishes, calls and leaves out (nothing when it is all).

    chosen: the topics were named (--topics), so what is left out goes without saying.
    """
    from cam_ros.recording.engage_replay import engage_topics
    from cam_ros.recording.mcap_file import OUTPUTS_RECORD

    called = engage_topics(recording)
    left = [name for name, info in recording.topics.items()
            if info.count and not chosen and name not in published and name not in called]
    lines = []
    if calls:
        services = ', '.join(sorted({call.service for call in calls}))
        lines.append(f'calling {services} as recorded ({len(calls)} '
                     f'call{"s" * (len(calls) != 1)}), each before the master message the '
                     'recorded node took it at')
    if left:
        node = recording.metadata.get(OUTPUTS_RECORD, {}).get('node', 'the recording node')
        lines.append(f'leaving out {", ".join(left)} (the outputs of {node} and its parameter '
                     'events: --outputs publishes them)')
    if changes and not apply_parameters:
        lines.append(f'not setting the recorded parameter changes ({changes} '
                     f'set{"s" * (changes != 1)}; --apply-parameters makes them)')
    if lines:
        say('replay', 'publishing ' + (', '.join(
            f'{name} ({recording.topics[name].count})' for name in published) or 'nothing'))
    for line in lines:
        say('replay', line)


def _set_atomically(node: Any, executor: Any, event: ParameterEvent) -> None:
    """Set one recorded event's changes on its node in one call; raise _Rejected if not."""
    from rcl_interfaces.srv import SetParametersAtomically

    request = SetParametersAtomically.Request(parameters=event.messages())
    deadline = time.monotonic() + DEFAULT_TIMEOUT_S
    response, problem = request_once(node, executor, SetParametersAtomically,
                                     f'{event.node}/set_parameters_atomically', request,
                                     deadline, DEFAULT_TIMEOUT_S)
    names = ', '.join(change.name for change in event.changes)
    if response is None:
        raise _Rejected(f'recorded change of {names} at log time {event.time_ns} ns: {problem}')
    if not response.result.successful:
        raise _Rejected(f'{event.node} rejected the recorded change of {names} at log time '
                        f'{event.time_ns} ns: {response.result.reason}')


def _call_engage(node: Any, executor: Any, call: EngageCall) -> None:
    """Make one recorded ~/engage call; raise _Rejected unless answered as recorded."""
    from std_srvs.srv import SetBool

    response, problem = request_once(node, executor, SetBool, call.service,
                                     SetBool.Request(data=call.engage),
                                     time.monotonic() + DEFAULT_TIMEOUT_S, DEFAULT_TIMEOUT_S)
    if response is None:
        raise _Rejected(f'recorded call {call.service} {str(call.engage).lower()}: {problem}')
    if response.success != call.success:
        raise _Rejected(f'{call.service} {str(call.engage).lower()} answered '
                        f'{response.success} ({response.message}); the recorded node answered '
                        f'{call.success} ({call.message})')


def recover(path: str, output: str | None = None, in_place: bool = False) -> int:
    """Rewrite a recording cut short by a killed recorder into a finished file."""
    from cam_ros.recording import recover as rewrite

    source = Path(path)
    target = source if in_place else Path(output or source.with_suffix('.recovered.mcap'))
    with writing('recover', f'recovering {source}', target):
        result = rewrite(source, target)
    print(f'recovered {result.message_count} messages on {result.topic_count} topics into '
          f'{result.output} ({result.dropped_bytes} bytes of unfinished records dropped)')
    return EXIT_OK
