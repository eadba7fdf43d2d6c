"""A partition: the link is down for 10 s and comes back.

The node keeps serving clients on its own host during the cut, the remote client is answered
again soon after the heal, and the node's own recording loses nothing.
"""
from __future__ import annotations

import time

from cam_ros.recording import open_recording

from .support import recorded_stamps

CUT_S = 10.0
HEAL_ANSWER_LIMIT_S = 5.0
LOCAL_CALLS = 200  # spread over the cut
STATE_RATE_HZ = 50.0


def test_the_node_serves_locally_through_a_partition_and_remotely_after_it(
        heavy, network, report):
    folder = network.folder / 'runs'
    node = network.start_node(network.a, '-p', f'output.state_rate_hz:={STATE_RATE_HZ}',
                              '-p', 'recording.enabled:=true',
                              '-p', f'recording.directory:={folder}')
    local = network.client(network.a)
    remote = network.client(network.b)
    local.ask('stamps')

    network.a.set_link(False)
    cut_at = time.monotonic()
    during = local.ask('calls', count=LOCAL_CALLS, timeout=1.0)
    cut_off = remote.ask('first_answer', within=1.0)
    time.sleep(max(0.0, CUT_S - (time.monotonic() - cut_at)))
    network.a.set_link(True)
    healed_at = time.monotonic()
    network.link.wait_up()
    answer = remote.ask('first_answer', within=30.0)['seconds']
    healed = None if answer is None else time.monotonic() - healed_at
    after = remote.ask('calls', count=20, timeout=1.0)
    witnessed = local.ask('stamps')['stamps_ns']
    assert node.stop() == 0, node.log()

    assert (during['failures'], during['wrong']) == ([], 0), during
    assert cut_off['seconds'] is None, 'the cut let a remote call through'
    assert healed is not None and healed <= HEAL_ANSWER_LIMIT_S, (healed, node.log())
    assert (after['failures'], after['wrong']) == ([], 0), after
    recording = open_recording(next(folder.glob('*.mcap')))
    kept = recorded_stamps(recording, '/cam/joint_states')
    inside = [stamp for stamp in witnessed if kept[0] <= stamp <= kept[-1]]
    assert set(inside) <= set(kept), len(set(inside) - set(kept))
    assert len(inside) >= 0.9 * STATE_RATE_HZ * CUT_S  # the comparison covers the cut
    report('partition', f'link down {CUT_S:g} s; local calls during the cut answered: '
                        f'{len(during["latencies_s"])} of {LOCAL_CALLS}')
    report('remote answered after the link came back up (s)', round(healed, 2))
    report('joint_states during the run: local witness / in the recording',
           f'{len(inside)} / {len(kept)}')
