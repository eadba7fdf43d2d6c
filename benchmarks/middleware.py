"""
What the shipped Fast DDS profile (config/fastdds.xml) costs on a clean link.

``python -m benchmarks.middleware`` (root: it uses network namespaces) runs two copies of the
same system side by side, each on its own pair of "hosts" (network namespaces joined by a veth
link, as in test/network): cam_node (50 Hz state topics) on one; on the other a client process
that subscribes to the joint states and makes one-angle calls through CamClient. One copy uses
the shipped profile, the other Fast DDS's defaults (a profile file without default profiles).
Calls alternate between the two in blocks, so drift on a shared machine hits both alike.
Measured: round trips (p50, p99), CPU time of node and client and bytes on the link per call,
and the same per second when idle (state topics only).
Writes benchmarks/middleware_results.md and .json.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path

from benchmarks.netns import Link
from benchmarks.report import Figure, machine, write_results
from benchmarks.ros import BENCH_DIR, DEFAULT_CONFIG, REPO
from benchmarks.timing import cpu_seconds, percentile_ms
from cam_ros.paths import fastdds_profile_path

READY_TIMEOUT_S = 90.0
DEFAULTS_XML = ('<?xml version="1.0" encoding="UTF-8"?>\n'
                '<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">'
                '<profiles><participant profile_name="fast_dds_defaults"/></profiles></dds>\n')


@dataclass(frozen=True)
class ProfileSizes:
    """How much to measure (the defaults are the published run's)."""

    calls: int = 3000  # per copy
    block: int = 250  # calls in a row before the other copy's turn
    idle_s: float = 10.0


@dataclass
class Copy:
    """One copy of the system: two hosts, the node on one and the client on the other."""

    link: Link
    node: subprocess.Popen
    client: subprocess.Popen

    def cpu_s(self) -> float:
        """Return the CPU time (user + system) node and client used so far."""
        return cpu_seconds(self.node.pid) + cpu_seconds(self.client.pid)

    def link_bytes(self) -> int:
        """Return the bytes sent over the link (both ways) so far."""
        return self.link.a.sent_bytes() + self.link.b.sent_bytes()

    def calls(self, count: int) -> list[int]:
        """Make count timed calls; return their round trips in ns."""
        self.client.stdin.write(f'{count}\n')
        self.client.stdin.flush()
        return json.loads(self.client.stdout.readline())

    def stop(self) -> None:
        """Stop client and node."""
        self.client.stdin.close()
        self.client.wait(READY_TIMEOUT_S)
        self.node.send_signal(2)
        self.node.wait(READY_TIMEOUT_S)


def start_copy(link: Link, profile: str, workdir: Path) -> Copy:
    """Start the node on link.a and the client on link.b with the given profile file."""
    env = dict(os.environ, FASTRTPS_DEFAULT_PROFILES_FILE=profile, ROS_DOMAIN_ID='0',
               ROS_AUTOMATIC_DISCOVERY_RANGE='SUBNET')
    with open(workdir / f'{link.a.namespace}.log', 'wb') as log:
        node = subprocess.Popen(link.a.command(sys.executable, '-m', 'cam_ros.node', '--ros-args',
                                               '--params-file', str(DEFAULT_CONFIG)),
                                env=env, cwd=workdir, stdout=log, stderr=subprocess.STDOUT)
    client = subprocess.Popen(link.b.command(sys.executable, '-m', 'benchmarks.middleware_client'),
                              env=env, cwd=REPO, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                              text=True)
    copy = Copy(link, node, client)
    if json.loads(client.stdout.readline() or 'null') != {'ready': True}:
        raise RuntimeError(f'{link.a.namespace}: no first answer')
    return copy


def measure(copies: dict[str, Copy], sizes: ProfileSizes) -> dict[str, dict]:
    """Alternating call blocks, then an idle phase; return the raw numbers of each copy."""
    raw = {name: {'round_trips': [], 'call_cpu_s': 0.0, 'call_bytes': 0} for name in copies}
    for copy in copies.values():
        copy.calls(sizes.block)  # warm-up
    while len(raw['shipped']['round_trips']) < sizes.calls:
        for name, copy in copies.items():
            cpu, sent = copy.cpu_s(), copy.link_bytes()
            raw[name]['round_trips'] += copy.calls(sizes.block)
            raw[name]['call_cpu_s'] += copy.cpu_s() - cpu
            raw[name]['call_bytes'] += copy.link_bytes() - sent
    before = {name: (copy.cpu_s(), copy.link_bytes()) for name, copy in copies.items()}
    time.sleep(sizes.idle_s)
    for name, copy in copies.items():
        raw[name]['idle_cpu_s'] = copy.cpu_s() - before[name][0]
        raw[name]['idle_bytes'] = copy.link_bytes() - before[name][1]
    return raw


def figures(raw: dict[str, dict], sizes: ProfileSizes) -> list[Figure]:
    """Turn the raw numbers into figures: the shipped profile over Fast DDS's defaults."""
    ours, base = raw['shipped'], raw['defaults']
    calls = len(ours['round_trips'])
    how = (f'{calls} one-angle calls through CamClient per copy, alternating blocks of '
           f'{sizes.block}; both copies (cam_node 50 Hz on one host, the client on another, '
           'joined by a veth link) run at once; reference: the same with Fast DDS defaults.')
    idle_s = sizes.idle_s
    idle = (f'Over {idle_s:g} s after the calls: the 50 Hz joint_states to the client (which '
            'subscribes), discovery and heartbeats only; node and client processes.')
    per_call = {key: {name: raw[name][key] / calls for name in raw}
                for key in ('call_cpu_s', 'call_bytes')}
    return [
        Figure('profile_p50_ms', 'Shipped profile: call p50',
               percentile_ms(ours['round_trips'], 50), 'ms', 'Fast DDS defaults',
               percentile_ms(base['round_trips'], 50), note=how),
        Figure('profile_p99_ms', 'Shipped profile: call p99',
               percentile_ms(ours['round_trips'], 99), 'ms', 'Fast DDS defaults',
               percentile_ms(base['round_trips'], 99)),
        Figure('profile_call_cpu_ms', 'Shipped profile: CPU per call (node + client)',
               1e3 * per_call['call_cpu_s']['shipped'], 'ms', 'Fast DDS defaults',
               1e3 * per_call['call_cpu_s']['defaults']),
        Figure('profile_call_bytes', 'Shipped profile: bytes on the link per call',
               per_call['call_bytes']['shipped'], 'B', 'Fast DDS defaults',
               per_call['call_bytes']['defaults']),
        Figure('profile_idle_cpu_percent', 'Shipped profile: idle CPU (node + client)',
               100 * ours['idle_cpu_s'] / idle_s, '%', 'Fast DDS defaults',
               100 * base['idle_cpu_s'] / idle_s, note=idle),
        Figure('profile_idle_bytes_per_s', 'Shipped profile: idle bytes on the link',
               ours['idle_bytes'] / idle_s, 'B/s', 'Fast DDS defaults',
               base['idle_bytes'] / idle_s),
    ]


def benchmark(sizes: ProfileSizes, json_path: Path, markdown_path: Path) -> str:
    """Run both copies side by side, write the results and return the table."""
    start = time.perf_counter()
    links: dict[str, Link] = {}
    copies: dict[str, Copy] = {}
    with tempfile.TemporaryDirectory(prefix='cam_ros_bench_') as folder:
        workdir = Path(folder)
        defaults = workdir / 'defaults.xml'
        defaults.write_text(DEFAULTS_XML)
        profiles = {'shipped': str(fastdds_profile_path()), 'defaults': str(defaults)}
        try:
            for name, profile in profiles.items():
                links[name] = Link(f'cb{os.getpid()}{name[0]}')
                copies[name] = start_copy(links[name], profile, workdir)
            raw = measure(copies, sizes)
            for copy in copies.values():
                copy.stop()
        finally:
            for copy in copies.values():
                for process in (copy.client, copy.node):
                    if process.poll() is None:
                        process.kill()
            for link in links.values():
                link.remove()
    header = {'date': datetime.now(timezone.utc).isoformat(timespec='seconds'),
              'machine': machine(), 'config': str(DEFAULT_CONFIG.relative_to(REPO)),
              'run_time_s': round(time.perf_counter() - start, 1)}
    return write_results(figures(raw, sizes), header, json_path, markdown_path)


def main() -> int:
    """Run the published measurement and print the table."""
    print(benchmark(ProfileSizes(), BENCH_DIR / 'middleware_results.json',
                    BENCH_DIR / 'middleware_results.md'))
    return 0


if __name__ == '__main__':
    sys.exit(main())
