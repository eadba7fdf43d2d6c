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
           apply_parameters: bool = False) -> int:
    """Publish a recording back with its recorded QoS and timing; Ctrl-C stops it."""
    from cam_ros.recording import open_recording, parameter_changes, replay as replay_recording
    from cam_ros.recording.parameter_replay import (at_master_messages, parameter_events,
                                                    ParameterSchedule)
    from cam_ros.recording.parameters import PARAMETER_EVENTS_TOPIC

    if apply_parameters and loop:
        raise InvalidParameter('--apply-parameters', True, 'cannot go with --loop: the '
                               'changes are made once, in recorded order')
    recording = open_recording(path)
    if apply_parameters and topics is None:  # the node says its own changes
        topics = [name for name in recording.topics if name != PARAMETER_EVENTS_TOPIC]
    total = sum(recording.topics[name].count for name in topics or recording.topics
                if name in recording.topics)
    published = 0

    def show(message: object) -> None:
        nonlocal published
        published += 1
        progress('replay', f'{published} of {total} messages' + (' (looping)' if loop else ''))

    stop = threading.Event()
    with ros_node('replay') as (node, executor):
        schedule = None
        if apply_parameters:
            def apply(event: ParameterEvent) -> None:
                _set_atomically(node, executor, event)
            events = parameter_events(parameter_changes(recording))
            schedule = ParameterSchedule(at_master_messages(events, recording), apply)
        # Ctrl-C sets stop: a KeyboardInterrupt inside publish() could leave its handle held.
        previous = signal.signal(signal.SIGINT, lambda signum, frame: stop.set())
        try:
            count = replay_recording(recording, node, rate=rate, topics=topics, loop=loop,
                                     on_message=show, wait_for_subscribers=wait, stop=stop,
                                     before_message=schedule)
        except _Rejected as err:
            end_progress()
            say('replay', str(err))
            return EXIT_FAILED
        finally:
            signal.signal(signal.SIGINT, previous)
            end_progress()
    print(f'published {count} messages from {path}')
    return EXIT_OK


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
