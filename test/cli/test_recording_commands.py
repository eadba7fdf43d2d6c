"""`cam_ros info` and `cam_ros replay` on a recording made here with cam_ros.recording."""
from __future__ import annotations

import json
import re
import signal
import subprocess
import threading
import time

import pytest
import rclpy
from cli_support import assert_one_error_line, console_script, run_cli
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.recording import Recorder, TopicSpec

STREAM, LATCHED = '/cli_test/joint_states', '/cli_test/profile'
STREAM_QOS = QoSProfile(depth=10)
LATCHED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                         reliability=ReliabilityPolicy.RELIABLE)
STREAM_COUNT = 5
GRAPH_TIMEOUT_S = 10.0
REPLAY_RATE = 20.0  # the 20 ms stream replays in ~1 ms steps
LOOP_TIME_S = 3.0  # start-up (~1.5 s) and several passes of the ~10 ms recording at rate 10


def wait_until(predicate, timeout: float = GRAPH_TIMEOUT_S) -> bool:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


def joint_state(index: int) -> JointState:
    return JointState(name=['cam', 'follower'], position=[0.25 * index, -0.5 * index])


def profile() -> JointTrajectory:
    return JointTrajectory(joint_names=['follower'], points=[
        JointTrajectoryPoint(positions=[0.001 * k]) for k in range(4)])


@pytest.fixture
def recording(ros_domain, tmp_path):
    """Record a latched trajectory and a 50 Hz JointState stream; return the file.

    Source and recorder live in their own context, shut down before the tests replay: no stale
    latched sample of the original publisher can reach the tests' subscribers.
    """
    path = tmp_path / 'cam.mcap'
    context = Context()
    rclpy.init(context=context, domain_id=ros_domain)
    spinner = SingleThreadedExecutor(context=context)
    thread = threading.Thread(target=spinner.spin, daemon=True)
    thread.start()
    nodes = [rclpy.create_node(name, context=context)
             for name in ('cli_test_source', 'cli_test_recorder')]
    try:
        for node in nodes:
            spinner.add_node(node)
        source, recorder_node = nodes
        latched = source.create_publisher(JointTrajectory, LATCHED, LATCHED_QOS)
        stream = source.create_publisher(JointState, STREAM, STREAM_QOS)
        latched.publish(profile())
        with Recorder(recorder_node, path, [TopicSpec(STREAM, JointState, STREAM_QOS),
                                            TopicSpec(LATCHED, JointTrajectory, LATCHED_QOS)],
                      description={'purpose': 'cli test'}) as recorder:
            assert wait_until(lambda: stream.get_subscription_count() == 1)
            assert wait_until(lambda: recorder.message_count == 1)
            for index in range(STREAM_COUNT):
                stream.publish(joint_state(index))
                time.sleep(0.02)
            assert wait_until(lambda: recorder.message_count == STREAM_COUNT + 1)
    finally:
        spinner.shutdown()
        thread.join(GRAPH_TIMEOUT_S)
        for node in nodes:
            node.destroy_node()
        rclpy.try_shutdown(context=context)
    return path


def test_info_lists_topics_counts_and_qos(recording, capsys):
    run = run_cli(capsys, 'info', recording)
    assert run.code == 0 and run.err == ''
    assert f'Topic: {STREAM} | Type: sensor_msgs/msg/JointState | Count: {STREAM_COUNT}' in run.out
    assert f'Topic: {LATCHED} | Type: trajectory_msgs/msg/JointTrajectory | Count: 1' in run.out
    assert 'transient_local' in run.out and 'Description purpose:' in run.out
    data = json.loads(run_cli(capsys, 'info', recording, '--json').out)
    assert data['message_count'] == STREAM_COUNT + 1 and data['complete'] is True
    assert {topic['name']: topic['count'] for topic in data['topics']} == {
        STREAM: STREAM_COUNT, LATCHED: 1}


def test_replay_publishes_the_recorded_messages(recording, executor, capsys):
    listener = executor.node('cli_test_listener')
    received: dict[str, list] = {STREAM: [], LATCHED: []}
    done = threading.Event()

    def keep(topic):
        def callback(message):
            received[topic].append(message)
            if len(received[STREAM]) == STREAM_COUNT and received[LATCHED]:
                done.set()
        return callback

    listener.create_subscription(JointState, STREAM, keep(STREAM), STREAM_QOS)
    listener.create_subscription(JointTrajectory, LATCHED, keep(LATCHED), LATCHED_QOS)
    run = run_cli(capsys, 'replay', recording, '--rate', REPLAY_RATE, '--wait', GRAPH_TIMEOUT_S)
    assert run.code == 0, run.err
    assert run.out == f'published {STREAM_COUNT + 1} messages from {recording}\n'
    assert done.wait(GRAPH_TIMEOUT_S)
    assert received[STREAM] == [joint_state(index) for index in range(STREAM_COUNT)]
    assert received[LATCHED] == [profile()]


def test_replay_of_chosen_topics_only(recording, executor, capsys):
    listener = executor.node('cli_test_listener')
    received = []
    listener.create_subscription(JointState, STREAM, received.append, STREAM_QOS)
    run = run_cli(capsys, 'replay', recording, '--topics', STREAM, '--rate', REPLAY_RATE,
                  '--wait', GRAPH_TIMEOUT_S)
    assert run.code == 0 and run.out.startswith(f'published {STREAM_COUNT} messages')
    assert wait_until(lambda: len(received) == STREAM_COUNT)


def test_replay_of_an_unrecorded_topic_exits_2(recording, capsys):
    run = run_cli(capsys, 'replay', recording, '--topics', '/elsewhere')
    assert_one_error_line(run, 'replay', "topics[0] = '/elsewhere'", 'must be a recorded topic')


@pytest.mark.parametrize('command', ['info', 'replay'])
def test_a_file_that_is_not_a_recording_exits_2(command, tmp_path, capsys):
    path = tmp_path / 'not.mcap'
    path.write_text('hello')
    run = run_cli(capsys, command, path)
    assert run.code == 2 and run.out == '' and len(run.err.splitlines()) == 1
    assert run.err.startswith(f'cam_ros {command}: ') and 'not.mcap' in run.err


@pytest.mark.parametrize('argv, fragment', [
    (['--rate', '0'], "argument --rate: '0': must be a finite number > 0"),
    (['--wait', '-1'], "argument --wait: '-1': must be a finite number >= 0"),
    (['--topics'], 'argument --topics: expected at least one argument'),
])
def test_bad_replay_arguments_exit_2(argv, fragment, tmp_path, capsys):
    assert_one_error_line(run_cli(capsys, 'replay', tmp_path / 'x.mcap', *argv), 'replay',
                          fragment)


def test_replay_waits_for_a_fresh_echo_by_default(recording):
    """A replay started with an echo (no --wait) still reaches it: the stream is not latched."""
    echo = subprocess.Popen([console_script(), 'echo', STREAM, '--csv', '--count',
                             str(STREAM_COUNT), '--timeout', str(4 * GRAPH_TIMEOUT_S)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        replay = subprocess.run([console_script(), 'replay', str(recording), '--topics', STREAM],
                                capture_output=True, text=True, timeout=4 * GRAPH_TIMEOUT_S)
        out, err = echo.communicate(timeout=4 * GRAPH_TIMEOUT_S)
    finally:
        if echo.poll() is None:
            echo.kill()
    assert replay.returncode == 0, replay.stderr
    assert echo.returncode == 0, err
    rows = out.splitlines()[1:]
    assert [float(row.split(',')[2]) for row in rows] == [
        joint_state(index).position[0] for index in range(STREAM_COUNT)]


def test_recover_cli_writes_a_new_file_and_never_overwrites(recording, tmp_path, capsys):
    run = run_cli(capsys, 'recover', recording)
    target = recording.with_suffix('.recovered.mcap')
    assert run.code == 0, run.err
    assert run.out == (f'recovered {STREAM_COUNT + 1} messages on 2 topics into {target} '
                       '(0 bytes of unfinished records dropped)\n')
    assert json.loads(run_cli(capsys, 'info', target, '--json').out)['message_count'] == (
        STREAM_COUNT + 1)
    run = run_cli(capsys, 'recover', recording, '-o', target)
    assert_one_error_line(run, 'recover', f"-o = '{target}': exists already")
    run = run_cli(capsys, 'recover', recording, '-o', target, '--in-place')
    assert_one_error_line(run, 'recover', 'not allowed with argument')


def test_looping_replay_stops_cleanly_on_ctrl_c(recording):
    process = subprocess.Popen([console_script(), 'replay', str(recording), '--loop',
                                '--rate', '10', '--wait', '0'], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(LOOP_TIME_S)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=GRAPH_TIMEOUT_S)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0, err
    count = int(re.fullmatch(r'published (\d+) messages from .*\n', out).group(1))
    assert count > STREAM_COUNT + 1  # more than one pass
    assert err == ''
