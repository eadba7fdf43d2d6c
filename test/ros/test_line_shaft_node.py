"""A real cam_node running a limited four-axis line on its line shaft, from a simulated encoder
in real time: every transition stays on the cams, within every axis's limits and collision-free.

The line is config/machine.yaml (pusher, one-way knife, jaw) plus a second pusher (tucker), each
axis limited to about 1.25 x what its cam uses at cam_speed. The encoder, run here on a thread
of its own with stamps on the wall clock, accelerates at 300 rad/s^2 (about ten times what the
line allows), runs at 1.5 x cam speed, stops and starts again, and falls silent for a second.
Every check reads the commands themselves (~/joint_states, by stamp): the difference of two
positions over their stamps is the mean velocity between them, a second difference the mean
acceleration, so neither exceeds a limit the commands keep; the interference pairs are
evaluated on every command.
"""
from __future__ import annotations

import math
import subprocess
import sys
import threading
import time

import numpy as np
import yaml
from conftest import CONFIG_DIR
from ecam_support import master_message, MasterLink, stamp_of, StateWatch
from sensor_msgs.msg import JointState

MACHINE = CONFIG_DIR / 'machine.yaml'
NAMES = ('feeder', 'knife', 'jaw', 'tucker')
NOMINAL = 10.471975511965978  # cam_speed, rad/s of line shaft
#: slave.max_velocity and slave.max_acceleration of each axis, in its unit (mm or deg).
LIMITS = {'feeder': (2500.0, 40_000.0), 'knife': (math.degrees(15.0), math.degrees(30.0)),
          'jaw': (2000.0, 55_000.0), 'tucker': (2500.0, 40_000.0)}
SI = {'feeder': 1e-3, 'knife': math.pi / 180, 'jaw': 1e-3, 'tucker': 1e-3}
DT = 0.004  # a 250 Hz encoder
SLACK = 1e-6


def line_file(folder) -> str:
    """Write the four-axis line: machine.yaml, limits, and the tucker (the feeder 10 deg on)."""
    document = yaml.safe_load(MACHINE.read_text())
    values = document['/**']['ros__parameters']
    values['axes'] = list(NAMES)
    values['master']['joint'] = 'cam'
    values['master']['timeout'] = 0.5
    values['tucker'] = yaml.safe_load(yaml.safe_dump(values['feeder']))
    values['tucker']['master'] = {'offset_deg': 10.0}
    for name, (velocity, acceleration) in LIMITS.items():
        values[name].setdefault('slave', {}).update(
            max_velocity=velocity, max_acceleration=acceleration)
    values['knife']['slave']['direction'] = 'positive'
    path = folder / 'line.yaml'
    path.write_text(yaml.safe_dump(document))
    return str(path)


class Encoder:
    """A master encoder sent in real time on a thread of its own, stamped with the wall clock:
    it runs the constant-acceleration phases it is given (run), then on at its speed, and says
    nothing while silent."""

    def __init__(self, link: MasterLink):
        self.link = link
        self.theta = self.omega = self.alpha = 0.0
        self.silent = False
        self._phases: list[tuple[float, float]] = []
        self._ends = 0.0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._send, daemon=True)
        self._thread.start()

    def run(self, phases, silent: bool = False) -> None:
        """Run phases [(seconds, acceleration)] from now; wait until they are done."""
        with self._lock:
            self._phases, self.silent = list(phases), silent
        time.sleep(sum(seconds for seconds, _ in phases) + DT)
        with self._lock:
            self.silent = False

    def close(self) -> None:
        """Stop sending."""
        self._stop.set()
        self._thread.join()

    def _send(self) -> None:
        last = time.time_ns()
        left = 0.0  # of the current phase
        while not self._stop.wait(DT):
            now = time.time_ns()  # the stamp, and where the encoder is then
            step, last = (now - last) * 1e-9, now
            with self._lock:
                while self._phases and left <= 0.0:
                    left, self.alpha = self._phases.pop(0)
                if left <= 0.0:
                    self.alpha = 0.0
                left -= step
                self.theta += self.omega * step + 0.5 * self.alpha * step * step
                self.omega += self.alpha * step
                silent = self.silent
            if not silent:
                self.link.publisher.publish(master_message(
                    now, position=(self.theta,), velocity=(self.omega,)))


def check_within(joints) -> None:
    """Every axis's commands within its limits, the knife never backward, the pairs apart."""
    ns = np.array([stamp_of(m) for m in joints])
    assert (np.diff(ns) > 0).all()  # stamps always increase
    t = (ns - ns[0]) * 1e-9
    positions = np.array([list(m.position[1:]) for m in joints])
    for column, name in enumerate(NAMES):
        p = positions[:, column] / SI[name]  # the axis's unit
        v = np.diff(p) / np.diff(t)
        a = np.diff(v) / (0.5 * (t[2:] - t[:-2]))
        velocity, acceleration = LIMITS[name]
        assert np.abs(v).max() <= velocity * (1 + SLACK), (name, np.abs(v).max())
        assert np.abs(a).max() <= acceleration * (1 + 1e-3), (name, np.abs(a).max())
        if name == 'knife':
            assert v.min() >= -SLACK
    # Pair 0: the jaw's face 310 mm ahead of the pusher's finger, each toward the other.
    gap = 310.0 - positions[:, 0] / SI['feeder'] - positions[:, 2] / SI['jaw']
    assert gap.min() >= 15.0 - 1e-9, gap.min()
    # Pair 1: jaw above 60 mm and blade above 320 deg (mod a turn) never at once.
    jaw_in = positions[:, 2] / SI['jaw'] > 60.0
    knife_in = np.degrees(positions[:, 1]) % 360.0 > 320.0
    assert not (jaw_in & knife_in).any()


def test_a_four_axis_line_stays_on_its_cams_within_its_limits_through_every_transition(
        start_cam_node, executor, tmp_path):
    process, _ = start_cam_node(line_file(tmp_path), evaluate='feeder/evaluate')
    link = MasterLink(executor)
    states = StateWatch(link)
    link.connect(process, stamp_ns=time.time_ns() - 10 ** 9)
    encoder = Encoder(link)
    try:
        said = len(link.messages('joints'))
        # Up to cam speed at 300 rad/s^2, run, 1.5 x cam speed, back: filtered, then locked.
        encoder.run([(NOMINAL / 300.0, 300.0), (1.0, 0.0), (0.5 * NOMINAL / 300.0, 300.0),
                     (1.0, 0.0), (0.5 * NOMINAL / 300.0, -300.0)])
        master = link.diagnostics('cam: master', lambda v: v['line_shaft'] == 'locked' and int(
            v['filtered_steps']) > 50)  # the master was filtered, then followed again
        assert float(master['lag_deg']) == 0.0 and master['level'] == b'\x00'
        # A stop and a start within the limits: the axes stay coupled.
        encoder.run([(NOMINAL / 4.0, -4.0), (0.5, 0.0), (NOMINAL / 4.0, 4.0), (0.5, 0.0)])
        accepted = int(master['accepted'])
        link.diagnostics('cam: master', lambda v: v['line_shaft'] == 'locked' and int(
            v['accepted']) > accepted + 400)  # after the stop and the start
        assert states.latest() == 'engaged'
        assert 'master lost' not in [m.message for m in states.inbox.messages][-3:]
        check_within(link.messages('joints')[said:])
        # Silent for a second: a synchronized stop on the cams; back: a catch-up, locked.
        encoder.run([(1.5, 0.0)], silent=True)
        words = [m.message for m in states.inbox.messages]
        last = len(words) - 1 - words[::-1].index('stopping: master lost')
        assert words[last + 1] == 'at rest: master lost', words[last:]
        link.diagnostics('cam: master', lambda v: v['line_shaft'] == 'locked' and int(
            v['accepted']) > int(master['accepted']) + 250, timeout=20.0)
        check_within(link.messages('joints')[said:])
        assert 'stopping: master lost' in [m.message for m in states.inbox.messages]
        assert process.process.poll() is None
    finally:
        encoder.close()


def test_the_line_on_a_loaded_machine_has_no_false_loss_and_every_command_in_time(
        start_cam_node, executor, tmp_path):
    """With two busy processes beside it: no master loss though the encoder never stops,
    stamps always increasing, and every command received within master.timeout of its stamp
    (the middleware's reception stamp: the test's own delays are not the node's)."""
    busy = [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(2)]
    try:
        process, _ = start_cam_node(line_file(tmp_path), evaluate='feeder/evaluate')
        link = MasterLink(executor)
        arrivals: list[tuple[int, int]] = []
        lock = threading.Lock()

        def arrived(message: JointState, info) -> None:  # when the middleware received it
            with lock:
                arrivals.append((stamp_of(message), int(info['received_timestamp'])))
        link.node.create_subscription(JointState, '/cam/joint_states', arrived, 1000)
        link.connect(process, stamp_ns=time.time_ns() - 10 ** 9)
        encoder = Encoder(link)
        began = time.time_ns()
        try:
            encoder.run([(NOMINAL / 10.0, 10.0), (6.0, 0.0)])
        finally:
            encoder.close()
        with lock:
            late = [(arrived - stamp) * 1e-9 for stamp, arrived in arrivals if stamp > began]
        assert max(late) < 0.5, max(late)  # master.timeout
        assert process.log().count('master silent') <= 1  # only the connect probes' end
        stamps = [stamp_of(m) for m in link.messages('joints')]
        assert all(b > a for a, b in zip(stamps, stamps[1:]))
    finally:
        for child in busy:
            child.kill()
            child.wait()
