"""
Figure 4: the MCAP recorder (cam_ros.recording.Recorder): throughput and publish-loop overhead.

Both run in a host process (recording_host.py) holding the real cam_node (default config), spun by
a SingleThreadedExecutor in a background thread, with a Recorder attached to that node (its
subscriptions are taken in batches by the Recorder's own thread, not by that executor).

Throughput: a publisher process (paced_publisher.py) sends serialized sensor_msgs/JointState at a
rising series of rates (reliable, keep last 10: cam_node's state QoS) to three hosts in turn, one
recording, two with a bare raw subscription that only counts, each until it no longer receives
KEPT_FRACTION of a rate's messages; the figure is the most messages written per second at any
rate, i.e. the capacity seen at the first rate not kept. The reference is the bare subscription
taken in batches like the Recorder's ('drain': the Recorder without writing); the other bare
subscription has one executor callback per message ('bare', rclpy's usual way), reported beside.
(A flood instead of a schedule overloads rclpy's executor and measures its collapse, not its
capacity.)

Overhead: the host's main thread publishes JointState messages shaped like cam_node's state
message on the node's ~/joint_states at a fixed rate, in alternating rounds with nothing
subscribed, with the two bare raw subscriptions and with the node's recording switch on
(recording.enabled: its Recorder takes the node's topics in the node's process and writes them in
a writer process); the figure is the mean time of one build-and-publish with recording on, the
reference the same with nothing subscribed.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
import time

from benchmarks.report import Figure, Target
from benchmarks.ros import DEFAULT_CONFIG, RosGraph, ServerProcess

#: The issue's targets: >= 20,000 messages/s recorded; publishing at most 10 % slower.
THROUGHPUT_TARGET = Target('>=', 20000.0, on='value')
OVERHEAD_TARGET = Target('<=', 1.05)  # issue 28 (1.10 before)
#: Issue 28: the recorder writes every message offered at 2 kHz (ratio written / published).
NO_DROP_TARGET = Target('>=', 1.0)
#: Seconds the written count must stay unchanged after a publisher ends (the intake's last take).
SETTLE_S = 0.3
#: A rate is kept when at least this fraction of its messages is written.
KEPT_FRACTION = 0.999
#: Offers of a rate to a sink before its sweep ends there: a stall of the shared machine gets a
#: second chance, a rate beyond the sink's capacity fails both.
OFFERS = 2
HOST = 'benchmarks.recording_host'
#: The throughput sinks: bare raw subscriptions (one callback per message; taken in batches, the
#: reference) and a Recorder.
SINKS = ('bare', 'drain', 'recorder')
LABELS = {'bare': 'per-message', 'drain': 'batched', 'recorder': 'recorder'}


@dataclass(frozen=True)
class RecordingSizes:
    """How much to measure: rates offered, for how long, in how many sweeps; the publish loop."""

    rates_hz: tuple[float, ...] = (1000.0, 2000.0, 3000.0, 4000.0, 5000.0, 6000.0, 8000.0,
                                   10000.0, 15000.0, 20000.0, 30000.0, 40000.0, 50000.0,
                                   60000.0)
    rate_seconds: float = 2.0
    sweep_rounds: int = 2
    loop_rate_hz: float = 1000.0
    loop_seconds: float = 1.5
    loop_rounds: int = 3
    drop_rate_hz: float = 2000.0
    drop_seconds: float = 10.0


def start_host(graph: RosGraph, name: str, *args: str) -> ServerProcess:
    """Start a recording host (a cam_node on the default config) with piped input and output."""
    return graph.start(HOST, name, *args, ros_args=('--params-file', str(DEFAULT_CONFIG)),
                       pipe=True)


def kept(step: dict[str, float]) -> bool:
    """Return whether a sweep step's messages arrived (at least KEPT_FRACTION of them)."""
    return step['received'] >= KEPT_FRACTION * step['published']


def offer(graph: RosGraph, host: ServerProcess, topic: str, rate_hz: float,
          seconds: float) -> dict[str, float]:
    """Publish to topic at rate_hz for seconds from a new process; return what host received."""
    publisher = graph.start('benchmarks.paced_publisher', f'{host.name}_at_{rate_hz:.0f}', topic,
                            str(rate_hz), str(seconds), pipe=True)
    publisher.ask()  # matched the host's subscription
    if not host.ask('matched')['matched']:
        raise RuntimeError(f'{host.name} never matched {publisher.name}:\n{host.log()}')
    before = host.ask('count')
    sent = publisher.ask('go')
    publisher.stop()
    after = host.ask('count')
    received = after['count'] - before['count']
    return {'rate_hz': rate_hz, 'published': sent['published'], 'seconds': sent['seconds'],
            'received': received,
            'cpu_us_per_message': 1e6 * (after['cpu_s'] - before['cpu_s']) / max(received, 1)}


def sweep(graph: RosGraph, hosts: dict[str, ServerProcess],
          sizes: RecordingSizes) -> dict[str, list[dict[str, float]]]:
    """Offer each rate to each sink in turn, each until a rate is not kept in OFFERS offers."""
    steps: dict[str, list[dict[str, float]]] = {mode: [] for mode in SINKS}
    ended: set[str] = set()
    for rate in sizes.rates_hz:
        for mode in [mode for mode in SINKS if mode not in ended]:
            for _ in range(OFFERS):
                steps[mode].append(offer(graph, hosts[mode], f'/bench/{mode}', rate,
                                         sizes.rate_seconds))
                if kept(steps[mode][-1]):
                    break
            else:
                ended.add(mode)
    return steps


def settled_count(host: ServerProcess) -> int:
    """Return host's count once it has stopped growing for SETTLE_S (at most 10 x that)."""
    count = host.ask('count')['count']
    for _ in range(10):
        time.sleep(SETTLE_S)
        latest = host.ask('count')['count']
        if latest == count:
            break
        count = latest
    return int(count)


def drops(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> Figure:
    """Figure 4c: messages a Recorder writes of those published at drop_rate_hz (no drop: 1)."""
    host = start_host(graph, 'drop_recorder', 'sink', 'recorder', '/bench/drops',
                      str(workdir / 'drops.mcap'))
    host.ask()  # ready
    rate = sizes.drop_rate_hz
    publisher = graph.start('benchmarks.paced_publisher', f'drops_at_{rate:.0f}', '/bench/drops',
                            str(rate), str(sizes.drop_seconds), pipe=True)
    publisher.ask()  # matched the host's subscription
    if not host.ask('matched')['matched']:
        raise RuntimeError(f'{host.name} never matched {publisher.name}:\n{host.log()}')
    before = host.ask('count')['count']
    sent = publisher.ask('go')
    publisher.stop()
    written = settled_count(host) - before
    host.stop()
    return Figure(
        f'recorder_written_at_{rate:.0f}_hz', f'Recorder at {rate:,.0f} msg/s, messages written',
        written, 'msg', 'published', sent['published'], NO_DROP_TARGET,
        f'A publisher process sends serialized JointState (reliable, keep last 10) at {rate:g} '
        f'msg/s for {sizes.drop_seconds:g} s to a Recorder on a cam_node (zstd, 64 KiB chunks); '
        f'written: what the Recorder accepted once its count settled; ratio 1: nothing dropped '
        f'({sent["published"] - written:,} missing).',
        extra={'missing': sent['published'] - written, 'seconds': sent['seconds']})


def throughput(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> Figure:
    """Figure 4a: messages per second a Recorder writes, against a bare subscription."""
    hosts = {mode: start_host(graph, f'sink_{mode}', 'sink', mode, f'/bench/{mode}',
                              str(workdir / f'{mode}.mcap')) for mode in SINKS}
    for host in hosts.values():
        host.ask()  # ready
    rounds = [sweep(graph, hosts, sizes) for _ in range(sizes.sweep_rounds)]
    for host in hosts.values():
        host.stop()
        if host.process.returncode != 0:
            raise RuntimeError(f'{host.name} exited with {host.process.returncode}:\n'
                               f'{host.log()}')
    capacity = {mode: [max(step['received'] / step['seconds'] for step in steps[mode])
                       for steps in rounds] for mode in SINKS}
    offered = sorted({step['rate_hz'] for steps in rounds for values in steps.values()
                      for step in values})
    unbounded = [LABELS[mode] for mode in SINKS
                 if any(kept(steps[mode][-1]) for steps in rounds)]
    top = (f'; {", ".join(unbounded)} kept every rate: a lower bound there' if unbounded else '')
    listed = {mode: ', '.join(f'{value:,.0f}' for value in capacity[mode]) for mode in SINKS}
    return Figure(
        'recorder_messages_per_s', f'Recorder, JointState to MCAP, best of {len(rounds)}',
        max(capacity['recorder']), 'msg/s', 'bare raw subscription, batched takes',
        max(capacity['drain']), THROUGHPUT_TARGET,
        f'A publisher process sends serialized JointState (reliable, keep last 10) for '
        f'{sizes.rate_seconds:g} s at each of {", ".join(f"{rate:g}" for rate in offered)} msg/s '
        f'to each sink in turn, until a rate is not kept (>= {KEPT_FRACTION:.1%} written) in '
        f'{OFFERS} offers of it (a stall of the machine gets another); capacity: the '
        f'most messages written per second at any rate (at the first rate not kept){top}. '
        f'Sinks, each on a cam_node in a process of its own (SingleThreadedExecutor thread): a '
        f'Recorder (zstd, 64 KiB chunks; its thread takes the messages in batches); '
        f'reference: a bare raw subscription taken the same way, only counted; beside it a bare '
        f'raw subscription with one executor callback per message: {max(capacity["bare"]):,.0f} '
        f'msg/s. Best of {len(rounds)} sweeps: '
        + '; '.join(f'{LABELS[mode]} {listed[mode]}' for mode in SINKS) + ' msg/s.',
        extra={'rounds': rounds, 'per_message_callback_msg_per_s': max(capacity['bare'])})


def overhead(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> Figure:
    """Figure 4b: mean build-and-publish time with a Recorder on the node vs without."""
    count = max(1, round(sizes.loop_rate_hz * sizes.loop_seconds))
    host = start_host(graph, 'publish_loop', 'loop', '~/joint_states',
                      str(workdir / 'loop_recordings'), str(sizes.loop_rate_hz), str(count),
                      str(sizes.loop_rounds))
    result = host.ask()
    host.stop()
    return Figure(
        'recording_publish_overhead', 'Publish loop with recording on', result['on']['mean_us'],
        'us', 'recording off', result['off']['mean_us'], OVERHEAD_TARGET,
        f'In the cam_node host process, the main thread builds and publishes JointState (like '
        f'cam_node\'s state message) on the node\'s ~/joint_states at {sizes.loop_rate_hz:g} Hz '
        f'for {sizes.loop_seconds:g} s, {sizes.loop_rounds} rounds each of: nothing subscribed '
        f'(off), a bare raw subscription on the same node with a callback per message '
        f'({result["bare"]["mean_us"]:.1f} us) or taken in batches like the Recorder\'s '
        f'({result["drain"]["mean_us"]:.1f} us: what any reader in the process costs publish()), '
        f'a reader in a process of its own, as `ros2 bag record` is '
        f'({result["remote"]["mean_us"]:.1f} us: what an out-of-process recorder would cost it), '
        f'the node\'s recording switch on (on: recording.enabled true; the Recorder takes the '
        f'messages in the node\'s process and a writer process serialises, compresses and writes '
        f'them; {result["recorded_fraction"]:.2%} of the loop\'s messages in the files); mean '
        f'time per message. Process CPU per message: {result["off"]["cpu_us"]:.0f} us off, '
        f'{result["bare"]["cpu_us"]:.0f} us per-message, {result["drain"]["cpu_us"]:.0f} us '
        f'batched, {result["remote"]["cpu_us"]:.0f} us remote, {result["on"]["cpu_us"]:.0f} us '
        f'on (the writer process and the remote reader not included).',
        extra=result)


def recording_figures(graph: RosGraph, workdir: Path, sizes: RecordingSizes) -> list[Figure]:
    """Figure 4: recorder throughput, no drop at 2 kHz and publish-loop overhead."""
    return [throughput(graph, workdir, sizes), drops(graph, workdir, sizes),
            overhead(graph, workdir, sizes)]
