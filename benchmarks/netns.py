"""Two "hosts" on one machine: network namespaces joined by a veth link, with nftables faults.

Used by the network tests (test/network) and the middleware benchmark.

Every name carries the creating process's id, addresses are private 10.x addresses that exist
only inside these namespaces, and Link.remove() deletes everything (the veth pair goes with its
namespaces), so the machine's own interfaces and firewall are never touched.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import time
from dataclasses import dataclass

SUBNET = '10.77.0'
PREFIX_LENGTH = 24
LOSS_TABLE = 'cam_ros_test'
LINK_UP_TIMEOUT_S = 10.0  # a new veth pair takes about 1 s to come up


def run(*command: str) -> None:
    """Run an administration command; fail with its output."""
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode:
        raise OSError(f'{" ".join(command)}: exit {result.returncode}: '
                      f'{result.stderr.strip() or result.stdout.strip()}')


@dataclass(frozen=True)
class Host:
    """One side of the link: a network namespace with one veth end and an address."""

    namespace: str
    device: str
    address: str

    def command(self, *args: str) -> list[str]:
        """Return a command line that runs args inside this host."""
        return ['ip', 'netns', 'exec', self.namespace, *args]

    def nft(self, script: str) -> None:
        """Apply an nftables script in this host."""
        run(*self.command('nft', script))

    def drop(self, rule: str) -> None:
        """Drop incoming packets of the veth matching rule (nftables syntax, '' for all)."""
        self.nft(f'add table inet {LOSS_TABLE}; '
                 f'add chain inet {LOSS_TABLE} input {{ type filter hook input priority 0; }}; '
                 f'add rule inet {LOSS_TABLE} input iifname {self.device} {rule} drop')

    def lose(self, percent: int) -> None:
        """Drop a random percent of the packets arriving over the link."""
        self.drop(f'numgen random mod 100 < {percent}')

    def heal(self) -> None:
        """Remove every drop rule."""
        self.nft(f'delete table inet {LOSS_TABLE}')

    def set_link(self, up: bool) -> None:
        """Bring this host's end of the link down (a partition) or up again."""
        run(*self.command('ip', 'link', 'set', self.device, 'up' if up else 'down'))

    def sent_bytes(self) -> int:
        """Return the bytes this host sent over the link so far."""
        return int(subprocess.run(
            self.command('cat', f'/sys/class/net/{self.device}/statistics/tx_bytes'),
            capture_output=True, text=True, check=True).stdout)

    def link_is_up(self) -> bool:
        """Return whether this host's end of the link carries traffic (operstate up)."""
        state = subprocess.run(self.command('cat', f'/sys/class/net/{self.device}/operstate'),
                               capture_output=True, text=True).stdout
        return state.strip() == 'up'


class Link:
    """Two hosts, a and b, joined by a veth pair; remove() undoes everything."""

    def __init__(self, tag: str = f'camt{os.getpid()}'):
        self.a = Host(f'{tag}a', f'{tag}a', f'{SUBNET}.1')
        self.b = Host(f'{tag}b', f'{tag}b', f'{SUBNET}.2')
        try:
            for host in (self.a, self.b):
                run('ip', 'netns', 'add', host.namespace)
            run('ip', 'link', 'add', self.a.device, 'netns', self.a.namespace, 'type', 'veth',
                'peer', 'name', self.b.device, 'netns', self.b.namespace)
            for host in (self.a, self.b):
                run(*host.command('ip', 'address', 'add', f'{host.address}/{PREFIX_LENGTH}',
                                  'dev', host.device))
                run(*host.command('ip', 'link', 'set', 'lo', 'up'))
                host.set_link(True)
            self.wait_up()
        except BaseException:
            self.remove()
            raise

    def wait_up(self) -> None:
        """Wait until both ends are up: DDS only uses interfaces that are up when it starts."""
        deadline = time.monotonic() + LINK_UP_TIMEOUT_S
        while not (self.a.link_is_up() and self.b.link_is_up()):
            if time.monotonic() > deadline:
                raise OSError(f'link {self.a.device}-{self.b.device} not up in '
                              f'{LINK_UP_TIMEOUT_S} s')
            time.sleep(0.05)

    def remove(self) -> None:
        """Delete both namespaces (and with them the veth pair and any rules)."""
        for host in (self.a, self.b):
            subprocess.run(['ip', 'netns', 'delete', host.namespace], capture_output=True)


def missing_tool(*tools: str) -> str:
    """Return the first of tools not on PATH, or ''."""
    return next((tool for tool in tools if shutil.which(tool) is None), '')
