"""
Figure 4: the MCAP recorder (cam_ros.recording.Recorder), throughput and publish-loop overhead.

Throughput: a publisher process (flood_publisher.py) floods serialized sensor_msgs/JointState
messages (reliable, keep last 100) for a few seconds; in the benchmark process a Recorder attached
to a node spun by a SingleThreadedExecutor in a background thread writes them to MCAP (zstd, the
defaults). The rate is the slope of the recorder's message count over the flood, its first
quarter left out. The reference is the same flood into a bare raw subscription that only counts.

Overhead: in one process, a node publishes JointState messages shaped like cam_node's state
message at a fixed rate from the main thread, with a Recorder of that topic attached to the same
node (its callbacks run in the executor thread) or without one. The figure is the mean time of one
loop iteration (build the message, publish it), recording on vs off, in alternating rounds.
"""
from __future__ import annotations

import json
import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState

from benchmarks.report import Figure, Target
from benchmarks.ros import BENCH_DIR, RosGraph, ServerProcess
from cam_ros.recording import Recorder, TopicSpec

#: The issue's targets: >= 20,000 messages/s recorded; publishing at most 10 % slower.
THROUGHPUT_TARGET = Target('>=', 20000.0, on='value')
OVERHEAD_TARGET = Target('<=', 1.10)
#: The flood's QoS (the recorder subscribes with the same profile: its minimum depth is 100).
FLOOD_QOS = QoSProfile(depth=100)
#: cam_node's state topics' QoS (node.py STATE_QOS).
STATE_QOS = QoSProfile(depth=10)
#: Fraction of the flood left out at its start (discovery, first chunk, warm-up).
WARMUP_FRACTION = 0.25
#: Period of the count sampling during a flood (s), and the wait for stragglers after it (s).
SAMPLE_S = 0.01
DRAIN_S = 1.0
MATCH_TIMEOUT_S = 10.0


@dataclass(frozen=True)
class RecordingSizes:
    """How much to measure: flood length and rounds, publish rate, loop length and rounds."""

    flood_seconds: float = 3.0
    flood_rounds: int = 2
    publish_rate_hz: float = 1000.0
    loop_seconds: float = 1.5
    loop_rounds: int = 3


def wait_until(predicate: Callable[[], bool], timeout: float) -> bool:
    """Poll predicate until it holds or timeout seconds pass; return its last value."""
    deadline = time.monotonic() + timeout
    while not predicate() and time.monotonic() < deadline:
        time.sleep(0.001)
    return predicate()


def flood_log(process: ServerProcess) -> dict[str, float]:
    """Return the flood publisher's JSON report line."""
    for line in process.log().splitlines():
        if line.startswith('{'):
            return json.loads(line)
    raise RuntimeError(f'flood publisher gave no report:\n{process.log()}')


def flood(graph: RosGraph, topic: str, count: Callable[[], int],
          seconds: float, name: str) -> dict[str, float]:
    """Flood topic from a publisher process; return the sink's sustained rate and totals."""
    process = graph.start([str(BENCH_DIR / 'flood_publisher.py'), topic, str(seconds)], name)
    samples: list[tuple[float, int]] = []
    while process.process.poll() is None:
        samples.append((time.monotonic(), count()))
        time.sleep(SAMPLE_S)
    if process.process.returncode != 0:
        raise RuntimeError(f'flood publisher failed:\n{process.log()}')
    time.sleep(DRAIN_S)
    report = flood_log(process)
    start = report['start'] + WARMUP_FRACTION * (report['end'] - report['start'])
    times, counts = np.array(samples).T
    received = np.interp([start, report['end']], times, counts)
    return {'rate': float((received[1] - received[0]) / (report['end'] - start)),
            'offered': report['published'] / (report['end'] - report['start']),
            'published': report['published'], 'received': count()}


def throughput(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> Figure:
    """Figure 4a: messages per second a Recorder writes, against a bare raw subscription."""
    node = graph.node('bench_recorder')
    runs: dict[str, list[dict[str, float]]] = {'bare': [], 'recorder': []}
    for round_ in range(sizes.flood_rounds):
        topic = f'/bench/flood_{round_}'
        received = [0]

        def on_message(data: bytes) -> None:
            received[0] += 1

        subscription = node.create_subscription(JointState, f'{topic}_bare', on_message,
                                                FLOOD_QOS, raw=True)
        runs['bare'].append(flood(graph, f'{topic}_bare', lambda: received[0],
                                  sizes.flood_seconds, f'flood_bare_{round_}'))
        node.destroy_subscription(subscription)
        path = workdir / f'flood_{round_}.mcap'
        with Recorder(node, path, [TopicSpec(f'{topic}_recorded', JointState, FLOOD_QOS)]) \
                as recorder:
            runs['recorder'].append(flood(graph, f'{topic}_recorded',
                                          lambda: recorder.message_count,
                                          sizes.flood_seconds, f'flood_recorded_{round_}'))
        if recorder.failed:
            raise RuntimeError(f'recorder failed: {recorder.error}')
    rate = {kind: statistics.median(run['rate'] for run in values)
            for kind, values in runs.items()}
    offered = statistics.median(run['offered'] for run in runs['recorder'])
    kept = statistics.median(run['received'] / run['published'] for run in runs['recorder'])
    return Figure(
        'recorder_messages_per_s', 'Recorder, JointState to MCAP', rate['recorder'], 'msg/s',
        'bare raw subscription', rate['bare'], THROUGHPUT_TARGET,
        f'A publisher process floods serialized JointState (reliable, depth 100) at '
        f'{offered:,.0f} msg/s; a Recorder (zstd, 64 KiB chunks) on a node in the benchmark '
        f'process, spun by a SingleThreadedExecutor thread, wrote {kept:.0%} of them; the rate is '
        f'the slope of its message count over the last {1 - WARMUP_FRACTION:.0%} of a '
        f'{sizes.flood_seconds:g} s flood, median of {sizes.flood_rounds}. Ratio = recorder / '
        'bare raw subscription (a callback that only counts).',
        extra={'runs': runs})


def state_message(clock_ns: int, theta: float) -> JointState:
    """Build a JointState like cam_node's state message (two joints, stamped, framed)."""
    message = JointState(name=['cam', 'follower'], position=[theta, 0.01 * math.sin(theta)],
                         velocity=[6.28, 0.0628 * math.cos(theta)])
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(clock_ns, 1_000_000_000)
    message.header.frame_id = 'cam'
    return message


def publish_loop(publisher: Publisher, rate_hz: float, count: int) -> tuple[list[int], float]:
    """Publish count messages at rate_hz; return ns per iteration and CPU seconds per message."""
    period = 1.0 / rate_hz
    busy: list[int] = []
    cpu = time.process_time()
    wake = time.perf_counter()
    for index in range(count):
        start = time.perf_counter_ns()
        publisher.publish(state_message(time.time_ns(), index * 1e-3))
        busy.append(time.perf_counter_ns() - start)
        wake += period
        time.sleep(max(0.0, wake - time.perf_counter()))
    return busy, (time.process_time() - cpu) / count


def overhead(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> Figure:
    """Figure 4b: mean publish-loop iteration with a Recorder on the node vs without."""
    node = graph.node('bench_state')
    topic = '/bench/joint_states'
    publisher = node.create_publisher(JointState, topic, STATE_QOS)
    count = max(1, int(sizes.publish_rate_hz * sizes.loop_seconds))
    busy: dict[str, list[int]] = {'off': [], 'on': []}
    cpu: dict[str, list[float]] = {'off': [], 'on': []}
    publish_loop(publisher, sizes.publish_rate_hz, min(count, 100))  # warm-up
    for round_ in range(sizes.loop_rounds):
        times, seconds = publish_loop(publisher, sizes.publish_rate_hz, count)
        busy['off'].extend(times)
        cpu['off'].append(seconds)
        with Recorder(node, workdir / f'state_{round_}.mcap',
                      [TopicSpec(topic, JointState, STATE_QOS)]) as recorder:
            if not wait_until(lambda: publisher.get_subscription_count() > 0, MATCH_TIMEOUT_S):
                raise RuntimeError('the recorder never matched the state publisher')
            times, seconds = publish_loop(publisher, sizes.publish_rate_hz, count)
            busy['on'].extend(times)
            cpu['on'].append(seconds)
            if not wait_until(lambda: recorder.message_count >= count, MATCH_TIMEOUT_S):
                raise RuntimeError(f'recorder wrote {recorder.message_count} of {count}')
    mean = {kind: statistics.fmean(values) * 1e-3 for kind, values in busy.items()}
    cpu_us = {kind: statistics.median(values) * 1e6 for kind, values in cpu.items()}
    return Figure(
        'recording_publish_overhead', 'Publish loop with recording on', mean['on'], 'us',
        'recording off', mean['off'], OVERHEAD_TARGET,
        f'One process: the main thread publishes JointState (built like cam_node\'s state '
        f'message) at {sizes.publish_rate_hz:g} Hz for {sizes.loop_seconds:g} s; mean time of '
        f'build + publish per message, {sizes.loop_rounds} alternating rounds each, with a '
        f'Recorder of that topic attached to the same node (every message recorded) or none. '
        f'Process CPU per message: {cpu_us["on"]:.0f} us on, {cpu_us["off"]:.0f} us off.',
        extra={'cpu_us_per_message': cpu_us,
               'p50_us': {kind: float(np.median(values)) * 1e-3
                          for kind, values in busy.items()}})


def recording_figures(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> list[Figure]:
    """Figure 4: recorder throughput and publish-loop overhead."""
    return [throughput(graph, workdir, sizes), overhead(graph, workdir, sizes)]
