"""The recorder's file, read back by independent MCAP / rosbag2 readers (rosbags, mcap_ros2)."""

from pathlib import Path
import shutil

from mcap.reader import make_reader
from mcap_ros2.reader import read_ros2_messages
import pytest
from rosbags.highlevel import AnyReader
from sensor_msgs.msg import JointState
import yaml

from cam_ros.core.errors import InvalidParameter, RecordingError
from cam_ros.recording import open_recording, Recorder, TopicSpec

from .recording_support import (CONFIG_TEXT, LATCHED_TOPIC, PARAMETER_TOPIC, ReferenceRecording,
                                STREAM_COUNT, STREAM_QOS, STREAM_TOPIC, wait_until)
#: The offered QoS of the reference topics, spelled out as rosbag2 (Jazzy) writes them.
ZERO = {'sec': 0, 'nsec': 0}
EXPECTED_QOS = {
    STREAM_TOPIC: {
        'history': 'keep_last', 'depth': 10, 'reliability': 'reliable',
        'durability': 'volatile', 'deadline': ZERO, 'lifespan': ZERO,
        'liveliness': 'system_default', 'liveliness_lease_duration': ZERO,
        'avoid_ros_namespace_conventions': False},
    LATCHED_TOPIC: {
        'history': 'keep_last', 'depth': 1, 'reliability': 'reliable',
        'durability': 'transient_local', 'deadline': ZERO, 'lifespan': ZERO,
        'liveliness': 'system_default', 'liveliness_lease_duration': ZERO,
        'avoid_ros_namespace_conventions': False},
}
EXPECTED_TYPES = {
    STREAM_TOPIC: 'sensor_msgs/msg/JointState',
    LATCHED_TOPIC: 'trajectory_msgs/msg/JointTrajectory',
    PARAMETER_TOPIC: 'rcl_interfaces/msg/ParameterEvent',
}
EXPECTED_COUNTS = {STREAM_TOPIC: STREAM_COUNT, LATCHED_TOPIC: 1, PARAMETER_TOPIC: 1}


def summary(path: Path):
    """Return header and summary of an MCAP file, read by the mcap library."""
    with open(path, 'rb') as file:
        reader = make_reader(file)
        return reader.get_header(), reader.get_summary()


def metadata_records(path: Path) -> list:
    """Return all metadata records in file order."""
    with open(path, 'rb') as file:
        return list(make_reader(file).iter_metadata())


def assert_stream_equal(decoded: list, published: list) -> None:
    """Check decoded JointState-like objects field by field against the published messages."""
    assert len(decoded) == len(published)
    for got, sent in zip(decoded, published):
        assert list(got.name) == list(sent.name)
        assert list(got.position) == list(sent.position)
        assert list(got.velocity) == list(sent.velocity)
        assert list(got.effort) == list(sent.effort)
        assert got.header.frame_id == sent.header.frame_id
        assert (got.header.stamp.sec, got.header.stamp.nanosec) == \
            (sent.header.stamp.sec, sent.header.stamp.nanosec)


def test_rosbags_decodes_what_was_published(reference: ReferenceRecording):
    with AnyReader([reference.path]) as reader:
        by_topic: dict[str, list] = {}
        for connection, _, raw in reader.messages():
            by_topic.setdefault(connection.topic, []).append(
                reader.deserialize(raw, connection.msgtype))
    assert_stream_equal(by_topic[STREAM_TOPIC], reference.stream)
    [trajectory] = by_topic[LATCHED_TOPIC]
    assert list(trajectory.joint_names) == list(reference.trajectory.joint_names)
    assert [list(p.positions) for p in trajectory.points] == \
        [list(p.positions) for p in reference.trajectory.points]
    assert [p.time_from_start.nanosec for p in trajectory.points] == \
        [p.time_from_start.nanosec for p in reference.trajectory.points]
    [event] = by_topic[PARAMETER_TOPIC]
    assert event.node == '/reference_source'
    assert [(p.name, p.value.double_value) for p in event.changed_parameters] == \
        [(reference.parameter_name, 0.02)]


def test_mcap_ros2_decodes_what_was_published(reference: ReferenceRecording):
    messages = list(read_ros2_messages(str(reference.path), topics=[STREAM_TOPIC]))
    assert_stream_equal([m.ros_msg for m in messages], reference.stream)
    log_times = [m.log_time_ns for m in messages]
    assert log_times == sorted(log_times)
    assert all(m.publish_time_ns <= m.log_time_ns for m in messages)


def test_publish_time_is_the_source_time(reference: ReferenceRecording):
    """The latched trajectory was published before the recorder existed, received after."""
    [message] = read_ros2_messages(str(reference.path), topics=[LATCHED_TOPIC])
    assert message.publish_time_ns < reference.opened_ns < message.log_time_ns


def test_file_layout_is_rosbag2s(reference: ReferenceRecording):
    header, info = summary(reference.path)
    assert header.profile == 'ros2'
    assert sorted(s.name for s in info.schemas.values()) == sorted(EXPECTED_TYPES.values())
    assert {s.encoding for s in info.schemas.values()} == {'ros2msg'}
    channels = {c.topic: c for c in info.channels.values()}
    assert {t: info.schemas[c.schema_id].name for t, c in channels.items()} == EXPECTED_TYPES
    assert {c.message_encoding for c in channels.values()} == {'cdr'}
    assert {t: info.statistics.channel_message_counts[c.id] for t, c in channels.items()} == \
        EXPECTED_COUNTS
    assert info.chunk_indexes and all(i.compression == 'zstd' for i in info.chunk_indexes)


@pytest.mark.parametrize('topic', [STREAM_TOPIC, LATCHED_TOPIC])
def test_channel_metadata_carries_offered_qos_and_graph_type_hash(reference, topic):
    _, info = summary(reference.path)
    [channel] = [c for c in info.channels.values() if c.topic == topic]
    assert yaml.safe_load(channel.metadata['offered_qos_profiles']) == [EXPECTED_QOS[topic]]
    assert channel.metadata['topic_type_hash'] == reference.graph_hashes[topic]


def test_rosbag2_metadata_written_at_open_and_rewritten_at_close(reference):
    records = [r for r in metadata_records(reference.path) if r.name == 'rosbag2']
    assert len(records) == 2
    first, last = (yaml.safe_load(r.metadata['serialized_metadata']) for r in records)
    assert first['message_count'] == 0
    assert last['version'] == 9
    assert last['storage_identifier'] == 'mcap'
    assert last['relative_file_paths'] == [reference.path.name]
    assert last['message_count'] == sum(EXPECTED_COUNTS.values())
    topics = {t['topic_metadata']['name']: t for t in last['topics_with_message_count']}
    assert {name: t['message_count'] for name, t in topics.items()} == EXPECTED_COUNTS
    assert {name: t['topic_metadata']['type'] for name, t in topics.items()} == EXPECTED_TYPES
    for name, expected in EXPECTED_QOS.items():
        assert topics[name]['topic_metadata']['offered_qos_profiles'] == [expected]
        assert topics[name]['topic_metadata']['type_description_hash'] == \
            reference.graph_hashes[name]
    with AnyReader([reference.path]) as reader:
        assert last['starting_time']['nanoseconds_since_epoch'] == reader.start_time
        assert last['duration']['nanoseconds'] == reader.end_time - 1 - reader.start_time


def test_bag_directory_with_that_metadata_opens_in_rosbags(reference, tmp_path):
    """rosbags parses the metadata (v9) and checks each type hash against the schemas."""
    [*_, last] = [r for r in metadata_records(reference.path) if r.name == 'rosbag2']
    bag = tmp_path / 'bag'
    bag.mkdir()
    shutil.copy(reference.path, bag / reference.path.name)
    (bag / 'metadata.yaml').write_text(yaml.safe_dump(
        {'rosbag2_bagfile_information': yaml.safe_load(last.metadata['serialized_metadata'])}))
    with AnyReader([bag]) as reader:
        assert {c.topic: c.digest for c in reader.connections} == reference.graph_hashes
        assert reader.message_count == sum(EXPECTED_COUNTS.values())


def test_attachment_and_description_travel_in_the_file(reference):
    with open(reference.path, 'rb') as file:
        [attachment] = make_reader(file).iter_attachments()
    assert (attachment.name, attachment.media_type) == ('cam_config.yaml', 'application/yaml')
    assert attachment.data.decode() == CONFIG_TEXT
    [description] = [r for r in metadata_records(reference.path) if r.name == 'cam_ros']
    assert description.metadata == {'law': 'cycloidal'}


def test_the_recording_names_the_topics_its_node_publishes_as_its_outputs(
        reference, graph_nodes, tmp_path):
    # The reference's recorder publishes none of its topics (/parameter_events, which every
    # node publishes to, does not count).
    assert open_recording(reference.path).outputs == frozenset()
    [record] = [r for r in metadata_records(reference.path) if r.name == 'cam_ros_outputs']
    assert record.metadata == {'node': '/reference_recorder', 'topics': ''}
    node = graph_nodes('outputs', namespace='/cam')
    node.create_publisher(JointState, 'commands', STREAM_QOS)
    with Recorder(node, tmp_path / 'o.mcap', [TopicSpec('commands', JointState, STREAM_QOS),
                                              TopicSpec('/master', JointState, STREAM_QOS)]):
        pass
    assert open_recording(tmp_path / 'o.mcap').outputs == frozenset({'/cam/commands'})


def test_close_twice_and_context_manager(graph_nodes, tmp_path):
    node = graph_nodes('close_twice')
    recorder = Recorder(node, tmp_path / 'a.mcap', [TopicSpec('/x', JointState, STREAM_QOS)])
    recorder.close()
    recorder.close()
    assert recorder.closed and not recorder.failed
    assert summary(tmp_path / 'a.mcap')[1].statistics.message_count == 0
    with Recorder(node, tmp_path / 'b.mcap', [TopicSpec('/x', JointState, STREAM_QOS)]) as other:
        assert not other.closed and other.topics == ('/x',)
    assert other.closed


def test_relative_topic_names_are_recorded_fully_qualified(graph_nodes, tmp_path):
    node = graph_nodes('qualified', namespace='/cam')
    with Recorder(node, tmp_path / 'q.mcap', [TopicSpec('state', JointState, STREAM_QOS)]) as rec:
        assert rec.topics == ('/cam/state',)
    assert [c.topic for c in summary(tmp_path / 'q.mcap')[1].channels.values()] == ['/cam/state']


@pytest.mark.parametrize('compression', ['zstd', 'lz4', 'none'])
def test_every_compression_round_trips(graph_nodes, tmp_path, compression):
    node = graph_nodes(f'compress_{compression}')
    publisher = node.create_publisher(JointState, '/c', STREAM_QOS)
    path = tmp_path / 'c.mcap'
    with Recorder(node, path, [TopicSpec('/c', JointState, STREAM_QOS)],
                  compression=compression, chunk_size=256) as recorder:
        assert wait_until(lambda: publisher.get_subscription_count() == 1)
        sent = [JointState(name=['cam'], position=[float(i)]) for i in range(10)]
        for message in sent:
            publisher.publish(message)
        assert wait_until(lambda: recorder.message_count == len(sent))
    _, info = summary(path)
    assert {i.compression for i in info.chunk_indexes} == {'' if compression == 'none'
                                                           else compression}
    assert len(info.chunk_indexes) > 1
    assert [list(m.ros_msg.position) for m in read_ros2_messages(str(path))] == \
        [list(m.position) for m in sent]


def test_flush_period_puts_messages_on_disk_while_open(graph_nodes, tmp_path):
    """With a chunk far larger than the data, the timer alone writes the chunk out."""
    node = graph_nodes('flush_period')
    publisher = node.create_publisher(JointState, '/f', STREAM_QOS)
    path = tmp_path / 'f.mcap'
    with Recorder(node, path, [TopicSpec('/f', JointState, STREAM_QOS)],
                  chunk_size=1 << 20, flush_period=0.1) as recorder:
        assert wait_until(lambda: publisher.get_subscription_count() == 1)
        publisher.publish(JointState(name=['cam'], position=[1.5]))
        assert wait_until(lambda: recorder.message_count == 1)
        assert wait_until(lambda: open_recording(path).message_count == 1, timeout=1.0)


@pytest.mark.parametrize('option, value', [
    ('compression', 'gzip'), ('chunk_size', 0), ('flush_period', 0.0)])
def test_bad_options_name_the_parameter(graph_nodes, tmp_path, option, value):
    node = graph_nodes('bad_option')
    with pytest.raises(InvalidParameter) as error:
        Recorder(node, tmp_path / 'x.mcap', [TopicSpec('/x', JointState, STREAM_QOS)],
                 **{option: value})
    assert error.value.parameter == option
    assert not (tmp_path / 'x.mcap').exists()


def test_bad_topic_lists_are_rejected(graph_nodes, tmp_path):
    node = graph_nodes('bad_topics')
    with pytest.raises(InvalidParameter, match='topics = '):
        Recorder(node, tmp_path / 'x.mcap', [])
    spec = TopicSpec('/x', JointState, STREAM_QOS)
    with pytest.raises(InvalidParameter, match=r'topics\[1\].name'):
        Recorder(node, tmp_path / 'x.mcap', [spec, spec])


def test_existing_file_is_never_overwritten(graph_nodes, tmp_path):
    node = graph_nodes('existing')
    path = tmp_path / 'kept.mcap'
    path.write_bytes(b'precious')
    with pytest.raises(RecordingError, match='kept.mcap'):
        Recorder(node, path, [TopicSpec('/x', JointState, STREAM_QOS)])
    assert path.read_bytes() == b'precious'


def test_unwritable_location_raises_recording_error(graph_nodes, tmp_path):
    """A regular file where a directory should be: refused even when running as root."""
    node = graph_nodes('unwritable')
    (tmp_path / 'file').write_text('')
    with pytest.raises(RecordingError, match='cannot create recording'):
        Recorder(node, tmp_path / 'file' / 'sub' / 'r.mcap',
                 [TopicSpec('/x', JointState, STREAM_QOS)])
