"""QoS profiles in the YAML form rosbag2 (Jazzy, metadata version 9) writes and reads."""

from collections.abc import Mapping, Sequence
from typing import Any

from rclpy.duration import Duration
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile,
                       ReliabilityPolicy)
import yaml

_POLICIES: dict[str, Any] = {
    'history': HistoryPolicy,
    'reliability': ReliabilityPolicy,
    'durability': DurabilityPolicy,
    'liveliness': LivelinessPolicy,
}
_DURATIONS = ('deadline', 'lifespan', 'liveliness_lease_duration')
_NS_PER_S = 10**9
#: Queue depth rosbag2 falls back to when a recorded profile has none (rmw default profile).
DEFAULT_DEPTH = 10


def qos_to_dict(profile: QoSProfile) -> dict[str, Any]:
    """Return a profile as rosbag2 serialises it: policy words, durations as {sec, nsec}."""
    def duration(value: Duration) -> dict[str, int]:
        sec, nsec = divmod(value.nanoseconds, _NS_PER_S)
        return {'sec': sec, 'nsec': nsec}

    return {
        'history': profile.history.name.lower(),
        'depth': profile.depth,
        'reliability': profile.reliability.name.lower(),
        'durability': profile.durability.name.lower(),
        'deadline': duration(profile.deadline),
        'lifespan': duration(profile.lifespan),
        'liveliness': profile.liveliness.name.lower(),
        'liveliness_lease_duration': duration(profile.liveliness_lease_duration),
        'avoid_ros_namespace_conventions': profile.avoid_ros_namespace_conventions,
    }


def qos_from_dict(entry: Mapping[str, Any]) -> QoSProfile:
    """
    Return the publisher profile to offer for one recorded profile.

    Accepts policy words (metadata version 9) and the integers of older versions; unknown
    policies become SYSTEM_DEFAULT, and a history without a usable depth becomes KEEP_LAST of
    DEFAULT_DEPTH, as `ros2 bag play` does.
    """
    def policy(key: str) -> Any:
        enum, value = _POLICIES[key], entry.get(key, 'system_default')
        try:
            return enum(value) if isinstance(value, int) else enum[str(value).upper()]
        except (KeyError, ValueError):
            return enum.SYSTEM_DEFAULT

    def duration(key: str) -> Duration:
        value = entry.get(key) or {}
        return Duration(seconds=int(value.get('sec', 0)), nanoseconds=int(value.get('nsec', 0)))

    history, depth = policy('history'), int(entry.get('depth', 0))
    if history is HistoryPolicy.KEEP_ALL:
        depth = 0
    elif history is not HistoryPolicy.KEEP_LAST or depth <= 0:
        history, depth = HistoryPolicy.KEEP_LAST, DEFAULT_DEPTH
    return QoSProfile(
        history=history, depth=depth, reliability=policy('reliability'),
        durability=policy('durability'), liveliness=policy('liveliness'),
        avoid_ros_namespace_conventions=bool(entry.get('avoid_ros_namespace_conventions')),
        **{key: duration(key) for key in _DURATIONS})


def dump_qos(profiles: Sequence[QoSProfile]) -> str:
    """Return the 'offered_qos_profiles' channel metadata text (a YAML list)."""
    return yaml.safe_dump([qos_to_dict(p) for p in profiles], sort_keys=False,
                          default_flow_style=False)


def load_qos(text: str) -> list[dict[str, Any]]:
    """Return the profiles of an 'offered_qos_profiles' text ([] when empty or unreadable)."""
    try:
        loaded = yaml.safe_load(text) if text else []
    except yaml.YAMLError:
        return []
    if not isinstance(loaded, list):
        return []
    return [entry for entry in loaded if isinstance(entry, dict)]
