"""Middleware set-up shared by cam_node and the cam_ros commands: the shipped Fast DDS profile.

Fast DDS reads its XML profiles once per process, when the first DDS participant is created, from
the file named by FASTRTPS_DEFAULT_PROFILES_FILE (FASTDDS_DEFAULT_PROFILES_FILE in Fast DDS 3).
So the variable must be set before rclpy.init() and before any other rclpy context in the process.

cam_node also leaves out Fast DDS's shared-memory transport (serve_over_udp). Fast DDS 2.14
(Jazzy's) deadlocks a participant's whole output when it sends to the shared-memory port of a
process killed while that process was taking a message from it (eProsima/Fast-DDS#6485, fix
pending in #6497): one crashed client would silence the node for good. Over UDP a dead peer's
port is a closed socket. rmw_fastrtps always adds shared memory under
ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, so for that range the node asks rmw for Fast DDS's
system default and the profile says what LOCALHOST means: no multicast, peers 127.0.0.1 and
ROS_STATIC_PEERS.

The node's participant also announces itself every ANNOUNCEMENT_PERIOD_S instead of Fast DDS's
3 s. A new participant (a `cam_ros` command) announces itself before it listens (Fast DDS 2.14,
RTPSParticipantImpl::enable: the builtin protocols, then "Start reception"); when the node's
immediate answer comes in that gap, the newcomer learns of the node only from the node's next
periodic announcement, and the node takes the newcomer's further announcements for repeats.
Measured: 16 of 56 new participants waited 0.7-2.7 s for the node on a loaded machine
(docs/cli.md).
"""
from __future__ import annotations

import hashlib
import os
import socket
import tempfile
from pathlib import Path
from typing import MutableMapping

from cam_ros.core.errors import CamError
from cam_ros.paths import fastdds_profile_path

PROFILE_VARIABLES = ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE')
RANGE_VARIABLE = 'ROS_AUTOMATIC_DISCOVERY_RANGE'
#: Participants one host's UDP discovery probes, as rmw_fastrtps sets it for LOCALHOST.
LOCAL_PARTICIPANTS = 32
UDP_TRANSPORT = f'''    <transport_descriptors>
      <transport_descriptor>
        <transport_id>cam_ros_udp</transport_id>
        <type>UDPv4</type>
        <maxInitialPeersRange>{LOCAL_PARTICIPANTS}</maxInitialPeersRange>
      </transport_descriptor>
    </transport_descriptors>
'''
#: How often the node announces itself to the other participants (Fast DDS: 3 s), see above.
ANNOUNCEMENT_PERIOD_S = 0.25
PARTICIPANT = f'''    <participant profile_name="cam_ros_participant" is_default_profile="true">
      <rtps>
        <builtin>
          <discovery_config>
            <leaseAnnouncement>
              <sec>0</sec>
              <nanosec>{round(ANNOUNCEMENT_PERIOD_S * 1e9)}</nanosec>
            </leaseAnnouncement>
          </discovery_config>
{{localhost}}        </builtin>
        <userTransports><transport_id>cam_ros_udp</transport_id></userTransports>
        <useBuiltinTransports>false</useBuiltinTransports>
      </rtps>
    </participant>
'''
LOCALHOST_DISCOVERY = '''          <metatrafficUnicastLocatorList>
            <locator><udpv4/></locator>
          </metatrafficUnicastLocatorList>
          <initialPeersList>
{peers}          </initialPeersList>
'''
PEER = '            <locator><udpv4><address>{}</address></udpv4></locator>\n'


def use_shipped_profile(environ: MutableMapping[str, str] = os.environ) -> None:
    """Point Fast DDS at config/fastdds.xml unless the user chose a profile."""
    if not _user_chose_profile(environ):
        environ[PROFILE_VARIABLES[0]] = str(fastdds_profile_path())


def serve_over_udp(environ: MutableMapping[str, str] = os.environ) -> None:
    """
    Give this process the shipped profile with a UDP-only participant (cam_node; see above).

    A user who set either profile variable keeps it, shared memory and all. Raises CamError for a
    static peer that does not resolve (as rmw_fastrtps refuses it) or an unwritable temp folder.
    """
    if _user_chose_profile(environ):
        return
    localhost = ''
    localhost_only = environ.get('ROS_LOCALHOST_ONLY') == '1'  # rcl: prevails, no static peers
    if localhost_only or _discovery_range(environ) == 'LOCALHOST':
        given = [] if localhost_only else environ.get('ROS_STATIC_PEERS', '').split(';')
        peers = ['127.0.0.1'] + [_ipv4(peer) for peer in given if peer.strip()]
        localhost = LOCALHOST_DISCOVERY.format(peers=''.join(PEER.format(peer) for peer in peers))
        environ[RANGE_VARIABLE] = 'SYSTEM_DEFAULT'
        environ.pop('ROS_LOCALHOST_ONLY', None)
    shipped = fastdds_profile_path().read_text()
    profile = shipped.replace('  <profiles>\n', '  <profiles>\n' + UDP_TRANSPORT + PARTICIPANT
                              .format(localhost=localhost), 1)
    environ[PROFILE_VARIABLES[0]] = str(_written(profile))


def _user_chose_profile(environ: MutableMapping[str, str]) -> bool:
    """Return whether the user set either profile variable (even to '')."""
    return any(name in environ for name in PROFILE_VARIABLES)


def _discovery_range(environ: MutableMapping[str, str]) -> str:
    """Return the discovery range rcl reads from the environment (an unknown value: LOCALHOST)."""
    chosen = environ.get(RANGE_VARIABLE, '')
    if not chosen:
        return 'SUBNET'
    return chosen if chosen in ('OFF', 'LOCALHOST', 'SUBNET', 'SYSTEM_DEFAULT') else 'LOCALHOST'


def _ipv4(peer: str) -> str:
    """Return a static peer's first IPv4 address, as rmw_fastrtps resolves it."""
    try:
        return socket.gethostbyname(peer.strip())
    except OSError as err:
        raise CamError(f'ROS_STATIC_PEERS: cannot resolve {peer.strip()!r} ({err})') from None


def _written(profile: str) -> Path:
    """Write profile to a file named by its content, shared by the nodes that need it (a file
    of that name with other content, in a temp folder others can write, is replaced)."""
    digest = hashlib.sha256(profile.encode()).hexdigest()[:16]
    path = Path(tempfile.gettempdir()) / f'cam_ros_fastdds_{digest}.xml'
    if not (path.is_file() and path.read_bytes() == profile.encode()):
        try:
            with tempfile.NamedTemporaryFile('w', dir=path.parent, delete=False,
                                             suffix='.xml') as partial:
                partial.write(profile)
            os.replace(partial.name, path)
        except OSError as err:
            raise CamError(f'cannot write the Fast DDS profile to {path.parent}: {err}') from None
    return path
