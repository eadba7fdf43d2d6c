"""QoS profiles to and from rosbag2's YAML form."""

import pytest
from rclpy.duration import Duration, Infinite
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile,
                       ReliabilityPolicy)
import yaml

from cam_ros.recording.qos import (DEFAULT_DEPTH, dump_qos, load_qos, qos_from_dict,
                                   qos_to_dict)

PROFILES = [
    QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
               reliability=ReliabilityPolicy.RELIABLE),
    QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT,
               durability=DurabilityPolicy.VOLATILE, liveliness=LivelinessPolicy.AUTOMATIC),
    QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
               deadline=Duration(seconds=1, nanoseconds=500), lifespan=Infinite,
               liveliness=LivelinessPolicy.MANUAL_BY_TOPIC,
               liveliness_lease_duration=Duration(nanoseconds=2_000_000_001)),
]
#: rmw's infinite duration (2**63 - 1 ns) as rosbag2 writes it.
INFINITE = {'sec': 9223372036, 'nsec': 854775807}


def test_latched_profile_in_words():
    assert qos_to_dict(PROFILES[0]) == {
        'history': 'keep_last', 'depth': 1, 'reliability': 'reliable',
        'durability': 'transient_local', 'deadline': {'sec': 0, 'nsec': 0},
        'lifespan': {'sec': 0, 'nsec': 0}, 'liveliness': 'system_default',
        'liveliness_lease_duration': {'sec': 0, 'nsec': 0},
        'avoid_ros_namespace_conventions': False}


def test_durations_split_into_sec_and_nsec():
    entry = qos_to_dict(PROFILES[2])
    assert entry['deadline'] == {'sec': 1, 'nsec': 500}
    assert entry['lifespan'] == INFINITE
    assert entry['liveliness_lease_duration'] == {'sec': 2, 'nsec': 1}
    assert (entry['history'], entry['liveliness']) == ('keep_all', 'manual_by_topic')


@pytest.mark.parametrize('profile', PROFILES)
def test_round_trip_through_yaml_text(profile):
    [entry] = load_qos(dump_qos([profile]))
    restored = qos_from_dict(entry)
    assert (restored.history, restored.reliability, restored.durability, restored.liveliness) \
        == (profile.history, profile.reliability, profile.durability, profile.liveliness)
    if profile.history is HistoryPolicy.KEEP_LAST:
        assert restored.depth == profile.depth
    assert (restored.deadline, restored.lifespan, restored.liveliness_lease_duration) == \
        (profile.deadline, profile.lifespan, profile.liveliness_lease_duration)


def test_integer_policies_of_older_metadata_are_understood():
    """Metadata before version 9 wrote the rmw enum values (reliable = 1, transient_local = 1)."""
    words = qos_to_dict(PROFILES[0])
    numbers = {**words, 'history': 1, 'reliability': 1, 'durability': 1, 'liveliness': 0}
    assert qos_from_dict(numbers) == qos_from_dict(words)


@pytest.mark.parametrize('history, depth', [('unknown', 0), ('keep_last', 0), ('bogus', 3)])
def test_unusable_history_becomes_rosbag2s_default(history, depth):
    entry = {**qos_to_dict(PROFILES[0]), 'history': history, 'depth': depth}
    restored = qos_from_dict(entry)
    assert (restored.history, restored.depth) == (HistoryPolicy.KEEP_LAST, DEFAULT_DEPTH)
    assert restored.durability is DurabilityPolicy.TRANSIENT_LOCAL


def test_dump_is_a_block_yaml_list():
    text = dump_qos(PROFILES[:2])
    assert text.startswith('- history: keep_last\n  depth: 1\n')
    assert yaml.safe_load(text) == [qos_to_dict(p) for p in PROFILES[:2]]


@pytest.mark.parametrize('text', ['', 'not: [a list', 'just text', '[1, 2]'])
def test_unreadable_text_gives_no_profiles(text):
    assert load_qos(text) == []
