"""A test-side master axis for the electronic cam: stamped JointStates in, outputs back."""
from __future__ import annotations

import math
import threading
import time

import numpy as np
from cli.cli_support import CM, seed_000_motion
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.qos import DurabilityPolicy, QoSProfile
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from std_srvs.srv import SetBool
from test_node import Inbox
from trajectory_msgs.msg import JointTrajectory

from cam_ros.core import build_design, parse_parameters, read_parameters_file

DEEP = QoSProfile(depth=10000)  # reliable and deep: the test never loses a message
LATCHED = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL)
WAIT_S = 20.0
QUIET_S = 1.0  # no new answer for this long: the node answered what it will
TOPICS = {'commands': ('/cam/commands', Float64MultiArray),
          'joints': ('/cam/joint_states', JointState),
          'trajectories': ('/cam/joint_trajectory', JointTrajectory),
          'diagnostics': ('/diagnostics', DiagnosticArray)}


def ecam_design(params_file, **updates):
    """Return the design of a params file with updates (independently of the node)."""
    values = read_parameters_file(params_file)
    values.update(updates)
    return build_design(parse_parameters(values))


def master_message(stamp_ns, names=('cam',), position=(0.0,), velocity=(), effort=()):
    """Build a master JointState with an explicit stamp."""
    message = JointState(name=list(names), position=[float(p) for p in position],
                         velocity=[float(v) for v in velocity],
                         effort=[float(e) for e in effort])
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(int(stamp_ns), 10 ** 9)
    return message


def constant_speed(start_ns: int, q0: float, speed: float, count: int, dt: float):
    """Return the positions and the messages (with their speed) of a master at constant speed."""
    q = q0 + speed * dt * np.arange(count)
    return q, [master_message(start_ns + round(k * dt * 1e9), position=(position,),
                              velocity=(speed,)) for k, position in enumerate(q.tolist())]


def seed_000_follower(q, omega, master_offset: float = 0.0, slave_offset: float = 0.0):
    """Follower position (m) and velocity of config/default.yaml at master q, speed omega.

    Written out from the closed-form cycloidal rise and harmonic return (cli_support), not from
    the package: theta = q - master offset (scaling 1), y = s(theta) + slave offset.
    """
    s, ds, _, _ = seed_000_motion(np.asarray(q, dtype=float) - master_offset, rise=2 * CM)
    return s + slave_offset, ds * np.asarray(omega, dtype=float)


def engage(executor, on: bool) -> SetBool.Response:
    """Call /cam/engage and return the answer."""
    client = executor.node(f'engage_{time.monotonic_ns()}').create_client(SetBool, '/cam/engage')
    assert client.wait_for_service(timeout_sec=WAIT_S)
    future = client.call_async(SetBool.Request(data=on))
    deadline = time.monotonic() + WAIT_S
    while not future.done():
        assert time.monotonic() < deadline
        time.sleep(0.01)
    return future.result()


class StateWatch:
    """The node's latched ~/state (engagement), as it changes."""

    def __init__(self, link: 'MasterLink'):
        self.inbox = Inbox(link.node, DiagnosticStatus, '/cam/state', LATCHED)

    def wait(self, message: str, timeout: float = WAIT_S, since: int | None = None) -> None:
        """Wait until the latest ~/state says message (with since: until any ~/state from the
        since-th on has said it, as a state that has passed already)."""
        deadline = time.monotonic() + timeout
        while not self._said(message, since):
            assert time.monotonic() < deadline, f'~/state {self.latest()!r}, not {message!r}'
            time.sleep(0.01)

    def count(self) -> int:
        """Return how many ~/state messages came so far."""
        with self.inbox.arrived:
            return len(self.inbox.messages)

    def _said(self, message: str, since: int | None) -> bool:
        if since is None:
            return self.latest() == message
        with self.inbox.arrived:
            return message in [state.message for state in self.inbox.messages[since:]]

    def latest(self) -> str | None:
        """Return the message of the last ~/state received (None: none yet)."""
        with self.inbox.arrived:
            return self.inbox.messages[-1].message if self.inbox.messages else None


def stamp_of(message) -> int:
    """Return a message's header stamp in ns."""
    return message.header.stamp.sec * 10 ** 9 + message.header.stamp.nanosec


class MasterLink:
    """Publish master messages to /cam/master and collect what the node publishes."""

    def __init__(self, executor):
        self.node = executor.node(f'master_{time.monotonic_ns()}')
        self.publisher = self.node.create_publisher(JointState, '/cam/master', DEEP)
        self.inbox = {key: Inbox(self.node, msg_type, topic, DEEP)
                      for key, (topic, msg_type) in TOPICS.items()}

    def messages(self, key: str) -> list:
        """Return what arrived on one output so far."""
        with self.inbox[key].arrived:
            return list(self.inbox[key].messages)

    def after(self, key: str, message) -> list:
        """Return what arrived on one output after message, one that arrived there (such as
        the answer to the last master message: the node's own steps follow it)."""
        arrived = self.messages(key)
        return arrived[next(k for k, m in enumerate(arrived) if m is message) + 1:]

    def connect(self, process, stamp_ns: int = 1, advance: bool = True, publisher=None) -> None:
        """
        Send probes (position 0, at rest) until the node answers one: every path matched.

        Probes carry stamp_ns, counting up from it with advance (else the node takes only one);
        they go through `publisher` when given (e.g. a replay's), else through the link's own.
        """
        publisher = publisher or self.publisher
        deadline = time.monotonic() + WAIT_S
        while not (self.messages('commands') and self.messages('joints')):
            assert process.process.poll() is None, process.log()
            assert time.monotonic() < deadline, f'no commands from the node:\n{process.log()}'
            publisher.publish(master_message(stamp_ns, velocity=(0.0,)))
            stamp_ns += advance
            time.sleep(0.2)
        time.sleep(0.3)  # let the last probes' answers in

    def stream(self, messages, period: float, pause_at: int | None = None,
               resume: threading.Event | None = None) -> threading.Thread:
        """Publish messages period s apart on a thread of their own (at pause_at: wait for resume).

        Paced, as a master is, not in chunks: a recording of it replays with the same spacing,
        and a burst replayed into the node's best-effort master subscription can lose messages
        (seen: 41 of 152).
        """
        def run() -> None:
            origin = time.monotonic()
            for k, message in enumerate(messages):
                if k == pause_at:
                    assert resume is not None and resume.wait(WAIT_S)
                    origin = time.monotonic() - k * period
                time.sleep(max(0.0, origin + k * period - time.monotonic()))
                self.publisher.publish(message)

        thread = threading.Thread(target=run, daemon=True)
        thread.start()
        return thread

    def send(self, messages, answered: bool = True) -> None:
        """Publish messages in real time, each when its stamp says after the first (a master
        runs in real time: the node skips a backlog and steps its line shaft on its clock while
        the master is silent); with answered, wait for the answers (see answered)."""
        origin, first = time.monotonic(), stamp_of(messages[0])
        for message in messages:
            time.sleep(max(0.0, origin + (stamp_of(message) - first) * 1e-9 - time.monotonic()))
            self.publisher.publish(message)
        if answered:
            self.answered(messages)

    def answered(self, messages, timeout: float = WAIT_S) -> tuple[list, list]:
        """Wait until the last message is answered (~/joint_states, by stamp) or the answers
        stop coming for QUIET_S; return the messages answered and their answers, in order.

        A message the node skipped behind a newer one (its backlog) has none, and so has one
        that came later than the node's own clock had already stepped (a master that stalled
        under load: the clock's steps are never stamped as one of the test's messages). At
        least an eighth of the messages must be answered (a node on a loaded machine skips its
        backlog by design: a clean-clone CI run beside two busy processes saw 144 of 600).
        """
        stamps = [stamp_of(message) for message in messages]
        deadline = time.monotonic() + timeout
        count, changed = -1, time.monotonic()
        while True:
            joints = self.messages('joints')
            by_stamp = {stamp_of(m): m for m in joints}
            if stamps[-1] in by_stamp:
                break
            if len(joints) != count:
                count, changed = len(joints), time.monotonic()
            elif time.monotonic() - changed > QUIET_S and \
                    any(stamp in by_stamp for stamp in stamps):
                break
            assert time.monotonic() < deadline, (
                f'{sum(stamp in by_stamp for stamp in stamps)} of {len(stamps)} answered')
            time.sleep(0.01)
        pairs = [(message, by_stamp[stamp]) for message, stamp in zip(messages, stamps)
                 if stamp in by_stamp]
        assert 8 * len(pairs) >= len(messages), f'{len(pairs)} of {len(messages)} answered'
        return [message for message, _ in pairs], [answer for _, answer in pairs]

    def answers(self, messages, timeout: float = WAIT_S) -> list:
        """Return the ~/joint_states answering messages (see answered), in their order."""
        return self.answered(messages, timeout)[1]

    def diagnostics(self, name: str, predicate, timeout: float = WAIT_S) -> dict:
        """Wait for a /diagnostics status named name whose values satisfy predicate."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for array in reversed(self.messages('diagnostics')):
                for status in array.status:
                    if status.name == name:
                        values = {item.key: item.value for item in status.values}
                        values.update(level=status.level, message=status.message)
                        if predicate(values):
                            return values
                        break
            time.sleep(0.1)
        last = self.messages('diagnostics')[-1:]
        raise AssertionError(f'no {name} diagnostics as expected: {last}')


def phases_profile(phases, dt: float, q0: float = 0.0):
    """Sample a master of constant-acceleration phases [(duration s, alpha rad/s^2)] every dt.

    Return times, positions, speeds and the index of the phase each sample opens (a sample on a
    boundary belongs to the phase after it).
    """
    times, positions, speeds, phase_of = [], [], [], []
    t0, q, omega = 0.0, q0, 0.0
    for number, (length, alpha) in enumerate(phases):
        count = int(round(length / dt))
        local = dt * np.arange(count)
        times.append(t0 + local)
        positions.append(q + omega * local + 0.5 * alpha * local ** 2)
        speeds.append(omega + alpha * local)
        phase_of.append(np.full(count, number))
        t0, q, omega = t0 + count * dt, q + omega * count * dt + 0.5 * alpha * (count * dt) ** 2, \
            omega + alpha * count * dt
    return (np.concatenate(times), np.concatenate(positions), np.concatenate(speeds),
            np.concatenate(phase_of))


RPM = 2 * math.pi / 60
