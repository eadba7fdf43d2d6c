"""
Host a Recorder on a cam_node in its own process, for the recorder benchmarks.

Run as ``python -m benchmarks.recording_host COMMAND ARGS... --ros-args -r __node:=NAME
--params-file CONFIG``: builds the real CamNode, served as cam_node is (UDP alone), spins it with
a SingleThreadedExecutor in a background thread (as rclpy.spin would) and talks JSON lines over
stdin/stdout.

``sink MODE TOPIC PATH``: MODE 'recorder' attaches a Recorder of TOPIC (sensor_msgs/JointState,
offered with cam_node's state QoS) writing to PATH; MODE 'bare' a raw subscription that only
counts, one executor callback per message; MODE 'drain' a raw subscription whose messages the
Recorder's intake takes in batches, only counted (the Recorder without writing). Prints
{"ready": true}, then answers every 'count' line with {"count": n, "cpu_s": s} and every
'matched' line with {"matched": b} once its subscription has matched a publisher (or after
WAIT_S), until stdin closes.

``loop TOPIC FOLDER RATE_HZ COUNT ROUNDS``: the main thread publishes COUNT JointState messages
at RATE_HZ on the node's ~/joint_states (TOPIC is ignored), ROUNDS times in turn with nothing
subscribed ('off'), a bare raw subscription with a callback per message ('bare') or taken in
batches ('drain'), a reader in a process of its own ('remote', benchmarks/remote_reader.py), and
the node's recording switch on ('on': recording.enabled true, files in
FOLDER, the node's own state messages recorded beside the loop's); prints the time per
build-and-publish and the process CPU per message of each, and the fraction of the loop's 'on'
messages recorded.
"""
from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from contextlib import ExitStack
from pathlib import Path
from typing import Any, Sequence

import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.utilities import remove_ros_args
from sensor_msgs.msg import JointState

from benchmarks.remote_reader import BARE_QOS

from cam_ros.node.middleware import serve_over_udp
from cam_ros.node.node import CamNode, STATE_QOS
from cam_ros.node.parameters import parse_command_line
from cam_ros.paths import default_config_path
from cam_ros.node.parameters import RECORDING_SWITCH
from cam_ros.recording import open_recording, Recorder, TopicSpec
from cam_ros.recording.intake import RawIntake, Taken

#: Longest wait for a subscription to match a publisher (s).
WAIT_S = 10.0
#: Longest wait for the recorder to write the last messages of a publish loop (s).
DRAIN_S = 1.0
#: The publish loop's modes: no subscriber, bare raw subscriptions on the same node (a callback
#: per message; taken in batches), a reader in a process of its own (as `ros2 bag record`), the
#: node's recording switch on.
LOOP_MODES = ('off', 'bare', 'drain', 'remote', 'on')
#: Longest wait for the remote reader to end once its stdin is closed (s).
STOP_S = 10.0
#: frame_id of the publish loop's messages (the node's own state messages say 'cam').
LOOP_FRAME = 'bench_loop'


def reply(**values: Any) -> None:
    """Print one JSON line for the benchmark process."""
    print(json.dumps(values), flush=True)


def wait_until(predicate: Callable[[], bool], timeout: float = WAIT_S) -> bool:
    """Poll predicate until it holds or timeout seconds pass; return its last value."""
    deadline = time.monotonic() + timeout
    while not predicate() and time.monotonic() < deadline:
        time.sleep(0.001)
    return predicate()


def ignore(data: bytes) -> None:
    """Drop a message (the bare subscription of the publish loop)."""


def ignore_batch(index: int, batch: list[Taken]) -> None:
    """Drop a batch of messages (the batched bare subscription of the publish loop)."""


def reader_matched(node: CamNode, topic: str) -> bool:
    """Return whether a subscription of the node on topic has matched a publisher."""
    name = node.resolve_topic_name(topic)
    return any(subscription.topic_name == name and subscription.get_publisher_count() > 0
               for subscription in node.subscriptions)


def sink(node: CamNode, mode: str, topic: str, path: str) -> None:
    """Record or just count topic, answering 'count' and 'matched' until stdin closes."""
    recorder = intake = None
    received = [0]

    def count(data: bytes) -> None:
        received[0] += 1

    def count_batch(index: int, batch: list[Taken]) -> None:
        received[0] += len(batch)

    if mode == 'recorder':
        recorder = Recorder(node, path, [TopicSpec(topic, JointState, STATE_QOS)])
    elif mode == 'drain':
        intake = RawIntake(node, [(topic, JointState, BARE_QOS)], count_batch)
    else:
        node.create_subscription(JointState, topic, count, BARE_QOS, raw=True)
    reply(ready=True)
    for line in sys.stdin:
        if line.strip() == 'count':
            reply(count=received[0] if recorder is None else recorder.message_count,
                  cpu_s=time.process_time())
        elif line.strip() == 'matched':
            reply(matched=wait_until(lambda: reader_matched(node, topic)))
    if intake is not None:
        intake.stop()
    if recorder is not None:
        recorder.close()
        if recorder.failed:
            raise SystemExit(f'recorder failed: {recorder.error}')


def state_message(clock_ns: int, theta: float, frame: str = 'cam') -> JointState:
    """Build a JointState like cam_node's state message (two joints, stamped, framed)."""
    message = JointState(name=['cam', 'follower'], position=[theta, 0.01 * math.sin(theta)],
                         velocity=[6.28, 0.0628 * math.cos(theta)])
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(clock_ns, 1_000_000_000)
    message.header.frame_id = frame
    return message


def publish_loop(publisher: Publisher, rate_hz: float, count: int) -> tuple[list[int], float]:
    """Publish count messages at rate_hz; return ns per build-and-publish, CPU s per message."""
    period = 1.0 / rate_hz
    busy: list[int] = []
    cpu = time.process_time()
    wake = time.perf_counter()
    for index in range(count):
        start = time.perf_counter_ns()
        publisher.publish(state_message(time.time_ns(), index * period, LOOP_FRAME))
        busy.append(time.perf_counter_ns() - start)
        wake += period
        time.sleep(max(0.0, wake - time.perf_counter()))
    return busy, (time.process_time() - cpu) / count


def stop(process: subprocess.Popen) -> None:
    """End the remote reader by closing its stdin; kill it if it does not end."""
    process.stdin.close()
    try:
        process.wait(STOP_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    process.stdout.close()


def switch_recording(node: CamNode, on: bool) -> None:
    """Set recording.enabled, as `ros2 param set` would; the node's switch follows."""
    result = node.set_parameters([Parameter(RECORDING_SWITCH, Parameter.Type.BOOL, on)])[0]
    if not result.successful or node.get_parameter(RECORDING_SWITCH).value != on:
        raise SystemExit(f'recording switch not {on}: {result.reason}')


def loop_messages_recorded(folder: Path, topic: str) -> int:
    """Return how many of the publish loop's messages the folder's recordings hold."""
    return sum(1 for path in folder.glob('*.mcap')
               for message in open_recording(path).messages([topic])
               if message.message.header.frame_id == LOOP_FRAME)


def loop(node: CamNode, topic: str, folder: str, rate_hz: float, count: int,
         rounds: int) -> None:
    """Run the publish loop ROUNDS times in each of LOOP_MODES; print the statistics."""
    node.set_parameters([Parameter('recording.directory', Parameter.Type.STRING, folder)])
    publisher = node.create_publisher(JointState, '~/joint_states', STATE_QOS)
    topic = publisher.topic_name
    busy: dict[str, list[int]] = {mode: [] for mode in LOOP_MODES}
    cpu: dict[str, list[float]] = {mode: [] for mode in LOOP_MODES}
    publish_loop(publisher, rate_hz, min(count, 100))  # warm-up
    for _ in range(rounds):
        for mode in LOOP_MODES:
            subscribers = publisher.get_subscription_count()
            with ExitStack() as stack:
                if mode == 'bare':
                    subscription = node.create_subscription(JointState, topic, ignore, BARE_QOS,
                                                            raw=True)
                    stack.callback(node.destroy_subscription, subscription)
                elif mode == 'drain':
                    stack.callback(RawIntake(node, [(topic, JointState, BARE_QOS)],
                                             ignore_batch).stop)
                elif mode == 'remote':
                    reader = subprocess.Popen([sys.executable, '-m', 'benchmarks.remote_reader',
                                               topic], stdin=subprocess.PIPE,
                                              stdout=subprocess.PIPE, text=True)
                    stack.callback(stop, reader)
                    if not json.loads(reader.stdout.readline() or '{}').get('matched'):
                        raise SystemExit('remote: the reader never matched the publisher')
                elif mode == 'on':
                    switch_recording(node, True)
                    stack.callback(switch_recording, node, False)
                if mode != 'off' and not wait_until(
                        lambda: publisher.get_subscription_count() > subscribers
                        and (mode == 'remote' or reader_matched(node, topic))):
                    raise SystemExit(f'{mode}: nothing matched the publisher')
                times, seconds = publish_loop(publisher, rate_hz, count)
                busy[mode].extend(times)
                cpu[mode].append(seconds)
            if not wait_until(lambda: publisher.get_subscription_count() == subscribers):
                raise SystemExit(f'{mode}: a reader stayed matched after the mode ended')
    reply(recorded_fraction=loop_messages_recorded(Path(folder), topic) / (rounds * count),
          **{mode: {'mean_us': statistics.fmean(busy[mode]) * 1e-3,
                    'p50_us': statistics.median(busy[mode]) * 1e-3,
                    'cpu_us': statistics.median(cpu[mode]) * 1e6} for mode in busy})


def main(args: Sequence[str] | None = None) -> int:
    """Start the cam node, spin it in a thread and run the requested command."""
    argv = list(sys.argv if args is None else args)
    command, *rest = remove_ros_args(argv)[1:]
    serve_over_udp()
    rclpy.init(args=argv)
    node = CamNode(parse_command_line(argv, default_config_path()).sources)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        if command == 'sink':
            sink(node, *rest)
        else:
            topic, path, rate_hz, count, rounds = rest
            loop(node, topic, path, float(rate_hz), int(count), int(rounds))
    except ExternalShutdownException:
        return 1
    finally:
        executor.shutdown()
        thread.join()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
