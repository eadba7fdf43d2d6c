"""Recording commands: summarise, recover and replay MCAP recordings."""
from __future__ import annotations

import signal
import threading
from pathlib import Path
from typing import Sequence

from cam_ros.commands.common import dump_json, end_progress, progress, writing
from cam_ros.exit_codes import EXIT_OK
from cam_ros.commands.ros import ros_node

#: Seconds replay waits by default for every topic to have a subscriber (fresh ones need time
#: to discover the replaying node).
DEFAULT_WAIT_S = 3.0


def info(path: str, json_output: bool = False) -> int:
    """Print what a recording holds, laid out like `ros2 bag info` (or as JSON)."""
    from cam_ros.recording import format_info, info as recording_info

    data = recording_info(path)
    print(dump_json(data) if json_output else format_info(data))
    return EXIT_OK


def replay(path: str, rate: float = 1.0, topics: Sequence[str] | None = None,
           loop: bool = False, wait: float = DEFAULT_WAIT_S) -> int:
    """Publish a recording back with its recorded QoS and timing; Ctrl-C stops it."""
    from cam_ros.recording import open_recording, replay as replay_recording

    recording = open_recording(path)
    total = sum(recording.topics[name].count for name in topics or recording.topics
                if name in recording.topics)
    published = 0

    def show(message: object) -> None:
        nonlocal published
        published += 1
        progress('replay', f'{published} of {total} messages' + (' (looping)' if loop else ''))

    stop = threading.Event()
    with ros_node('replay') as (node, _):
        # Ctrl-C sets stop: a KeyboardInterrupt inside publish() could leave its handle held.
        previous = signal.signal(signal.SIGINT, lambda signum, frame: stop.set())
        try:
            count = replay_recording(recording, node, rate=rate, topics=topics, loop=loop,
                                     on_message=show, wait_for_subscribers=wait, stop=stop)
        finally:
            signal.signal(signal.SIGINT, previous)
            end_progress()
    print(f'published {count} messages from {path}')
    return EXIT_OK


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
