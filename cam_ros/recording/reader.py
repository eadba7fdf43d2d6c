"""Open, inspect and decode MCAP recordings, finished or cut short by a killed recorder."""

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
import os
from pathlib import Path
import struct
from types import MappingProxyType
from typing import Any, BinaryIO, NamedTuple, Optional, Union

from mcap.exceptions import EndOfFile, McapError
from mcap.opcode import Opcode
from mcap.reader import SeekingReader
from mcap.records import Attachment, Channel, Message, Metadata, Schema
from mcap.stream_reader import MAGIC_SIZE, StreamReader
from mcap.writer import MCAP0_MAGIC
from rclpy.serialization import deserialize_message

from cam_ros.core.errors import RecordingError
from cam_ros.recording.mcap_file import OUTPUTS_RECORD
from cam_ros.recording.qos import load_qos
from cam_ros.recording.schema import import_type

_RECORD_HEAD = struct.Struct('<BQ')  # opcode, record length
_FOOTER_SIZE = _RECORD_HEAD.size + 20  # summary start, summary offset start, summary CRC


@dataclass(frozen=True)
class TopicInfo:
    """One recorded topic: type, message count, offered QoS profiles (rosbag2 mappings), hash."""

    name: str
    type: str
    count: int
    serialization_format: str
    qos: tuple[Mapping[str, Any], ...]
    type_hash: str


class RecordedMessage(NamedTuple):
    """One message: topic, decoded message (or wire bytes), log and publish time in ns."""

    topic: str
    message: Any
    log_time_ns: int
    publish_time_ns: int


@dataclass(frozen=True)
class Recording:
    """
    What a recording holds; messages are read from the file on demand.

    `complete` is False for a file without summary (recorder killed or failed): its counts and
    times then come from the messages that survived.
    """

    path: Path
    complete: bool
    topics: Mapping[str, TopicInfo]
    message_count: int
    start_ns: int
    end_ns: int
    attachments: Mapping[str, str]
    metadata: Mapping[str, Mapping[str, str]]

    @property
    def duration_ns(self) -> int:
        """Return the time between first and last message, in ns."""
        return self.end_ns - self.start_ns

    @property
    def outputs(self) -> Optional[frozenset[str]]:
        """Return the recorded topics the recording node published itself (None: not said)."""
        record = self.metadata.get(OUTPUTS_RECORD)
        return None if record is None else frozenset(record.get('topics', '').split())

    def messages(self, topics: Optional[Iterable[str]] = None, *,
                 raw: bool = False) -> Iterator[RecordedMessage]:
        """
        Yield the messages of `topics` (default all) in log-time order.

        Messages are decoded into their generated classes, or left as wire bytes with `raw`.
        A file without summary is streamed in file order (its reception order).
        """
        wanted = None if topics is None else set(topics)
        classes: dict[str, type] = {}
        with open_file(self.path) as file:
            for schema, channel, message in _iter_messages(file, self.complete, wanted):
                if wanted is not None and channel.topic not in wanted:
                    continue
                data: Any = message.data
                if not raw:
                    name = schema.name if schema is not None else ''
                    if name not in classes:
                        classes[name] = import_type(name)
                    data = deserialize_message(data, classes[name])
                yield RecordedMessage(channel.topic, data, message.log_time, message.publish_time)


def open_recording(path: Union[str, os.PathLike]) -> Recording:
    """Return what the MCAP recording at `path` holds; RecordingError if it is unreadable."""
    path = Path(path)
    with open_file(path) as file:
        if file.read(MAGIC_SIZE) != MCAP0_MAGIC:
            raise RecordingError(f'{path} is not an MCAP file')
        finished = _has_footer(file)
        file.seek(0)
        reader = SeekingReader(file)
        summary = reader.get_summary() if finished else None
        if summary is not None and summary.statistics is not None:
            stats = summary.statistics
            return _recording(path, True, summary.schemas, summary.channels,
                              stats.channel_message_counts,
                              (stats.message_start_time, stats.message_end_time),
                              reader.iter_attachments(), reader.iter_metadata())
        schemas: dict[int, Schema] = {}
        channels: dict[int, Channel] = {}
        counts: dict[int, int] = {}
        attachments: list[Attachment] = []
        metadata: list[Metadata] = []
        start, end = 2**64, 0
        for record in surviving_records(file):
            if isinstance(record, Message):
                counts[record.channel_id] = counts.get(record.channel_id, 0) + 1
                start, end = min(start, record.log_time), max(end, record.log_time)
            elif isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                channels[record.id] = record
            elif isinstance(record, Attachment):
                attachments.append(record)
            elif isinstance(record, Metadata):
                metadata.append(record)
        return _recording(path, False, schemas, channels, counts, (start, end), attachments,
                          metadata)


def _has_footer(file: BinaryIO) -> bool:
    """Return whether a file ends with a footer record and the magic (a finished MCAP file)."""
    size = file.seek(0, os.SEEK_END)
    if size < 2 * MAGIC_SIZE + _FOOTER_SIZE:
        return False
    file.seek(-(_FOOTER_SIZE + MAGIC_SIZE), os.SEEK_END)
    tail = file.read()
    opcode, length = _RECORD_HEAD.unpack_from(tail)
    return (opcode, length) == (Opcode.FOOTER, _FOOTER_SIZE - _RECORD_HEAD.size) and \
        tail[-MAGIC_SIZE:] == MCAP0_MAGIC


def open_file(path: Path) -> BinaryIO:
    """Open a recording for reading, as a RecordingError when impossible."""
    try:
        return open(path, 'rb')
    except OSError as exc:
        raise RecordingError(f'cannot open recording {path}: {exc.strerror or exc}') from exc


def _recording(path: Path, complete: bool, schemas: Mapping[int, Schema],
               channels: Mapping[int, Channel], counts: Mapping[int, int],
               times: tuple[int, int], attachments: Iterable[Attachment],
               metadata: Iterable[Metadata]) -> Recording:
    """Assemble a Recording from the schema, channel, attachment and metadata records."""
    topics: dict[str, TopicInfo] = {}
    for channel in channels.values():
        schema = schemas.get(channel.schema_id)
        previous = topics.get(channel.topic)
        topics[channel.topic] = TopicInfo(
            name=channel.topic,
            type=schema.name if schema is not None else '',
            count=counts.get(channel.id, 0) + (previous.count if previous else 0),
            serialization_format=channel.message_encoding,
            qos=tuple(load_qos(channel.metadata.get('offered_qos_profiles', ''))),
            type_hash=channel.metadata.get('topic_type_hash', ''))
    start, end = times if sum(counts.values()) else (0, 0)
    return Recording(
        path=path, complete=complete, topics=MappingProxyType(topics),
        message_count=sum(counts.values()), start_ns=start, end_ns=end,
        attachments=MappingProxyType(
            {a.name: bytes(a.data).decode('utf-8', errors='replace') for a in attachments}),
        metadata=MappingProxyType({m.name: MappingProxyType(dict(m.metadata)) for m in metadata}))


def _iter_messages(file: BinaryIO, complete: bool, topics: Optional[set[str]]
                   ) -> Iterator[tuple[Optional[Schema], Channel, Message]]:
    """Yield (schema, channel, message): indexed for a finished file, streamed otherwise.

    With topics, a finished file's chunks holding none of them are not even read.
    """
    if complete:
        yield from SeekingReader(file).iter_messages(
            topics=None if topics is None else list(topics), log_time_order=True)
        return
    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    for record in surviving_records(file):
        if isinstance(record, Message):
            channel = channels[record.channel_id]
            yield schemas.get(channel.schema_id), channel, record
        elif isinstance(record, Schema):
            schemas[record.id] = record
        elif isinstance(record, Channel):
            channels[record.id] = record


class _Prefix:
    """Read-only view of the first `size` bytes of a file."""

    def __init__(self, file: BinaryIO, size: int):
        self._file = file
        self._left = size

    def read(self, size: int = -1) -> bytes:
        data = self._file.read(self._left if size < 0 else min(size, self._left))
        self._left -= len(data)
        return data


def complete_prefix(file: BinaryIO) -> int:
    """Return the size of a possibly truncated file up to the end of its last complete record."""
    size = file.seek(0, os.SEEK_END)
    offset = MAGIC_SIZE
    while True:
        file.seek(offset)
        head = file.read(_RECORD_HEAD.size)
        if len(head) < _RECORD_HEAD.size:
            return offset
        end = offset + _RECORD_HEAD.size + _RECORD_HEAD.unpack(head)[1]
        if end > size:
            return offset
        offset = end


def surviving_records(file: BinaryIO) -> Iterator[Any]:
    """Yield the records of a possibly truncated file, up to its last complete record."""
    offset = complete_prefix(file)
    file.seek(0)
    records = StreamReader(_Prefix(file, offset)).records  # type: ignore[arg-type]
    try:
        yield from records
    except EndOfFile:  # the stream ends at a record boundary of an unfinished file
        return
    except McapError as exc:
        raise RecordingError(f'{getattr(file, "name", "recording")} is damaged: {exc}') from exc
