"""Record topics of a live ROS graph into a rosbag2-compatible MCAP file, as exact wire bytes."""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import os
from pathlib import Path
import threading
from typing import Any, Optional, Union

from rcl_interfaces.msg import ParameterEvent
from rclpy.clock import ROSClock
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, qos_profile_parameter_events, QoSProfile

from cam_ros.core.errors import InvalidParameter, RecordingError
from cam_ros.recording.intake import RawIntake, Taken
from cam_ros.recording.mcap_file import COMPRESSIONS, DEFAULT_CHUNK_SIZE, FileSpec
from cam_ros.recording.qos import dump_qos, qos_to_dict
from cam_ros.recording.schema import message_definition, type_hash, type_name
from cam_ros.recording.writer_process import WriterGone, WriterProcess

__all__ = ['DEFAULT_CHUNK_SIZE', 'DEFAULT_FLUSH_PERIOD', 'MIN_SUBSCRIPTION_DEPTH',
           'PARAMETER_EVENTS', 'Recorder', 'TopicSpec']

#: Seconds between forced chunk flushes, bounding the loss on slow topics too.
DEFAULT_FLUSH_PERIOD = 1.0
#: Seconds between checks that the writer process still runs when nothing is flushed.
CHECK_PERIOD = 1.0
#: Smallest queue depth of the recorder's own subscriptions: it holds what arrives between two
#: takes of the intake thread (every intake.POLL_PERIOD, but a full garbage collection of the
#: process stops it for tens of ms: 1000 messages at 20,000 msg/s) and bursts; a short queue
#: drops them. Memory is only taken as a backlog builds up.
MIN_SUBSCRIPTION_DEPTH = 2000


@dataclass(frozen=True)
class TopicSpec:
    """One topic to record: its name, generated message class and the QoS it is offered with."""

    name: str
    msg_type: type
    qos: QoSProfile


#: The node parameter change log, recorded like any other topic.
PARAMETER_EVENTS = TopicSpec('/parameter_events', ParameterEvent, qos_profile_parameter_events)
#: Topics every node publishes to: never counted as the recording node's outputs.
GRAPH_TOPICS = frozenset({PARAMETER_EVENTS.name, '/rosout'})


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


class Recorder:
    """
    Record topics into one MCAP file that rosbag2, Foxglove and rosbags can read.

    Raw subscriptions of the node (matching the offered QoS, so latched topics are received) are
    taken in batches by a thread of the recorder's own (RawIntake), never by the node's executor,
    which sends the exact wire bytes to a writer process (writer_process): MCAP serialisation,
    compression and file writes hold neither the node's GIL nor its disk waits. Log time is the
    time of reception (the DDS reception stamp; the node clock when it runs on simulated time),
    publish time the publisher's source timestamp. The recorded topics `node` publishes itself
    (but GRAPH_TOPICS) are named as its outputs (metadata record OUTPUTS_RECORD; a replay leaves
    them out). Chunks are written as they fill and at least every `flush_period` seconds, so a
    killed process loses at most the open chunk. A write error or a dead writer stops the
    recording (logged, `error` set), never the node. Use as a context manager or call close().
    """

    def __init__(self, node: Node, path: Union[str, os.PathLike], topics: Sequence[TopicSpec],
                 *, compression: str = 'zstd', chunk_size: int = DEFAULT_CHUNK_SIZE,
                 flush_period: Optional[float] = DEFAULT_FLUSH_PERIOD,
                 attachments: Optional[Mapping[str, str]] = None,
                 description: Optional[Mapping[str, str]] = None):
        """
        Create `path` (a new file; parents are created) and start recording `topics`.

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
        self._flushing = flush_period is not None
        self._lock = threading.Lock()
        self._error: Optional[RecordingError] = None
        self._clock = node.get_clock()
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
        own = {publisher.topic_name for publisher in node.publishers} - GRAPH_TOPICS
        file_spec = FileSpec(
            self.path.name, tuple(self._topics), tuple(dump_qos([spec.qos]) for spec in specs),
            schemas, compression, chunk_size, dict(attachments or {}), dict(description or {}),
            self._clock.now().nanoseconds,
            {'node': node.get_fully_qualified_name(),
             'topics': ' '.join(name for name in names if name in own)})
        self._writer: Optional[WriterProcess] = self._start_writer(file_spec)
        try:
            self._intake = RawIntake(
                node, [(name, spec.msg_type, _subscription_qos(spec.qos))
                       for name, spec in zip(names, specs)],
                self._write, every=(flush_period or CHECK_PERIOD, self._flush),
                name=f'recorder {self.path.name}')
        except BaseException:
            self._writer.kill()
            self._writer = None
            self.path.unlink(missing_ok=True)
            raise

    def _start_writer(self, spec: FileSpec) -> WriterProcess:
        """Create the file and start the writer process on it."""
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with open(self.path, 'xb') as file:
                try:
                    return WriterProcess(file, spec)
                except (OSError, WriterGone) as exc:
                    self.path.unlink(missing_ok=True)
                    why = exc.text if isinstance(exc, WriterGone) else exc.strerror or exc
                    raise RecordingError(f'cannot write recording {self.path}: {why}') from exc
        except OSError as exc:
            raise RecordingError(f'cannot create recording {self.path}: {exc.strerror or exc}'
                                 ) from exc

    def _write(self, index: int, batch: Sequence[Taken]) -> None:
        """Send a batch of messages of one topic to the writer (the intake's hand-over)."""
        now = self._clock.now().nanoseconds
        if self._ros_clock is not None and self._ros_clock.ros_time_is_active:
            log_times = [now] * len(batch)
        else:
            log_times = [info.get('received_timestamp') or now for _, info in batch]
        records = [(data, log_time, info.get('source_timestamp') or log_time,
                    (info.get('publication_sequence_number') or 0) & 0xFFFFFFFF)
                   for (data, info), log_time in zip(batch, log_times)]
        with self._lock:
            if self._writer is None:
                return
            self._counts[index] += len(records)
            try:
                self._writer.write(index, records)
            except WriterGone as gone:
                self._fail(gone.text)

    def _flush(self) -> None:
        """Have the open chunk written (every flush_period); notice a writer that stopped."""
        with self._lock:
            if self._writer is not None:
                try:
                    self._writer.flush() if self._flushing else self._writer.check()
                except WriterGone as gone:
                    self._fail(gone.text)

    def _fail(self, why: str) -> None:
        """Stop recording after the writer stopped: keep the error, log it, release (lock held)."""
        self._error = RecordingError(f'recording {self.path} stopped: {why}')
        self._node.get_logger().error(str(self._error))
        self._writer = None
        self._intake.stop()

    def close(self) -> None:
        """Write what was received, then the summary (safe to call twice; errors in `error`)."""
        self._intake.stop()
        with self._lock:
            writer, self._writer = self._writer, None
            if writer is None:
                return
            try:
                writer.close()
            except WriterGone as gone:
                self._writer = writer
                self._fail(gone.text)

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
    def writer_pid(self) -> Optional[int]:
        """Return the process id of the writer process while it records (else None)."""
        writer = self._writer
        return None if writer is None else writer.pid

    @property
    def topics(self) -> tuple[str, ...]:
        """Return the fully qualified names of the recorded topics."""
        return tuple(topic['name'] for topic in self._topics)

    @property
    def message_count(self) -> int:
        """Return the number of messages handed to the writer (the open chunk included)."""
        return sum(self._counts)
