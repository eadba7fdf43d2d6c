"""A run engaged through ~/engage replays: the calls are recorded and made again in place.

A real node, started disengaged with slave.state_topic, is recorded while the test engages it
(ramp from the axis's reported position) and disengages it (the line shaft stops on the cam)
on a 250 Hz master. `cam_ros replay
FILE` (no options) publishes the master and the slave's state, makes both ~/engage calls before
the master message after the one the recorded node had followed, and publishes none of the
node's outputs: a stand-in for the node hears the calls at those stamps and nothing on the
outputs (with --outputs, the recorded outputs). Replayed into a fresh node the run gives the
recorded commands, by master stamp (for the messages both nodes took: each may skip a backlog),
outside the engagement's move and catch-up (see the end of the test).
"""
from __future__ import annotations

import math
import signal
import subprocess
import sys
import threading
import time

import numpy as np
from conftest import CONFIG_DIR
from ecam_support import constant_speed, engage, MasterLink, seed_000_follower, stamp_of, WAIT_S
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool
from test_node import Inbox

from cam_ros_interfaces.msg import EngageRequest
from cam_ros.core.ecam.path_limits import MARGIN
from cam_ros.recording import open_recording
from cam_ros.recording.schema import import_type

DEFAULT = CONFIG_DIR / 'default.yaml'
SLAVE_TOPIC = '/axis/joint_states'
ECAM = ('-p', 'master.source:=topic', '-p', 'master.timeout:=30.0', '-p',
        'master.engage_on_start:=false', '-p', f'slave.state_topic:={SLAVE_TOPIC}')
AXIS_AT = 0.0123  # m: where the axis reports the follower
AXIS_LEAD_S = 2.0
START_NS = 9_000 * 10 ** 9
DT = 0.004  # 250 Hz
SPEED = 2 * math.pi  # 60 rpm: the 30 deg ramp takes some 21 messages
COUNT = 750  # 3 s: the disengage call may come late on a loaded machine
ENGAGE_AT, DISENGAGE_AT = 0.5, 1.65  # s into the stream (disengaged in the cam's return)
ANY = QoSProfile(depth=10000, reliability=ReliabilityPolicy.BEST_EFFORT)  # matches every offer
REQUESTS = QoSProfile(depth=10)


def report_axis(node, stop: threading.Event) -> threading.Thread:
    """Publish the axis's position every 50 ms until stop is set."""
    publisher = node.create_publisher(JointState, SLAVE_TOPIC, QoSProfile(depth=10))

    def run() -> None:
        while not stop.wait(0.05):
            publisher.publish(JointState(name=['follower'], position=[AXIS_AT]))

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


def replay(path, *options: str) -> subprocess.CompletedProcess:
    """Run `cam_ros replay FILE options` and check it ends well."""
    result = subprocess.run([sys.executable, '-m', 'cam_ros.cli', 'replay', str(path), '--wait',
                             str(WAIT_S), *options], capture_output=True, text=True, timeout=90)
    assert result.returncode == 0, result.stderr
    return result


class StandIn:
    """Serves /cam/engage as the recorded node answered and listens to the recording's topics."""

    def __init__(self, executor, recording):
        self.node = executor.node(f'stand_in_{time.monotonic_ns()}')
        self.heard = {name: Inbox(self.node, import_type(info.type), name, ANY)
                      for name, info in recording.topics.items()
                      if name != '/cam/engage_requests'}
        self.calls: list[tuple[bool, list[int]]] = []  # request, master stamps heard by then
        self.service = self.node.create_service(SetBool, '/cam/engage', self._answer)

    def _answer(self, request, response):
        with self.heard['/cam/master'].arrived:
            stamps = [stamp_of(m) for m in self.heard['/cam/master'].messages]
        self.calls.append((request.data, stamps))
        response.success = True
        return response

    def counts(self) -> dict[str, int]:
        """Return how many messages each topic brought so far."""
        return {name: len(inbox.messages) for name, inbox in self.heard.items()}


def test_a_run_engaged_through_engage_replays_into_a_fresh_node(
        start_cam_node, executor, tmp_path):
    folder = tmp_path / 'runs'
    first, _ = start_cam_node(DEFAULT, *ECAM, '-p', 'recording.enabled:=true',
                              '-p', f'recording.directory:={folder}')
    link = MasterLink(executor)
    axis_stop = threading.Event()
    axis = report_axis(link.node, axis_stop)
    link.connect(first)  # answered once the node knows where the axis is: it holds there
    # The axis keeps reporting before the master runs, so a fresh node still matching the
    # replay's best-effort publisher (see docs/cli.md) hears it in time too.
    time.sleep(AXIS_LEAD_S)
    axis_stop.set()
    axis.join()
    q, stream = constant_speed(START_NS, 0.5, SPEED, COUNT, DT)
    thread = link.stream(stream, DT)
    time.sleep(ENGAGE_AT)
    assert engage(executor, True).success
    time.sleep(DISENGAGE_AT - ENGAGE_AT)
    assert engage(executor, False).success
    thread.join()
    taken, answers = link.answered(stream)  # by stamp: a backlog is skipped
    assert first.stop(signal.SIGINT) == 0, first.log()

    path = next(folder.glob('*.mcap'))
    recording = open_recording(path)
    requests = [m.message for m in recording.messages(['/cam/engage_requests'])]
    assert [(r.engage, r.success, r.master_followed) for r in requests] == [
        (True, True, True), (False, True, True)]
    engaged_after, disengaged_after = (stamp_of(r) for r in requests)
    stamps = [stamp_of(m) for m in stream]
    assert stamps[0] < engaged_after < disengaged_after < stamps[-1]
    assert recording.topics[SLAVE_TOPIC].count > 0
    assert {'/cam/commands', '/cam/joint_states', '/cam/switches', '/cam/state',
            '/cam/switch_state', '/cam/engage_requests', '/diagnostics'} <= recording.outputs
    assert not {'/cam/master', SLAVE_TOPIC, '/parameter_events'} & recording.outputs

    # The run: held at the axis's position, a move onto the cam from a message after the
    # engage call, once planned (off the master thread: within 0.2 s here; the line shaft
    # resting where it was: nothing followed it); after the
    # disengage call the line shaft stops on the cam (no limits: over
    # master.engage_distance_deg, 30 deg, from its speed) and rests.
    position = np.array([m.position[1] for m in answers])
    taken_stamps = np.array([stamp_of(m) for m in taken])
    engaged = np.searchsorted(taken_stamps, engaged_after, side='right')
    moving = engaged + int(np.argmax(position[engaged:] != AXIS_AT))  # once it is planned
    assert np.all(position[:moving] == AXIS_AT) and moving < engaged + 50
    assert np.all(np.diff(position[moving - 1:moving + 5]) != 0.0)
    # The stop starts from the line shaft at the call's master message (whichever the node
    # takes next) and decelerates it at the rate that stops the master's speed over 30 deg,
    # path_limits.MARGIN below it: theta_v written out here, the cam at theta_v exactly.
    called = q[stamps.index(disengaged_after)]
    deceleration = (1.0 - MARGIN) * SPEED ** 2 / (2 * math.radians(30.0))
    since = (taken_stamps - disengaged_after) * 1e-9
    stopping = since > 0.0
    tau = np.minimum(since[stopping], SPEED / deceleration)
    theta_v = called + SPEED * tau - deceleration * tau ** 2 / 2
    on_cam, velocity = seed_000_follower(theta_v, SPEED - deceleration * tau)
    assert np.sum(since > SPEED / deceleration) > 10  # at rest for a while
    np.testing.assert_allclose(position[stopping], on_cam, rtol=0, atol=1e-12)
    np.testing.assert_allclose([m.velocity[1] for m, on in zip(answers, stopping) if on],
                               velocity, rtol=0, atol=1e-12)

    # Plain replay: inputs and calls only, said on stderr; nothing on the node's outputs.
    stand_in = StandIn(executor, recording)
    result = replay(path)
    assert 'calling /cam/engage as recorded (2 calls)' in result.stderr
    [left] = [line for line in result.stderr.splitlines() if 'leaving out' in line]
    assert '/cam/commands' in left and '/cam/joint_states' in left and '/cam/master' not in left
    assert left.endswith('(the outputs of /cam and its parameter events: --outputs publishes '
                         'them)')
    recorded_inputs = recording.topics['/cam/master'].count + recording.topics[SLAVE_TOPIC].count
    assert result.stdout.startswith(f'published {recorded_inputs} messages')
    assert [request for request, _ in stand_in.calls] == [True, False]
    for (_, heard), after in zip(stand_in.calls, (engaged_after, disengaged_after)):
        assert after in heard and max(heard) == after  # after that message, before the next
    time.sleep(0.5)
    counts = stand_in.counts()
    assert {name: counts[name] for name in recording.outputs if name in counts} == {
        name: 0 for name in recording.outputs if name in counts}
    assert counts[SLAVE_TOPIC] > 0
    replay(path, '--outputs')
    for name in ('/cam/commands', '/cam/joint_states', '/cam/switch_state'):
        stand_in.heard[name].wait(recording.topics[name].count, WAIT_S)

    # Replayed into a fresh node: the recorded commands, by master stamp.
    stand_in.node.destroy_service(stand_in.service)  # the fresh node serves /cam/engage
    for subscription in list(stand_in.node.subscriptions):  # so --wait waits for the fresh node
        stand_in.node.destroy_subscription(subscription)
    second, _ = start_cam_node(DEFAULT, *ECAM)
    fresh = MasterLink(executor)
    calls = Inbox(fresh.node, EngageRequest, '/cam/engage_requests', REQUESTS)
    replay(path)
    recorded = {stamp_of(m): m.position[1] for m in answers}
    fresh.answered(stream)  # the last message, or all the node will (one that came after its
    # clock had stepped, the replay held up on a loaded machine, has no answer)
    assert second.stop(signal.SIGINT) == 0, second.log()
    replayed = {stamp_of(m): m.position[1] for m in fresh.messages('joints')}
    assert 2 * len(replayed.keys() & recorded.keys()) >= len(recorded)
    # The same (to round-off: the rest may be a machine cycle off) outside the engagement: from
    # the engage call until both runs command the cam at the master again, each node moved
    # from where its line shaft rested (the last message it took) and integrated its catch-up
    # over the steps it took (a backlog skipped, the clock's steps): there they may differ.
    common = np.array(sorted(replayed.keys() & recorded.keys()))
    master_at = {stamp_of(m): m.position[0] for m in stream}
    cam, _ = seed_000_follower(np.array([master_at[stamp] for stamp in common]), SPEED)
    mine, theirs = (np.array([run[stamp] for stamp in common]) for run in (replayed, recorded))
    on_cam = (np.abs(mine - cam) <= 1e-12) & (np.abs(theirs - cam) <= 1e-12)
    # locked from where both stay on the cam until the disengagement (in a dwell a catching-up
    # axis can touch its cam before)
    engaged = (common > engaged_after) & (common < disengaged_after)
    locked = common[engaged & ~on_cam].max() + 1
    outside = (common <= engaged_after) | (common >= locked)
    np.testing.assert_allclose(mine[outside], theirs[outside], rtol=0, atol=1e-12)
    assert outside.mean() >= 0.5 and locked < disengaged_after
    assert [(m.engage, stamp_of(m)) for m in calls.messages] == [
        (True, engaged_after), (False, disengaged_after)]
