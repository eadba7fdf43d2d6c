"""Recording a real cam_node run to MCAP, and reading it back with independent readers."""
from __future__ import annotations

import json
import signal
import sys
import time
from pathlib import Path

import numpy as np
from conftest import CONFIG_DIR
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool

from cam_ros.core import build_design, load_config
from cam_ros.recording import open_recording

DEFAULT = CONFIG_DIR / 'default.yaml'
CALL_TIMEOUT_S = 10.0
RUN_S = 1.5
STATE_RATE_HZ = 200.0
FLUSH_PERIOD_S = 1.0  # the Recorder's default flush_period
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


def test_recording_from_start_up_opens_with_rosbags_and_mcap_ros2(start_cam_node, tmp_path):
    folder = tmp_path / 'runs'
    process, _ = start_cam_node(DEFAULT, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={folder}')
    time.sleep(RUN_S)
    assert process.stop(signal.SIGINT) == 0, process.log()
    path = only_file(folder)

    recording = open_recording(path)
    assert recording.complete
    assert NODE_TOPICS <= set(recording.topics)
    assert 'cam_config.yaml' in recording.attachments
    assert recording.attachments['cam_config.yaml'] == DEFAULT.read_text()
    joints = recording.topics['/cam/joint_states']
    assert joints.count >= RUN_S * 50 * 0.5
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
    angles = np.array([s.position[0] for s in states])
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


def test_sigkill_while_recording_loses_at_most_the_open_chunk(start_cam_node, executor,
                                                              tmp_path):
    folder = tmp_path / 'runs'
    process, _ = start_cam_node(DEFAULT, '-p', 'recording.enabled:=true',
                                '-p', f'recording.directory:={folder}',
                                '-p', f'output.state_rate_hz:={STATE_RATE_HZ}')
    received: list[int] = []
    executor.node('witness').create_subscription(
        JointState, '/cam/joint_states',
        lambda m: received.append(m.header.stamp.sec * 10**9 + m.header.stamp.nanosec), 100)
    deadline = time.monotonic() + 10.0
    while len(received) < 2 * STATE_RATE_HZ and time.monotonic() < deadline:
        time.sleep(0.05)
    process.stop(signal.SIGKILL)
    witnessed = list(received)
    recording = open_recording(only_file(folder))
    assert not recording.complete
    stamps = [m.message.header.stamp.sec * 10**9 + m.message.header.stamp.nanosec
              for m in recording.messages(['/cam/joint_states'])]
    assert stamps == sorted(stamps)
    # Compare from the witness's first message on (the recorder started before it subscribed).
    kept = [stamp for stamp in stamps if stamp >= witnessed[0]]
    assert set(kept) <= set(witnessed)
    # The recorder flushes its open chunk every FLUSH_PERIOD_S: only that chunk may be lost.
    lost = len(witnessed) - len(kept)
    assert 0 <= lost <= STATE_RATE_HZ * FLUSH_PERIOD_S * 1.5 + 10, (lost, len(witnessed))
