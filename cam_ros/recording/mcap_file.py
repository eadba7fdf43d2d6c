"""The MCAP file of a recording as rosbag2 writes it; no ROS import (for the writer process)."""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
import os
from pathlib import Path
import time
from typing import Any, BinaryIO, cast, IO, Optional

from mcap.writer import CompressionType, LIBRARY_IDENTIFIER, Writer
import yaml

COMPRESSIONS = {
    'zstd': CompressionType.ZSTD,
    'lz4': CompressionType.LZ4,
    'none': CompressionType.NONE,
}
#: Chunk size in bytes (uncompressed): the most a killed recorder loses.
DEFAULT_CHUNK_SIZE = 64 * 1024
#: Version of the rosbag2 bag metadata written (Jazzy).
METADATA_VERSION = 9
PROFILE = 'ros2'
#: Metadata record naming the recording node ('node') and the recorded topics it publishes
#: itself ('topics', space-separated): its outputs, which a replay leaves out unless asked.
OUTPUTS_RECORD = 'cam_ros_outputs'
LIBRARY = f'cam_ros recorder; {LIBRARY_IDENTIFIER}'
#: Attachment media types by file suffix; anything else is text/plain.
MEDIA_TYPES = {'.yaml': 'application/yaml', '.yml': 'application/yaml',
               '.json': 'application/json'}
#: One message to write: wire bytes, log time, publish time (ns), sequence number.
Record = tuple[bytes, int, int, int]


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


@dataclass(frozen=True)
class FileSpec:
    """Everything a recording's file holds besides its messages (picklable, no ROS types).

    `topics` are rosbag2 topic_metadata mappings, `channel_qos` each topic's
    'offered_qos_profiles' channel metadata text, `schemas` the ros2msg text of each type,
    `outputs` the OUTPUTS_RECORD (empty: none written).
    """

    name: str
    topics: tuple[Mapping[str, Any], ...]
    channel_qos: tuple[str, ...]
    schemas: Mapping[str, str]
    compression: str
    chunk_size: int
    attachments: Mapping[str, str]
    description: Mapping[str, str]
    opened_ns: int
    outputs: Mapping[str, str] = field(default_factory=dict)


class McapFile:
    """Write one recording: header, attachments, metadata, schemas and channels, then messages.

    OSError from any call means the file cannot be written any more.
    """

    def __init__(self, file: BinaryIO, spec: FileSpec):
        """Write everything but the messages to `file` (a new, empty binary file)."""
        self._file, self._spec = file, spec
        self.counts = [0] * len(spec.topics)
        self._first_ns: Optional[int] = None
        self._last_ns: Optional[int] = None
        self._writer = writer = Writer(cast(IO[bytes], _FlushingFile(file)),
                                       chunk_size=spec.chunk_size,
                                       compression=COMPRESSIONS[spec.compression])
        writer.start(profile=PROFILE, library=LIBRARY)
        now = time.time_ns()
        for name, text in spec.attachments.items():
            media_type = MEDIA_TYPES.get(Path(name).suffix.lower(), 'text/plain')
            writer.add_attachment(now, now, name, media_type, text.encode('utf-8'))
        if spec.description:
            writer.add_metadata('cam_ros', dict(spec.description))
        if spec.outputs:
            writer.add_metadata(OUTPUTS_RECORD, dict(spec.outputs))
        writer.add_metadata('rosbag2', {'serialized_metadata': self._bag_metadata()})
        schema_ids = {name: writer.register_schema(name, 'ros2msg', text.encode('utf-8'))
                      for name, text in spec.schemas.items()}
        self._channels = [
            writer.register_channel(
                topic['name'], 'cdr', schema_ids[topic['type']],
                {'offered_qos_profiles': qos, 'topic_type_hash': topic['type_description_hash']})
            for topic, qos in zip(spec.topics, spec.channel_qos)]

    def _bag_metadata(self) -> str:
        """Return the rosbag2 metadata text for the messages written so far."""
        start = self._spec.opened_ns if self._first_ns is None else self._first_ns
        end = start if self._last_ns is None else self._last_ns
        return bag_metadata(self._spec.name, self._spec.topics, self.counts, start, end - start,
                            self._spec.description)

    def write(self, index: int, records: Sequence[Record]) -> None:
        """Write messages received on topic `index` (counted as they are accepted)."""
        add_message, channel = self._writer.add_message, self._channels[index]
        accepted = 0
        try:
            for data, log_time, publish_time, sequence in records:
                accepted += 1
                add_message(channel, log_time=log_time, data=data, publish_time=publish_time,
                            sequence=sequence)
        finally:
            if accepted:
                self.counts[index] += accepted
                times = [record[1] for record in records[:accepted]]
                first, last = min(times), max(times)
                self._first_ns = first if self._first_ns is None else min(self._first_ns, first)
                self._last_ns = last if self._last_ns is None else max(self._last_ns, last)

    def flush(self) -> None:
        """Write out the open chunk."""
        self._writer.flush()

    def finish(self) -> None:
        """Write the final rosbag2 record, the summary and the footer."""
        self._writer.add_metadata('rosbag2', {'serialized_metadata': self._bag_metadata()})
        self._writer.finish()
