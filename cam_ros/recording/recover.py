"""Rewrite a recording cut short (recorder killed) into a finished file every reader opens."""

from collections.abc import Mapping
from dataclasses import dataclass
import math
import os
from pathlib import Path
import tempfile
from typing import Any, BinaryIO, Union

from mcap.records import Attachment, Channel, Header, Message, Metadata, Schema
from mcap.stream_reader import MAGIC_SIZE
from mcap.writer import MCAP0_MAGIC, Writer

from cam_ros.core.errors import InvalidParameter, RecordingError
from cam_ros.recording.qos import load_qos
from cam_ros.recording.reader import complete_prefix, open_file, surviving_records
from cam_ros.recording.mcap_file import bag_metadata, DEFAULT_CHUNK_SIZE, LIBRARY, PROFILE


@dataclass(frozen=True)
class Recovery:
    """What recover() wrote: messages and topics kept, bytes of the unfinished tail dropped."""

    output: Path
    message_count: int
    topic_count: int
    dropped_bytes: int


def recover(path: Union[str, os.PathLike], output: Union[str, os.PathLike]) -> Recovery:
    """
    Copy every complete record of the recording at `path` into a new, finished MCAP file.

    Schemas, channels (with their QoS and type-hash metadata), messages, attachments and
    metadata are kept; the rosbag2 metadata is rewritten with the recovered counts and times and
    the file gets its summary and footer, which `rosbags` and `ros2 bag` need. `output` must be
    a new file, or `path` itself: then the input is replaced once the new file is complete.
    """
    source, target = Path(path), Path(output)
    if target.resolve() != source.resolve() and target.exists():
        raise InvalidParameter('-o', str(target), 'exists already (choose a new file)')
    with open_file(source) as file:
        if file.read(MAGIC_SIZE) != MCAP0_MAGIC:
            raise RecordingError(f'{source} is not an MCAP file')
        file.seek(complete_prefix(file))
        tail = file.read()
        dropped = 0 if tail == MCAP0_MAGIC else len(tail)  # a finished file ends in the magic
        folder = target.resolve().parent
        try:
            handle, temporary = tempfile.mkstemp(suffix='.mcap', prefix='.recover-', dir=folder)
        except OSError as exc:
            raise InvalidParameter('-o', str(target),
                                   f'cannot be written ({exc.strerror or exc})') from exc
        try:
            with os.fdopen(handle, 'wb') as out:
                messages, topics = _copy(file, out, target.name)
            os.replace(temporary, target)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
    return Recovery(target, messages, topics, dropped)


def _copy(file: BinaryIO, out: BinaryIO, name: str) -> tuple[int, int]:
    """Write the surviving records of `file` to `out` as a finished file; return counts."""
    writer = Writer(out, chunk_size=DEFAULT_CHUNK_SIZE)
    schemas: dict[int, tuple[int, str]] = {}  # file's schema id: (new id, type name)
    channels: dict[int, int] = {}
    topics: dict[int, dict[str, Any]] = {}
    counts: dict[int, int] = {}
    start, end = math.inf, -math.inf  # log times of the first and last surviving message
    description: Mapping[str, str] = {}
    started = False
    for record in surviving_records(file):
        if isinstance(record, Header):
            writer.start(profile=record.profile or PROFILE, library=LIBRARY)
            started = True
        elif not started:
            raise RecordingError(f'{name}: no MCAP header record')
        elif isinstance(record, Schema):
            schemas[record.id] = (writer.register_schema(record.name, record.encoding,
                                                         record.data), record.name)
        elif isinstance(record, Channel) and record.id not in channels:
            schema_id, type_name = schemas.get(record.schema_id, (0, ''))
            channels[record.id] = writer.register_channel(
                record.topic, record.message_encoding, schema_id, dict(record.metadata))
            topics[record.id] = _topic_metadata(record, type_name)
            counts[record.id] = 0
        elif isinstance(record, Message) and record.channel_id in channels:
            writer.add_message(channels[record.channel_id], log_time=record.log_time,
                               data=record.data, publish_time=record.publish_time,
                               sequence=record.sequence)
            counts[record.channel_id] += 1
            start, end = min(start, record.log_time), max(end, record.log_time)
        elif isinstance(record, Attachment):
            writer.add_attachment(record.create_time, record.log_time, record.name,
                                  record.media_type, record.data)
        elif isinstance(record, Metadata) and record.name != 'rosbag2':
            writer.add_metadata(record.name, record.metadata)
            if record.name == 'cam_ros':
                description = record.metadata
    if not started:
        raise RecordingError(f'{name}: no MCAP header record')
    if start > end:  # no message survived
        start = end = 0
    writer.add_metadata('rosbag2', {'serialized_metadata': bag_metadata(
        name, list(topics.values()), list(counts.values()), int(start), int(end - start),
        description)})
    writer.finish()
    return sum(counts.values()), len(topics)


def _topic_metadata(channel: Channel, type_name: str) -> dict[str, Any]:
    """Return the rosbag2 topic_metadata of a channel the cam_ros recorder wrote."""
    return {'name': channel.topic, 'type': type_name,
            'serialization_format': channel.message_encoding,
            'offered_qos_profiles': load_qos(channel.metadata.get('offered_qos_profiles', '')),
            'type_description_hash': channel.metadata.get('topic_type_hash', '')}
