"""recover(): a recording cut short becomes a finished file that every reader opens."""

import hashlib
from pathlib import Path
import shutil
import struct

import pytest
from rosbags.highlevel import AnyReader
import yaml

from cam_ros.core.errors import InvalidParameter, RecordingError
from cam_ros.recording import open_recording, recover

from .recording_support import KILL_AFTER, record_then_kill

MAGIC = b'\x89MCAP0\r\n'
CHUNK_OPCODE = 0x06  # MCAP specification: record opcodes


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def rosbags_messages(path: Path) -> list[tuple[str, int, bytes]]:
    """Return (topic, log time, wire bytes) of every message, as the rosbags library reads them."""
    with AnyReader([path]) as reader:
        return [(connection.topic, stamp, bytes(raw))
                for connection, stamp, raw in reader.messages()]


def file_order(path: Path) -> list[tuple[str, int, bytes]]:
    """Return (topic, log time, wire bytes) of every message of a file, in file order."""
    return [(m.topic, m.log_time_ns, bytes(m.message))
            for m in open_recording(path).messages(raw=True)]


@pytest.fixture(scope='module')
def killed(python, child_env, tmp_path_factory) -> Path:
    """Return a recording whose recorder was killed with SIGKILL after KILL_AFTER messages."""
    path = tmp_path_factory.mktemp('killed') / 'killed.mcap'
    assert record_then_kill(python, child_env, path) >= KILL_AFTER
    return path


def test_rosbags_refuses_a_killed_recording(killed):
    assert not open_recording(killed).complete
    with pytest.raises(Exception):
        rosbags_messages(killed)


def test_recovered_file_opens_everywhere_with_every_surviving_message(killed, tmp_path):
    before = digest(killed)
    survived = file_order(killed)
    output = tmp_path / 'recovered.mcap'
    result = recover(killed, output)
    assert digest(killed) == before  # the input is left alone
    assert result.output == output and result.topic_count == 1
    assert result.message_count == len(survived) > 0
    recovered = open_recording(output)
    assert recovered.complete
    assert recovered.topics['/crash'].count == len(survived)
    # rosbags reads the summary the recorder never wrote: the same messages, the same bytes.
    assert sorted(rosbags_messages(output)) == sorted(survived)
    positions = [m.message.position[0] for m in recovered.messages()]
    assert positions == [float(i) for i in range(len(survived))]
    bag = yaml.safe_load(recovered.metadata['rosbag2']['serialized_metadata'])
    assert bag['message_count'] == len(survived)
    assert bag['relative_file_paths'] == ['recovered.mcap']
    [topic] = bag['topics_with_message_count']
    assert topic['message_count'] == len(survived)
    assert topic['topic_metadata']['type'] == 'sensor_msgs/msg/JointState'
    times = [stamp for _, stamp, _ in survived]
    assert bag['starting_time']['nanoseconds_since_epoch'] == min(times)
    assert bag['duration']['nanoseconds'] == max(times) - min(times)


def chunk_spans(data: bytes) -> list[tuple[int, int]]:
    """Return (start, end) of every chunk record, read with the MCAP record framing."""
    spans, offset = [], len(MAGIC)
    while offset + 9 <= len(data):
        opcode, length = struct.unpack_from('<BQ', data, offset)
        end = offset + 9 + length
        if opcode == CHUNK_OPCODE:
            spans.append((offset, end))
        offset = end
    return spans


def test_a_cut_inside_a_chunk_keeps_the_records_before_it(killed, tmp_path):
    data = killed.read_bytes()
    whole = file_order(killed)
    spans = chunk_spans(data)
    assert len(spans) > 2
    start, end = spans[-2]
    cut = tmp_path / 'cut.mcap'
    cut.write_bytes(data[:(start + end) // 2])
    result = recover(cut, tmp_path / 'recovered.mcap')
    kept = file_order(result.output)
    assert 0 < len(kept) < len(whole) and kept == whole[:len(kept)]
    assert kept == file_order(cut)  # what the streaming reader sees in the cut file
    assert result.dropped_bytes == (start + end) // 2 - start


def test_a_finished_recording_is_copied_whole(reference, tmp_path):
    result = recover(reference.path, tmp_path / 'copy.mcap')
    original, copy = open_recording(reference.path), open_recording(result.output)
    assert result.dropped_bytes == 0 and result.message_count == original.message_count
    assert sorted(file_order(result.output)) == sorted(file_order(reference.path))
    assert copy.attachments == original.attachments
    assert copy.metadata['cam_ros'] == original.metadata['cam_ros']
    assert copy.metadata['cam_ros_outputs'] == original.metadata['cam_ros_outputs']
    assert {t.name: (t.type, t.qos, t.type_hash) for t in copy.topics.values()} == {
        t.name: (t.type, t.qos, t.type_hash) for t in original.topics.values()}


def test_recover_in_place_replaces_the_file_only_when_asked(killed, tmp_path):
    copy = tmp_path / 'copy.mcap'
    shutil.copyfile(killed, copy)
    survived = file_order(copy)
    with pytest.raises(InvalidParameter, match='exists already'):
        recover(copy, killed)  # another existing file is never overwritten
    result = recover(copy, copy)
    assert result.output == copy and open_recording(copy).complete
    assert file_order(copy) == sorted(survived, key=lambda item: item[1])
    assert [p.name for p in tmp_path.iterdir()] == ['copy.mcap']  # no temporary left


def test_recover_refuses_a_file_that_is_not_mcap(tmp_path):
    path = tmp_path / 'not.mcap'
    path.write_text('hello')
    with pytest.raises(RecordingError, match='not an MCAP file'):
        recover(path, tmp_path / 'out.mcap')
    assert not (tmp_path / 'out.mcap').exists()
