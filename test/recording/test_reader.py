"""Reading recordings back: summary data, decoded messages, info text, unfinished files."""

from pathlib import Path
import struct

from mcap.reader import make_reader
import pytest
from sensor_msgs.msg import JointState

from cam_ros.core.errors import RecordingError
from cam_ros.recording import format_info, info, open_recording, Recorder, TopicSpec
from cam_ros.recording.qos import qos_to_dict

from .recording_support import (CONFIG_TEXT, joint_state, LATCHED_TOPIC, PARAMETER_TOPIC,
                                STREAM_COUNT, STREAM_QOS, STREAM_TOPIC, wait_until)

CHUNKED_COUNT = 40
#: Bytes per chunk of the chunked recording: a few messages each.
SMALL_CHUNK = 400
#: Offsets between the cuts made into the chunked recording.
CUT_STRIDE = 17
#: Footer record: opcode, length, summary start, summary offset start, summary CRC.
FOOTER = struct.Struct('<BQQQI')


def mcap_messages(path: Path) -> list:
    """Return (topic, data, log_time, publish_time) of every message, read by the mcap library."""
    with open(path, 'rb') as file:
        return [(c.topic, m.data, m.log_time, m.publish_time)
                for _, c, m in make_reader(file).iter_messages(log_time_order=True)]


@pytest.fixture(scope='module')
def chunked(ros, tmp_path_factory) -> Path:
    """Record a burst of JointState messages into many small chunks."""
    path = tmp_path_factory.mktemp('chunked') / 'chunked.mcap'
    node = ros.node('chunked_recorder')
    try:
        publisher = node.create_publisher(JointState, '/burst', STREAM_QOS)
        with Recorder(node, path, [TopicSpec('/burst', JointState, STREAM_QOS)],
                      chunk_size=SMALL_CHUNK, attachments={'notes.txt': 'burst'}) as recorder:
            assert wait_until(lambda: publisher.get_subscription_count() == 1)
            for index in range(CHUNKED_COUNT):
                publisher.publish(joint_state(index))
                assert wait_until(lambda: recorder.message_count == index + 1)
    finally:
        ros.drop(node)
    return path


def test_summary_of_the_reference(reference):
    recording = open_recording(reference.path)
    expected = mcap_messages(reference.path)
    assert recording.complete
    assert recording.message_count == len(expected) == STREAM_COUNT + 2
    assert (recording.start_ns, recording.end_ns) == (expected[0][2], expected[-1][2])
    assert recording.duration_ns == expected[-1][2] - expected[0][2]
    assert {t.name: (t.type, t.count) for t in recording.topics.values()} == {
        STREAM_TOPIC: ('sensor_msgs/msg/JointState', STREAM_COUNT),
        LATCHED_TOPIC: ('trajectory_msgs/msg/JointTrajectory', 1),
        PARAMETER_TOPIC: ('rcl_interfaces/msg/ParameterEvent', 1)}
    stream = recording.topics[STREAM_TOPIC]
    assert stream.serialization_format == 'cdr'
    assert stream.qos == (qos_to_dict(STREAM_QOS),)
    assert {t.name: t.type_hash for t in recording.topics.values()} == reference.graph_hashes
    assert recording.attachments == {'cam_config.yaml': CONFIG_TEXT}
    assert dict(recording.metadata['cam_ros']) == {'law': 'cycloidal'}


def test_decoded_messages_equal_the_published_ones(reference):
    recording = open_recording(reference.path)
    stream = list(recording.messages([STREAM_TOPIC]))
    assert [m.message for m in stream] == reference.stream
    assert all(m.topic == STREAM_TOPIC for m in stream)
    [latched] = recording.messages([LATCHED_TOPIC])
    assert latched.message == reference.trajectory


def test_raw_messages_are_the_stored_bytes_in_log_time_order(reference):
    raw = [tuple(m) for m in open_recording(reference.path).messages(raw=True)]
    assert raw == mcap_messages(reference.path)


def test_info_and_its_text(reference):
    data = info(reference.path)
    assert data['complete'] and data['message_count'] == STREAM_COUNT + 2
    assert data['size_bytes'] == reference.path.stat().st_size
    assert data['ros_distro'] == 'jazzy'
    assert data['attachments'] == {'cam_config.yaml': len(CONFIG_TEXT)}
    assert data['description'] == {'law': 'cycloidal'}
    text = format_info(data)
    lines = text.splitlines()
    assert lines[0] == f'Files:             {reference.path.name}'
    assert f'Messages:          {STREAM_COUNT + 2}' in lines
    assert (f'Topic: {STREAM_TOPIC} | Type: sensor_msgs/msg/JointState | Count: {STREAM_COUNT}'
            ' | Serialization Format: cdr | QoS: reliable, volatile, keep_last (10)') in text
    assert 'reliable, transient_local, keep_last (1)' in text
    seconds = data['duration_ns'] / 1e9
    assert f'Duration:          {seconds:.9f}s' in lines


def test_chunked_recording_has_many_chunks(chunked):
    with open(chunked, 'rb') as file:
        assert len(make_reader(file).get_summary().chunk_indexes) >= CHUNKED_COUNT // 8


def test_every_cut_of_a_file_reads_as_a_prefix(chunked, tmp_path):
    """A file cut anywhere (as by a killed writer) yields the messages before the cut, in order."""
    data = chunked.read_bytes()
    full = [tuple(m) for m in open_recording(chunked).messages(raw=True)]
    assert len(full) == CHUNKED_COUNT
    cut_file = tmp_path / 'cut.mcap'
    previous = 0
    for size in range(8, len(data), CUT_STRIDE):
        cut_file.write_bytes(data[:size])
        recording = open_recording(cut_file)
        messages = [tuple(m) for m in recording.messages(raw=True)]
        assert not recording.complete
        assert messages == full[:len(messages)]
        assert recording.message_count == len(messages) >= previous
        if messages:
            assert recording.topics['/burst'].count == len(messages)
            assert (recording.start_ns, recording.end_ns) == (full[0][2], messages[-1][2])
            assert recording.attachments == {'notes.txt': 'burst'}
        previous = len(messages)
    assert previous == CHUNKED_COUNT  # the last cuts only remove summary and footer


def test_messages_survive_when_only_the_summary_is_lost(chunked, tmp_path):
    data = chunked.read_bytes()
    opcode, _, summary_start, _, _ = FOOTER.unpack(data[-FOOTER.size - 8:-8])
    assert opcode == 0x02
    cut_file = tmp_path / 'no_summary.mcap'
    cut_file.write_bytes(data[:summary_start])
    recording = open_recording(cut_file)
    assert not recording.complete and recording.message_count == CHUNKED_COUNT
    assert [tuple(m) for m in recording.messages(raw=True)] == mcap_messages(chunked)


def test_not_an_mcap_file(tmp_path):
    path = tmp_path / 'text.mcap'
    path.write_text('hello, this is not MCAP')
    with pytest.raises(RecordingError, match='not an MCAP file'):
        open_recording(path)


def test_missing_file(tmp_path):
    with pytest.raises(RecordingError, match='cannot open recording'):
        open_recording(tmp_path / 'absent.mcap')
