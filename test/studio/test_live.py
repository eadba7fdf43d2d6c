"""The studio linked to a real cam_node (`--node /cam`), in a real headless Chromium.

The node serves config/machine.yaml, its master driven by the test; the page shows the master
and each axis's command (checked against MC_CamIn written out here) and the feeder's reported
position, applies a phase shift of the knife (read back from the node's own parameter
service), is refused a jaw shift that collides (the node's reason shown, its value kept), and
its engage and disengage buttons reach the node (its latched ~/engage_requests).
"""
from __future__ import annotations

import math
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Iterator

import numpy as np
import pytest
from cli.cli_support import CM, seed_000_motion
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import DurabilityPolicy, QoSProfile
from sensor_msgs.msg import JointState

from .studio_support import CLI_TIMEOUT_S, CONFIG_DIR, Studio
from .test_browser import answered, open_page, seq, type_value

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.studio.document import DesignDocument
from cam_ros.studio.live import LiveLink
from cam_ros.studio.server import run_in_thread

MACHINE = CONFIG_DIR / 'machine.yaml'
SPEED = 2.0  # rad/s of master: a slow line shaft
PERIOD_S = 0.01
REPORTED_M = 0.05  # the feeder's drive reports 50 mm
WAIT_S = 60.0


def commanded_mm(values, name: str, q: float) -> float:
    """The axis's command (its file unit, mm) at master q: MC_CamIn written out (scaling 1)."""
    flat = {key.partition('.')[2]: value for key, value in values.items()
            if key.startswith(f'{name}.')}
    flat.update({key: values[key] for key in ('cam_speed', 'master.source')})
    program = build_design(parse_parameters(flat)).program
    turns = (q - math.radians(flat.get('master.offset_deg', 0.0))) / 1.0
    return float(program.evaluate(np.array([turns])).s[0]) * 1000.0 \
        + flat.get('slave.offset', 0.0)


class Drives:
    """The test's master axis on /cam/master and the feeder's drive reporting its position."""

    def __init__(self, executor):
        node = executor.node(f'drives_{time.monotonic_ns()}')
        self.master = node.create_publisher(JointState, '/cam/master', 10)
        self.feeder = node.create_publisher(JointState, '/feeder_drive', 10)
        self.requests: list = []
        from cam_ros_interfaces.msg import EngageRequest

        node.create_subscription(EngageRequest, '/cam/engage_requests', self.requests.append,
                                 QoSProfile(depth=100,
                                            durability=DurabilityPolicy.TRANSIENT_LOCAL))
        self.parameters = AsyncParameterClient(node, '/cam')
        self.running = True
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        start = time.monotonic()
        while self.running:
            now = time.time_ns()
            master = JointState(name=['line_shaft'], position=[SPEED * (time.monotonic()
                                                                        - start)],
                                velocity=[SPEED])
            master.header.stamp.sec, master.header.stamp.nanosec = divmod(now, 10 ** 9)
            self.master.publish(master)
            report = JointState(name=['feeder'], position=[REPORTED_M])
            report.header = master.header
            self.feeder.publish(report)
            time.sleep(PERIOD_S)

    def parameter(self, name: str) -> float:
        """Read one of the node's parameters from its own service."""
        assert self.parameters.wait_for_services(timeout_sec=WAIT_S)
        future = self.parameters.get_parameters([name])
        deadline = time.monotonic() + WAIT_S
        while not future.done():
            assert time.monotonic() < deadline
            time.sleep(0.01)
        return future.result().values[0].double_value

    def engaged(self, on: bool) -> None:
        """Wait until the node answered an ~/engage call of on with success."""
        deadline = time.monotonic() + WAIT_S
        while not any(r.engage == on and r.success for r in list(self.requests)):
            assert time.monotonic() < deadline, list(self.requests)
            time.sleep(0.01)


@pytest.fixture
def linked(start_cam_node, executor, tmp_path: Path) -> Iterator[tuple[Studio, Drives]]:
    """A cam_node on a copy of machine.yaml, driven by the test, and a studio linked to it."""
    path = tmp_path / 'designs' / 'machine.yaml'
    path.parent.mkdir()
    shutil.copy(MACHINE, path)
    start_cam_node(path, '-p', 'master.timeout:=30.0', '-p',
                   'feeder.slave.state_topic:=/feeder_drive', evaluate='knife/evaluate')
    drives = Drives(executor)
    document = DesignDocument(path)
    live = LiveLink('/cam', document.values)
    server, thread, url = run_in_thread(document, live=live)
    yield Studio(url, path), drives
    drives.running = False
    drives.thread.join(timeout=WAIT_S)
    server.should_exit = True
    thread.join(timeout=30)
    live.close()


def live_status(page) -> dict:
    """Wait for the next status the page drew with commands; return it."""
    seq = int(page.evaluate('document.body.dataset.liveSeq || 0'))
    page.wait_for_function(f'Number(document.body.dataset.liveSeq) > {seq} && '
                           "document.querySelector('[data-live-axis=\"jaw\"]')"
                           ".dataset.command !== ''")
    return page.evaluate('live.status')


def show_axis(page, axis: str) -> None:
    """Show an axis's tab and wait for its view."""
    before = seq(page)
    page.click(f'[data-axis="{axis}"]')
    answered(page, before)


def add_parameter(page, name: str, text: str) -> None:
    """Add a parameter the file lacks, as a user does, and wait for the answer."""
    before = seq(page)
    page.fill('#add-name', name)
    page.fill('#add-value', text)
    page.click('#add-button')
    answered(page, before)


def state_shown(page, text: str) -> None:
    """Wait until the page shows the node's ~/state as text."""
    page.wait_for_function("document.querySelector('[data-live-state]').textContent === "
                           f"{text!r}")


def click(page, action: str) -> None:
    """Click a live button and wait for the node's answer."""
    answers = int(page.evaluate('document.body.dataset.liveAnswers || 0'))
    page.click(f'[data-action="{action}"]')
    page.wait_for_function(f'Number(document.body.dataset.liveAnswers) > {answers}')


def test_the_page_shows_the_node_applies_a_phase_shift_and_shows_a_collision_refused(
        page, linked) -> None:
    studio, drives = linked
    values = read_parameters_file(MACHINE)
    open_page(page, studio)
    assert page.locator('[data-action="apply"]').is_visible()

    # The master, each axis's command and the feeder's reported position, as the node sent them.
    status = live_status(page)
    q = math.radians(status['master_deg'])  # the feeder and jaw repeat every machine cycle
    for name in ('feeder', 'jaw'):
        assert status['axes'][name]['command'] == pytest.approx(
            commanded_mm(values, name, q), abs=1e-6)
    page.wait_for_function("document.querySelector('[data-live-axis=\"feeder\"]')"
                           ".dataset.reported !== ''")
    status = page.evaluate('live.status')
    assert status['axes']['feeder']['reported'] == pytest.approx(REPORTED_M * 1000.0, abs=1e-9)
    marker = page.evaluate("document.getElementById('timing').data"
                           ".filter(t => t.meta === 'live').map(t => [t.name, t.x[0], t.y[0]])")
    drawn = {name: (x, y) for name, x, y in marker}
    assert drawn['feeder reported'][1] == pytest.approx(REPORTED_M * 1000.0)
    assert 0.0 <= drawn['jaw command'][0] < 360.0
    assert page.locator('[data-live-state]').text_content() != 'no state yet'

    # A phase shift of the knife: applied, and the node holds it.
    show_axis(page, 'knife')
    type_value(page, 'knife.master.offset_deg', '95.0')
    click(page, 'apply')
    assert page.locator('[data-live-answer]').text_content() == \
        'applied knife.master.offset_deg'
    assert page.locator('[data-live-error]').text_content() == ''
    assert drives.parameter('knife.master.offset_deg') == 95.0

    # A jaw shift into the knife's zone: the page shows the collision, the node refuses it.
    add_parameter(page, 'jaw.master.offset_deg', '-60.0')
    assert 'zones jaw-knife COLLIDES' in page.locator('[data-verdict]').text_content()
    click(page, 'apply')
    error = page.locator('[data-live-error]').text_content()
    assert error.startswith('/cam refused jaw.master.offset_deg: ')
    assert 'zones jaw-knife: smallest margin 15.53' in error
    assert drives.parameter('jaw.master.offset_deg') == 0.0
    assert drives.parameter('knife.master.offset_deg') == 95.0

    # Disengage and engage reach the node.
    click(page, 'disengage')
    drives.engaged(False)
    assert page.locator('[data-live-answer]').text_content().startswith('disengaged')
    state_shown(page, 'WARN: at rest: disengaged')
    click(page, 'engage')
    drives.engaged(True)
    state_shown(page, 'OK: engaged')


def test_without_node_the_live_routes_say_so(studio: Studio) -> None:
    assert studio.get('api/design').json()['live'] is None
    assert studio.get('api/live').json() == {'node': None}
    answer = studio.post('api/live/engage', {'engage': True})
    assert answer.status == 422
    assert answer.json()['error']['text'].startswith('--node = None: is needed to drive a '
                                                     'running node')


def test_a_node_that_is_not_there_is_named_with_the_domain_searched(
        ros_domain: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import cam_ros.studio.live

    monkeypatch.setattr(cam_ros.studio.live, 'CALL_TIMEOUT_S', 0.5)
    document = DesignDocument(shutil.copy(MACHINE, tmp_path / 'machine.yaml'))
    live = LiveLink('nobody', document.values)
    server, thread, url = run_in_thread(document, live=live)
    try:
        studio = Studio(url, document.path)
        status = studio.get('api/live').json()
        assert status['node'] == '/nobody' and status['master_deg'] is None
        assert status['axes']['jaw'] == {'unit': 'mm', 'cam_deg': None, 'command': None,
                                         'reported': None}
        answer = studio.post('api/live/apply', {'values': studio.texts()})
        assert answer.json()['applied'] and answer.json()['sent'] == []  # nothing to send
        texts = {**studio.texts(), 'knife.master.offset_deg': '95.0'}
        answer = studio.post('api/live/apply', {'values': texts})
        assert answer.status == 422
        assert answer.json()['error']['text'].startswith(
            "--node = '/nobody': has no service /nobody/set_parameters_atomically within "
            f'0.5 s (ROS_DOMAIN_ID={ros_domain}; similar services available: ')
    finally:
        server.should_exit = True
        thread.join(timeout=30)
        live.close()


def test_cam_ros_studio_node_follows_a_clock_driven_clockwise_cam(
        start_cam_node, tmp_path: Path) -> None:
    """`cam_ros studio FILE --node /cam` as a user starts it, on config/default.yaml's node: the
    cam joint of a clockwise cam falls (sigma theta), and the page's cam angle is theta."""
    path = shutil.copy(CONFIG_DIR / 'default.yaml', tmp_path / 'default.yaml')
    start_cam_node(path)
    studio_process = subprocess.Popen(
        [sys.executable, '-m', 'cam_ros.cli', 'studio', str(path), '--port', '0', '--node',
         '/cam'], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = studio_process.stdout.readline()
        assert ', linked to /cam at ' in line, studio_process.stderr.read()
        studio = Studio(re.search(r' at (http://\S+) ', line).group(1), Path(path))
        told_apart = 0
        deadline = time.monotonic() + WAIT_S
        while told_apart < 3:
            assert time.monotonic() < deadline, f'{told_apart} statuses told the sign apart'
            status = studio.get('api/live').json()['axes']['follower']
            if status['command'] is None:
                time.sleep(0.05)
                continue
            theta = math.radians(status['cam_deg'])
            s, mirrored = seed_000_motion(np.array([theta, -theta]), rise=2 * CM)[0] / CM
            assert status['command'] == pytest.approx(s, abs=1e-9)  # cm, the file's unit
            told_apart += abs(s - mirrored) > 1e-3
            time.sleep(0.05)
    finally:
        studio_process.send_signal(signal.SIGINT)
        assert studio_process.wait(timeout=CLI_TIMEOUT_S) == 0
