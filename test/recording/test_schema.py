"""Message definitions and type hashes as rosbag2 stores them."""

from pathlib import Path
import sys

from builtin_interfaces.msg import Time
import pytest
from rcl_interfaces.msg import ParameterEvent
from rosbags.typesys import get_types_from_msg, get_typestore, Stores
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

from cam_ros.core.errors import RecordingError
from cam_ros.recording.schema import (import_type, message_definition, SEPARATOR,
                                      share_directory, type_hash, type_name)

TYPES = [JointState, JointTrajectory, ParameterEvent, Time]
#: Dependency order worked out by hand from the .msg files: depth-first, sorted at each level.
DEPENDENCIES = {
    'sensor_msgs/msg/JointState': ['std_msgs/Header', 'builtin_interfaces/Time'],
    'trajectory_msgs/msg/JointTrajectory': [
        'std_msgs/Header', 'builtin_interfaces/Time', 'trajectory_msgs/JointTrajectoryPoint',
        'builtin_interfaces/Duration'],
    'rcl_interfaces/msg/ParameterEvent': [
        'builtin_interfaces/Time', 'rcl_interfaces/Parameter', 'rcl_interfaces/ParameterValue'],
    'builtin_interfaces/msg/Time': [],
}


def installed_msg(name: str) -> str:
    """Return the installed .msg text of 'pkg/Type' or 'pkg/msg/Type', read independently."""
    package, short = name.split('/')[0], name.split('/')[-1]
    return (Path(sys.prefix) / 'share' / package / 'msg' / f'{short}.msg').read_text()


@pytest.mark.parametrize('msg_type', TYPES)
def test_type_name_round_trips_through_import(msg_type):
    name = type_name(msg_type)
    assert name.count('/msg/') == 1
    assert import_type(name) is msg_type


@pytest.mark.parametrize('name', sorted(DEPENDENCIES))
def test_definition_is_the_msg_text_then_each_dependency_once(name):
    sections = message_definition(name).split('\n' + SEPARATOR + '\n')
    assert sections[0] == installed_msg(name)
    headers = [section.split('\n', 1)[0] for section in sections[1:]]
    assert headers == [f'MSG: {dependency}' for dependency in DEPENDENCIES[name]]
    for dependency, section in zip(DEPENDENCIES[name], sections[1:]):
        assert section.split('\n', 1)[1] == installed_msg(dependency)


@pytest.mark.parametrize('msg_type', TYPES)
def test_definition_reproduces_the_type_hash(msg_type):
    """rosbags rebuilds the type from the embedded text alone; its RIHS01 hash must agree."""
    name = type_name(msg_type)
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(message_definition(name), name))
    assert store.hash_rihs01(name) == type_hash(name)


def test_type_hash_has_the_rihs01_form():
    digest = type_hash('sensor_msgs/msg/JointState')
    assert digest.startswith('RIHS01_') and len(digest) == len('RIHS01_') + 64
    int(digest[len('RIHS01_'):], 16)


def test_share_directory_falls_back_to_the_interpreter_prefix(monkeypatch):
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    assert share_directory('sensor_msgs') == Path(sys.prefix, 'share', 'sensor_msgs')


@pytest.mark.parametrize('call', [import_type, message_definition, type_hash])
def test_uninstalled_type_raises_recording_error(call):
    with pytest.raises(RecordingError, match='no_such_msgs'):
        call('no_such_msgs/msg/Nothing')
