"""Networks that drop multicast: with ROS_STATIC_PEERS discovery and calls still work."""
from __future__ import annotations

import json

import numpy as np
import pytest

from .support import design_with

MULTICAST = 'ip daddr 224.0.0.0/4'
NO_DISCOVERY_WAIT_S = 5.0


@pytest.mark.usefixtures('nft')
def test_static_peers_find_the_node_when_multicast_is_dropped(heavy, network, report):
    network.a.drop(MULTICAST)
    network.b.drop(MULTICAST)
    node = network.start_node(network.a)
    blind = network.cam_ros(network.b, 'call', '1', '--timeout', str(NO_DISCOVERY_WAIT_S))
    assert blind.returncode == 1 and 'is not available' in blind.stderr, blind.stderr

    # The client names the node's host ...
    peers = dict(network.env, ROS_STATIC_PEERS=network.a.address)
    result = network.cam_ros(network.b, 'call', '100', '--deg', '--json', env=peers)
    assert result.returncode == 0, (result.stderr, node.log())
    np.testing.assert_array_equal(json.loads(result.stdout)['position'],
                                  design_with().evaluate(np.radians([100.0])).position)
    echo = network.cam_ros(network.b, 'echo', '/cam/joint_states', '--count', '3',
                           '--timeout', '30', env=peers)
    assert echo.returncode == 0, echo.stderr
    client = network.client(network.b, env=peers)
    calls = client.ask('calls', count=50, timeout=1.0)
    assert (len(calls['latencies_s']), calls['failures'], calls['wrong']) == (50, [], 0), calls
    client.close()
    assert node.stop() == 0, node.log()

    # ... or the node names the client's.
    node = network.start_node(network.a, env=dict(network.env,
                                                  ROS_STATIC_PEERS=network.b.address))
    result = network.cam_ros(network.b, 'call', '100', '--deg', '--json')
    assert result.returncode == 0, (result.stderr, node.log())
    report('multicast dropped', f'without static peers: "{blind.stderr.strip()}"; with them: '
                                f'call, echo and 50 of 50 calls answered; first answer after '
                                f'{client.ready["first_answer_s"]:.2f} s')
