"""cam_node on one host, its users on another: calls, echo, parameter updates, a recording."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cam_ros.recording import open_recording

from .support import design_with, recorded_stamps

RECORD_S = 3.0
STATE_RATE_HZ = 50.0
PERIOD_TOLERANCE = 0.1


def test_a_node_on_another_host_serves_calls_echo_updates_and_recording(network):
    node = network.start_node(network.a)
    client = network.client(network.b)
    angles_deg = [100.0, 130.0, 250.0]

    result = network.cam_ros(network.b, 'call', *map(str, angles_deg), '--deg', '--json')
    assert result.returncode == 0, (result.stderr, node.log())
    answer = json.loads(result.stdout)
    expected = design_with().evaluate(np.radians(angles_deg))
    for field in ('position', 'velocity', 'pressure_angle', 'radius_of_curvature'):
        np.testing.assert_array_equal(answer[field], getattr(expected, field), err_msg=field)

    result = network.cam_ros(network.b, 'echo', '/cam/joint_states', '--count', '3',
                             '--csv', '--timeout', '30')
    assert result.returncode == 0, result.stderr
    assert len(result.stdout.splitlines()) == 4  # header and 3 rows

    calls = client.ask('calls', count=20, timeout=2.0)
    assert (len(calls['latencies_s']), calls['failures'], calls['wrong']) == (20, [], 0), calls
    faster = 2 * math.tau
    updated = client.ask('set', name='cam_speed', value=faster)
    assert updated == {'successful': True, 'reason': ''}
    result = network.cam_ros(network.b, 'call', '100', '--deg', '--json')
    assert result.returncode == 0, result.stderr
    np.testing.assert_array_equal(json.loads(result.stdout)['velocity'],
                                  design_with(cam_speed=faster).evaluate(
                                      np.radians([100.0])).velocity)
    refused = client.ask('set', name='follower.base_radius', value=-1.0)
    assert refused['successful'] is False and 'follower.base_radius' in refused['reason']

    path = network.folder / 'remote.mcap'
    witnessed = client.ask('record', path=str(path), seconds=RECORD_S)['stamps_ns']
    recording = open_recording(path)
    assert recording.complete
    kept = recorded_stamps(recording, '/cam/joint_states')
    low, high = max(witnessed[0], kept[0]), min(witnessed[-1], kept[-1])
    assert [s for s in kept if low <= s <= high] == [s for s in witnessed if low <= s <= high]
    # The recording ran at the node's rate, by its messages' own stamps (a loaded host's late
    # timer skips a period now and then; it never shifts the typical interval).
    assert len(kept) > 1 and np.median(np.diff(kept)) * 1e-9 == pytest.approx(
        1.0 / STATE_RATE_HZ, rel=PERIOD_TOLERANCE), np.diff(kept)
    assert len(list(recording.messages(['/cam/profile']))) == 1  # latched: the current one
    assert node.stop() == 0, node.log()
