"""Record topics of a live ROS graph into a rosbag2-compatible MCAP file, as exact wire bytes."""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import os
from pathlib import Path
import threading
import time
from typing import Any, BinaryIO, cast, IO, Optional, Union

from mcap.writer import CompressionType, LIBRARY_IDENTIFIER, Writer
from rcl_interfaces.msg import ParameterEvent
from rclpy.clock import ROSClock
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, qos_profile_parameter_events, QoSProfile
import yaml

from cam_ros.core.errors import InvalidParameter, RecordingError
from cam_ros.recording.intake import RawIntake, Taken
from cam_ros.recording.qos import dump_qos, qos_to_dict
from cam_ros.recording.schema import message_definition, type_hash, type_name

COMPRESSIONS = {
    'zstd': CompressionType.ZSTD,
    'lz4': CompressionType.LZ4,
    'none': CompressionType.NONE,
}
#: Chunk size in bytes (uncompressed): the most a killed recorder loses.
DEFAULT_CHUNK_SIZE = 64 * 1024
#: Seconds between forced chunk flushes, bounding the loss on slow topics too.
DEFAULT_FLUSH_PERIOD = 1.0
#: Smallest queue depth of the recorder's own subscriptions: it holds what arrives between two
#: takes of the intake thread (every intake.POLL_PERIOD, but a full garbage collection of the
#: process stops it for tens of ms: 1000 messages at 20,000 msg/s) and bursts; a short queue
#: drops them. Memory is only taken as a backlog builds up.
MIN_SUBSCRIPTION_DEPTH = 2000
#: Version of the rosbag2 bag metadata written (Jazzy).
METADATA_VERSION = 9
PROFILE = 'ros2'
LIBRARY = f'cam_ros recorder; {LIBRARY_IDENTIFIER}'
#: Attachment media types by file suffix; anything else is text/plain.
MEDIA_TYPES = {'.yaml': 'application/yaml', '.yml': 'application/yaml',
               '.json': 'application/json'}


@dataclass(frozen=True)
class TopicSpec:
    """One topic to record: its name, generated message class and the QoS it is offered with."""

    name: str
    msg_type: type
    qos: QoSProfile


#: The node parameter change log, recorded like any other topic.
PARAMETER_EVENTS = TopicSpec('/parameter_events', ParameterEvent, qos_profile_parameter_events)


class _FlushingFile:
    """A binary file whose every write reaches the operating system at once."""

    def __init__(self, file: BinaryIO):
        self._file = file

    def write(self, data: bytes) -> int:
        count = self._file.write(data)
        self._file.flush()
        return count

    def tell(self) -> int:
        return self._file.tell()

    def flush(self) -> None:
        self._file.flush()


def _validated_topics(topics: Sequence[TopicSpec]) -> tuple[TopicSpec, ...]:
    """Return the topics as a tuple, rejecting an empty list and duplicate names."""
    specs = tuple(topics)
    if not specs:
        raise InvalidParameter('topics', specs, 'must name at least one topic')
    names = [spec.name for spec in specs]
    for index, name in enumerate(names):
        if name in names[:index]:
            raise InvalidParameter(f'topics[{index}].name', name, 'must be unique')
    return specs


def _subscription_qos(offered: QoSProfile) -> QoSProfile:
    """Return the offered profile with a queue deep enough not to drop bursts."""
    depth = offered.depth
    if offered.history is not HistoryPolicy.KEEP_ALL:
        depth = max(depth, MIN_SUBSCRIPTION_DEPTH)
    return QoSProfile(
        history=offered.history, depth=depth, reliability=offered.reliability,
        durability=offered.durability, deadline=offered.deadline, lifespan=offered.lifespan,
        liveliness=offered.liveliness,
        liveliness_lease_duration=offered.liveliness_lease_duration,
        avoid_ros_namespace_conventions=offered.avoid_ros_namespace_conventions)


def bag_metadata(file_name: str, topics: Sequence[Mapping[str, Any]], counts: Sequence[int],
                 start_ns: int, duration_ns: int,
                 custom_data: Optional[Mapping[str, str]] = None) -> str:
    """
    Return rosbag2 bag metadata (version 9) as the YAML text of record 'rosbag2'.

    `topics` are rosbag2 topic_metadata mappings, `counts` their message counts.
    """
    total = sum(counts)
    files = [{'path': file_name, 'starting_time': {'nanoseconds_since_epoch': start_ns},
              'duration': {'nanoseconds': duration_ns}, 'message_count': total}]
    metadata = {
        'version': METADATA_VERSION,
        'storage_identifier': 'mcap',
        'duration': {'nanoseconds': duration_ns},
        'starting_time': {'nanoseconds_since_epoch': start_ns},
        'message_count': total,
        'topics_with_message_count': [
            {'topic_metadata': dict(topic), 'message_count': count}
            for topic, count in zip(topics, counts)],
        'compression_format': '',
        'compression_mode': '',
        'relative_file_paths': [file_name],
        'files': files,
        'custom_data': dict(custom_data) if custom_data else None,
        'ros_distro': os.environ.get('ROS_DISTRO', 'jazzy'),
    }
    return yaml.safe_dump(metadata, sort_keys=False, default_flow_style=False)


class Recorder:
    """
    Record topics into one MCAP file that rosbag2, Foxglove and rosbags can read.

    Raw subscriptions of the node (matching the offered QoS, so latched topics are received)
    hand the exact wire bytes to an mcap Writer, in batches taken by a thread of the recorder's
    own (RawIntake), never by the node's executor. Log time is the time of reception (the DDS
    reception stamp; the node clock when it runs on simulated time), publish time the publisher's
    source timestamp. Chunks are written and flushed as they fill and at least every
    `flush_period` seconds, so a killed process loses at most the open chunk. A write error stops
    the recording (logged, `error` set), never the node. Use as a context manager or call close().
    """

    def __init__(self, node: Node, path: Union[str, os.PathLike], topics: Sequence[TopicSpec],
                 *, compression: str = 'zstd', chunk_size: int = DEFAULT_CHUNK_SIZE,
                 flush_period: Optional[float] = DEFAULT_FLUSH_PERIOD,
                 attachments: Optional[Mapping[str, str]] = None,
                 description: Optional[Mapping[str, str]] = None):
        """
        Open `path` (a new file; parents are created) and start recording `topics`.

        `attachments` are text files stored in the recording (e.g. 'cam_config.yaml'),
        `description` key/value text stored as metadata record 'cam_ros' and as rosbag2
        custom_data. Raises InvalidParameter for bad options, RecordingError when the file cannot
        be created or a message definition is not installed.
        """
        specs = _validated_topics(topics)
        if compression not in COMPRESSIONS:
            raise InvalidParameter('compression', compression,
                                   f'must be one of {list(COMPRESSIONS)}')
        if chunk_size <= 0:
            raise InvalidParameter('chunk_size', chunk_size, 'must be a positive number of bytes')
        if flush_period is not None and not flush_period > 0:
            raise InvalidParameter('flush_period', flush_period,
                                   'must be positive seconds or None')
        self.path = Path(path)
        self._node = node
        self._description = dict(description or {})
        self._lock = threading.Lock()
        self._error: Optional[RecordingError] = None
        self._clock = node.get_clock()
        self._opened_ns = self._clock.now().nanoseconds
        self._first_ns: Optional[int] = None
        self._last_ns: Optional[int] = None
        self._ros_clock = self._clock if isinstance(self._clock, ROSClock) else None
        names = [node.resolve_topic_name(spec.name) for spec in specs]
        types = [type_name(spec.msg_type) for spec in specs]
        schemas = {name: message_definition(name) for name in dict.fromkeys(types)}
        self._topics: list[dict[str, Any]] = [
            {'name': name, 'type': type_, 'serialization_format': 'cdr',
             'offered_qos_profiles': [qos_to_dict(spec.qos)],
             'type_description_hash': type_hash(type_)}
            for name, type_, spec in zip(names, types, specs)]
        self._counts = [0] * len(specs)
        self._file, writer, self._channels = self._open(specs, schemas, compression, chunk_size,
                                                        dict(attachments or {}))
        self._writer: Optional[Writer] = writer
        try:
            self._intake = RawIntake(
                node, [(name, spec.msg_type, _subscription_qos(spec.qos))
                       for name, spec in zip(names, specs)],
                self._write, every=None if flush_period is None else (flush_period, self._flush),
                name=f'recorder {self.path.name}')
        except BaseException:
            self._writer = None
            _close_quietly(self._file)
            self.path.unlink(missing_ok=True)
            raise

    def _open(self, specs: Sequence[TopicSpec], schemas: Mapping[str, str], compression: str,
              chunk_size: int, attachments: Mapping[str, str]
              ) -> tuple[BinaryIO, Writer, list[int]]:
        """Create the file; write header, attachments, metadata, schemas, channels (their ids)."""
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            file = open(self.path, 'xb')
        except OSError as exc:
            raise RecordingError(f'cannot create recording {self.path}: {exc.strerror or exc}'
                                 ) from exc
        try:
            writer = Writer(cast(IO[bytes], _FlushingFile(file)), chunk_size=chunk_size,
                            compression=COMPRESSIONS[compression])
            writer.start(profile=PROFILE, library=LIBRARY)
            now = time.time_ns()
            for name, text in attachments.items():
                media_type = MEDIA_TYPES.get(Path(name).suffix.lower(), 'text/plain')
                writer.add_attachment(now, now, name, media_type, text.encode('utf-8'))
            if self._description:
                writer.add_metadata('cam_ros', self._description)
            writer.add_metadata('rosbag2', {'serialized_metadata': self._bag_metadata()})
            schema_ids = {name: writer.register_schema(name, 'ros2msg', text.encode('utf-8'))
                          for name, text in schemas.items()}
            channels = [
                writer.register_channel(
                    topic['name'], 'cdr', schema_ids[topic['type']],
                    {'offered_qos_profiles': dump_qos([spec.qos]),
                     'topic_type_hash': topic['type_description_hash']})
                for topic, spec in zip(self._topics, specs)]
        except OSError as exc:
            _close_quietly(file)
            self.path.unlink(missing_ok=True)
            raise RecordingError(f'cannot write recording {self.path}: {exc.strerror or exc}'
                                 ) from exc
        return file, writer, channels

    def _bag_metadata(self) -> str:
        """Return the rosbag2 metadata text for the messages written so far."""
        start = self._opened_ns if self._first_ns is None else self._first_ns
        end = start if self._last_ns is None else self._last_ns
        return bag_metadata(self.path.name, self._topics, self._counts, start, end - start,
                            self._description)

    def _write(self, index: int, batch: Sequence[Taken]) -> None:
        """Write a batch of messages received on one topic (the intake's hand-over)."""
        now = self._clock.now().nanoseconds
        if self._ros_clock is not None and self._ros_clock.ros_time_is_active:
            log_times = [now] * len(batch)
        else:
            log_times = [info.get('received_timestamp') or now for _, info in batch]
        channel = self._channels[index]
        with self._lock:
            if self._writer is None:
                return
            add_message, accepted = self._writer.add_message, 0
            try:
                for (data, info), log_time in zip(batch, log_times):
                    accepted += 1
                    add_message(
                        channel, log_time=log_time, data=data,
                        publish_time=info.get('source_timestamp') or log_time,
                        sequence=(info.get('publication_sequence_number') or 0) & 0xFFFFFFFF)
            except OSError as exc:
                self._fail(exc)
            if accepted:
                self._counts[index] += accepted
                first, last = min(log_times[:accepted]), max(log_times[:accepted])
                self._first_ns = first if self._first_ns is None else min(self._first_ns, first)
                self._last_ns = last if self._last_ns is None else max(self._last_ns, last)

    def _flush(self) -> None:
        """Write out the open chunk (every flush_period)."""
        with self._lock:
            if self._writer is not None:
                try:
                    self._writer.flush()
                except OSError as exc:
                    self._fail(exc)

    def _fail(self, exc: OSError) -> None:
        """Stop recording after a write error: keep the error, log it, release everything."""
        self._error = RecordingError(f'recording {self.path} stopped: {exc.strerror or exc}')
        self._error.__cause__ = exc
        self._node.get_logger().error(str(self._error))
        self._release()

    def _release(self) -> None:
        """Stop the intake (which destroys the subscriptions) and close the file (lock held)."""
        self._writer = None
        self._intake.stop()
        _close_quietly(self._file)

    def close(self) -> None:
        """Write what was received, then the summary (safe to call twice; errors in `error`)."""
        self._intake.stop()
        with self._lock:
            writer = self._writer
            if writer is None:
                return
            try:
                writer.add_metadata('rosbag2', {'serialized_metadata': self._bag_metadata()})
                writer.finish()
            except OSError as exc:
                self._fail(exc)
            else:
                self._release()

    def __enter__(self) -> 'Recorder':
        """Return the recorder itself."""
        return self

    def __exit__(self, *exc_info: object) -> None:
        """Close the recorder."""
        self.close()

    @property
    def error(self) -> Optional[RecordingError]:
        """Return the error that stopped the recording, or None."""
        return self._error

    @property
    def failed(self) -> bool:
        """Return whether a write error stopped the recording."""
        return self._error is not None

    @property
    def closed(self) -> bool:
        """Return whether the recorder no longer records (closed or failed)."""
        return self._writer is None

    @property
    def topics(self) -> tuple[str, ...]:
        """Return the fully qualified names of the recorded topics."""
        return tuple(topic['name'] for topic in self._topics)

    @property
    def message_count(self) -> int:
        """Return the number of messages accepted for writing (the open chunk included)."""
        return sum(self._counts)


def _close_quietly(file: BinaryIO) -> None:
    """Close a file whose pending data may not be writable any more."""
    try:
        file.close()
    except OSError:
        pass
