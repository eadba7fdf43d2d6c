"""Recording a real cam_node run to MCAP, and reading it back with independent readers."""
from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool

from cam_ros.cli import main as cam_ros
from cam_ros.core import build_design, load_config
from cam_ros.recording import open_recording

DEFAULT = CONFIG_DIR / 'default.yaml'
CALL_TIMEOUT_S = 10.0
RUN_S = 1.5
WITNESSED_STATES = 40  # state messages a witness sees before the recording node is stopped
WITNESS_DEPTH = 100
ANGLES = np.radians([0.0, 100.0, 130.0, 150.0, 250.0, 330.0])
NODE_TOPICS = {'/cam/profile', '/cam/pressure_angle', '/cam/markers', '/cam/joint_states',
               '/cam/state_extras', '/parameter_events'}


def installed_type_hash(package: str, name: str) -> str:
    """Read a message type's RIHS01 hash from its installed .json description (independently)."""
    path = Path(sys.prefix) / 'share' / package / 'msg' / f'{name}.json'
    hashes = json.loads(path.read_text())['type_hashes']
    return next(item['hash_string'] for item in hashes
                if item['type_name'] == f'{package}/msg/{name}')


def only_file(folder: Path) -> Path:
    files = sorted(folder.glob('*.mcap'))
    assert len(files) == 1, files
    return files[0]


def test_recording_from_start_up_opens_with_rosbags_and_mcap_ros2(start_cam_node, executor,
                                                                  tmp_path):
    folder = tmp_path / 'runs'
    process, _ = start_cam_node(DEFAULT, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={folder}')
    # Evidence the node published, not a sleep: a witness's count of its state messages.
    witnessed = set()
    executor.node('witness').create_subscription(
        JointState, '/cam/joint_states', lambda m: witnessed.add(
            (m.header.stamp.sec, m.header.stamp.nanosec)), WITNESS_DEPTH)
    deadline = time.monotonic() + CALL_TIMEOUT_S * 3
    while len(witnessed) < WITNESSED_STATES:
        assert time.monotonic() < deadline, f'{len(witnessed)} state messages witnessed'
        time.sleep(0.01)
    assert process.stop(signal.SIGINT) == 0, process.log()
    path = only_file(folder)

    recording = open_recording(path)
    assert recording.complete
    assert NODE_TOPICS <= set(recording.topics)
    assert 'cam_config.yaml' in recording.attachments
    assert recording.attachments['cam_config.yaml'] == DEFAULT.read_text()
    joints = recording.topics['/cam/joint_states']
    assert joints.count >= WITNESSED_STATES  # recorded from start-up, before the witness
    assert joints.type_hash == installed_type_hash('sensor_msgs', 'JointState')
    profile_qos = recording.topics['/cam/profile'].qos[0]
    assert profile_qos['durability'] == 'transient_local'
    assert profile_qos['reliability'] == 'reliable'

    from rosbags.highlevel import AnyReader
    design = build_design(load_config(DEFAULT))
    expected = design.profile(design.config.sample_count)
    with AnyReader([path]) as reader:
        connections = [c for c in reader.connections if c.topic == '/cam/profile']
        assert connections[0].msgtype == 'trajectory_msgs/msg/JointTrajectory'
        messages = [reader.deserialize(raw, conn.msgtype)
                    for conn, _, raw in reader.messages(connections=connections)]
    assert len(messages) == 1
    np.testing.assert_array_equal([p.positions[0] for p in messages[0].points], expected.position)

    from mcap_ros2.reader import read_ros2_messages
    states = [m.ros_msg for m in read_ros2_messages(str(path), topics=['/cam/joint_states'])]
    assert len(states) == joints.count
    angles = -np.array([s.position[0] for s in states])  # a clockwise cam's joint is -theta
    np.testing.assert_allclose([s.position[1] for s in states],
                               design.evaluate(angles).position, atol=1e-12)


def test_record_service_starts_and_stops_a_file(start_cam_node, executor, tmp_path):
    folder = tmp_path / 'runs'
    process, _ = start_cam_node(DEFAULT, '-p', f'recording.directory:={folder}')
    assert not folder.exists()
    client = executor.node('record_client').create_client(SetBool, '/cam/record')
    assert client.wait_for_service(timeout_sec=CALL_TIMEOUT_S)
    started = client.call(SetBool.Request(data=True), timeout_sec=CALL_TIMEOUT_S)
    assert started.success and 'recording to' in started.message
    time.sleep(0.5)
    stopped = client.call(SetBool.Request(data=False), timeout_sec=CALL_TIMEOUT_S)
    assert stopped.success and 'stopped' in stopped.message
    recording = open_recording(only_file(folder))
    assert recording.complete and recording.topics['/cam/joint_states'].count > 0
    assert process.stop(signal.SIGTERM) == 0


def seed_000_in_mm(folder: Path) -> Path:
    """Write seed 000 with its lengths in mm (base radius 40 mm), as a user's file would be."""
    text = (DEFAULT.read_text().replace('length_unit: cm', 'length_unit: mm')
            .replace('base_radius: 4.0', 'base_radius: 40.0')
            .replace('roller_radius: 1.0', 'roller_radius: 10.0')
            .replace('offset: 0.5', 'offset: 5.0')
            .replace('[0.0, 0.0, 2.0, 2.0]', '[0.0, 0.0, 20.0, 20.0]')
            .replace('[0.0, 2.0, 2.0, 0.0]', '[0.0, 20.0, 20.0, 0.0]')
            .replace('min_radius_of_curvature: 0.5', 'min_radius_of_curvature: 5.0'))
    path = folder / 'seed_000_mm.yaml'
    path.write_text(text)
    return path


def cli(capsys, *argv) -> str:
    """Run `cam_ros` in this process; return what it printed, failing on a non-zero exit."""
    code = cam_ros([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def test_recording_carries_the_parameters_in_force_and_their_changes(start_cam_node, tmp_path,
                                                                     capsys):
    config = seed_000_in_mm(tmp_path)
    folder = tmp_path / 'runs'
    _, client = start_cam_node(config, '-p', f'recording.directory:={folder}',
                               '-p', 'limits.pressure_angle_deg:=35.0')
    # A run-time change before the recording starts: base radius 40 -> 55 mm.
    cli(capsys, 'param', 'set', 'follower.base_radius', '55.0', '--timeout', CALL_TIMEOUT_S)
    cli(capsys, 'record', 'on', '--timeout', CALL_TIMEOUT_S)
    served = client.call(EvaluateCam.Request(angles=ANGLES.tolist()), timeout_sec=CALL_TIMEOUT_S)
    assert served.success, served.message
    cli(capsys, 'param', 'set', 'follower.roller_radius', '12.0', '--timeout', CALL_TIMEOUT_S)
    time.sleep(0.3)
    cli(capsys, 'record', 'off', '--timeout', CALL_TIMEOUT_S)
    path = only_file(folder)

    recording = open_recording(path)
    assert recording.attachments['cam_config.yaml'] == config.read_text()  # as started
    in_force = tmp_path / 'in_force.yaml'
    in_force.write_text(recording.attachments['cam_parameters.yaml'])
    design = build_design(load_config(in_force))  # the CLI's loader
    assert design.config.length_unit == 'mm'
    assert design.follower.base_radius == pytest.approx(0.055, abs=1e-15)
    assert design.config.pressure_angle_limit == pytest.approx(np.radians(35.0))  # the -p
    state = design.evaluate(ANGLES)
    for field in ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                  'radius_of_curvature'):
        np.testing.assert_array_equal(getattr(served, field), getattr(state, field), field)

    # A node started on the attached file serves the same design.
    _, replica = start_cam_node(in_force, name='replica')
    again = replica.call(EvaluateCam.Request(angles=ANGLES.tolist()), timeout_sec=CALL_TIMEOUT_S)
    np.testing.assert_array_equal(again.position, served.position)
    np.testing.assert_array_equal(again.pressure_angle, served.pressure_angle)

    data = json.loads(cli(capsys, 'info', path, '--json'))
    changes = [c for c in data['parameter_changes'] if c['kind'] == 'changed']
    assert [(c['node'], c['name'], c['old'], c['new']) for c in changes] == [
        ('/cam', 'follower.roller_radius', 10.0, 12.0)]
    assert data['start_ns'] <= changes[0]['time_ns'] <= data['end_ns']
    text = cli(capsys, 'info', path)
    assert '/cam follower.roller_radius: 10.0 -> 12.0' in text
    assert 'cam_parameters.yaml' in text and 'Description node:' in text


def test_a_reload_publishes_only_the_parameters_it_changes(start_cam_node, tmp_path, capsys):
    live = tmp_path / 'live.yaml'
    live.write_text(DEFAULT.read_text())
    folder = tmp_path / 'runs'
    process, _ = start_cam_node(live, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={folder}')
    # Two real changes first: they show that the recording takes the node's parameter events.
    cli(capsys, 'param', 'set', 'follower.offset', '0.0', '--timeout', CALL_TIMEOUT_S)
    cli(capsys, 'param', 'set', 'follower.offset', '0.5', '--timeout', CALL_TIMEOUT_S)
    assert cli(capsys, 'reload', '--timeout', CALL_TIMEOUT_S) == f'reloaded {live}\n'
    live.write_text(DEFAULT.read_text().replace('roller_radius: 1.0', 'roller_radius: 1.25'))
    assert cli(capsys, 'reload', '--timeout', CALL_TIMEOUT_S) == f'reloaded {live}\n'
    time.sleep(0.3)
    assert process.stop(signal.SIGINT) == 0, process.log()
    path = only_file(folder)

    events = [m.message for m in open_recording(path).messages(['/parameter_events'])
              if m.message.node == '/cam']
    assert [([p.name for p in event.new_parameters], [p.name for p in event.changed_parameters],
             [p.name for p in event.deleted_parameters]) for event in events] == [
        ([], ['follower.offset'], []), ([], ['follower.offset'], []),
        ([], ['follower.roller_radius'], [])]
    data = json.loads(cli(capsys, 'info', path, '--json'))
    assert [(c['name'], c['kind'], c['old'], c['new']) for c in data['parameter_changes']] == [
        ('follower.offset', 'changed', 0.5, 0.0), ('follower.offset', 'changed', 0.0, 0.5),
        ('follower.roller_radius', 'changed', 1.0, 1.25)]


def test_a_killed_node_s_recording_is_recovered_for_rosbags(start_cam_node, tmp_path):
    from rosbags.highlevel import AnyReader

    folder = tmp_path / 'runs'
    process, _ = start_cam_node(DEFAULT, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={folder}')
    time.sleep(RUN_S)
    process.stop(signal.SIGKILL)
    killed = only_file(folder)
    kept = shutil.copyfile(killed, tmp_path / 'kept.mcap')
    survived = open_recording(killed)
    assert not survived.complete
    with pytest.raises(Exception):
        AnyReader([killed]).open()

    recovered = folder / 'recovered.mcap'
    result = subprocess.run([shutil.which('cam_ros', path=str(Path(sys.executable).parent)),
                             'recover', str(killed), '-o', str(recovered)],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    count = survived.message_count
    assert result.stdout.startswith(f'recovered {count} messages on {len(survived.topics)} '
                                    f'topics into {recovered} (')
    assert killed.read_bytes() == kept.read_bytes()  # the input is left alone
    with AnyReader([recovered]) as reader:
        assert reader.message_count == count
        states = [reader.deserialize(raw, conn.msgtype) for conn, _, raw in reader.messages(
            connections=[c for c in reader.connections if c.topic == '/cam/joint_states'])]
    assert len(states) == survived.topics['/cam/joint_states'].count > 0
    design = build_design(load_config(DEFAULT))
    theta = -np.array([m.position[0] for m in states])  # clockwise: the joint is -theta
    np.testing.assert_allclose([m.position[1] for m in states], design.evaluate(theta).position,
                               atol=1e-12)
