"""The studio's page in a real headless Chromium: edit, see, refuse, save, undo, drag.

Every wait is on the page's own state (body[data-seq] counts the answers drawn, data-state is
ready, error or busy), never a sleep, so the tests hold on a loaded machine. With
CAM_ROS_DOCS_SCREENSHOTS=1 the machine's test writes docs/studio.png.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest

from .studio_support import cli, CONFIG_DIR, edited_file, REPO, Studio

from cam_ros.core import read_parameters_file

#: Longest wait for one answer (ms): generous, for a loaded 2-core machine.
TIMEOUT_MS = 120_000


def open_page(page, studio: Studio):
    page.set_default_timeout(TIMEOUT_MS)
    page.goto(studio.url)
    page.wait_for_function("document.body.dataset.state === 'ready'")
    return page


def answered(page, seq: int) -> None:
    """Wait until the page drew the answer to an edit made after answer seq."""
    page.wait_for_function(f"Number(document.body.dataset.seq) > {seq} && "
                           "document.body.dataset.state !== 'busy'")


def seq(page) -> int:
    return int(page.evaluate('document.body.dataset.seq'))


def type_value(page, key: str, text: str) -> None:
    """Type text into the field of key, as a user does (Enter), and wait for the answer."""
    before = seq(page)
    box = page.locator(f'[data-key="{key}"]')
    box.fill(text)
    box.press('Enter')
    answered(page, before)


def trace(page, plot: str, index: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the x and y of a drawn plotly trace."""
    x, y = page.evaluate(f"[document.getElementById('{plot}').data[{index}].x, "
                         f"document.getElementById('{plot}').data[{index}].y]")
    return np.asarray(x, dtype=float), np.asarray(y, dtype=float)


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_an_edit_changes_the_plots_the_pairs_and_the_verdict(page, studio: Studio) -> None:
    open_page(page, studio)
    verdict = page.locator('[data-verdict]')
    assert verdict.text_content() == 'Verdict: no pair collides, every axis meets its limits'
    lines = re.findall(r'^  ((?:clearance|zones) .*)$', cli('report', studio.path).stdout, re.M)
    assert page.locator('[data-pair="feeder-jaw"]').text_content() == lines[0]
    assert page.locator('[data-pair="jaw-knife"]').text_content() == lines[1]
    if os.environ.get('CAM_ROS_DOCS_SCREENSHOTS') == '1':
        page.screenshot(path=str(REPO / 'docs' / 'studio.png'), full_page=False)

    type_value(page, 'interference.min_clearance[0]', '40.0')
    assert verdict.text_content() == 'Verdict: clearance feeder-jaw COLLIDES'
    assert page.locator('[data-pair="feeder-jaw"]').text_content().endswith('COLLIDES')
    shaded = page.evaluate("document.getElementById('timing').layout.shapes"
                           ".filter(s => s.type === 'rect').map(s => [s.x0, s.x1])")
    assert any(start <= 215.0 <= end for start, end in shaded)  # 310 - 200 - 80 < 40 mm

    # the feeder's stroke 200 -> 150 mm: both ends of the joint, the first alone is refused
    type_value(page, 'feeder.motion.end_position[0]', '150.0')
    assert page.evaluate("document.body.dataset.state") == 'error'
    assert 'must equal' in page.locator('[data-error-for="feeder.motion.start_position[1]"]'
                                        ).text_content()
    type_value(page, 'feeder.motion.start_position[1]', '150.0')
    type_value(page, 'feeder.motion.start_position[2]', '150.0')
    type_value(page, 'feeder.motion.end_position[1]', '150.0')
    assert page.evaluate("document.body.dataset.state") == 'ready'
    angle, position = trace(page, 'svaj', 0)
    # the cycloidal forward stroke over 0-140 deg, written out: h (t - sin(2 pi t) / 2 pi)
    t = angle[angle <= 140.0] / 140.0
    expected = 150.0 * (t - np.sin(2.0 * np.pi * t) / (2.0 * np.pi))
    assert np.abs(position[angle <= 140.0] - expected).max() < 1e-9
    assert verdict.text_content() == 'Verdict: no pair collides, every axis meets its limits'


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_bad_value_shows_the_clis_line_at_its_field(page, studio: Studio,
                                                      tmp_path: Path) -> None:
    open_page(page, studio)
    type_value(page, 'follower.base_radius', '4')
    shown = page.locator('[data-error-for="follower.base_radius"]').text_content()
    by_hand = edited_file(CONFIG_DIR / 'default.yaml', tmp_path / 'default.yaml',
                          [('base_radius: 4.0', 'base_radius: 4')])
    assert cli('report', by_hand).stderr == f'cam_ros report: {shown}\n'
    assert page.locator('[data-verdict]').get_attribute('class').split().count('stale') == 1
    type_value(page, 'follower.base_radius', '4.0')
    assert page.locator('[data-error-for="follower.base_radius"]').text_content() == ''
    assert page.locator('[data-verdict]').text_content() == 'Verdict: meets its limits'


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_undo_redo_and_save_give_the_report_shown(page, studio: Studio) -> None:
    open_page(page, studio)
    pressure = trace(page, 'geometry', 0)[1]
    type_value(page, 'follower.offset', '1.5')
    assert not np.array_equal(trace(page, 'geometry', 0)[1], pressure)
    before = seq(page)
    page.click('[data-action="undo"]')
    answered(page, before)
    assert page.locator('[data-key="follower.offset"]').input_value() == '0.5'
    assert np.array_equal(trace(page, 'geometry', 0)[1], pressure)
    before = seq(page)
    page.click('[data-action="redo"]')
    answered(page, before)
    assert page.locator('[data-key="follower.offset"]').input_value() == '1.5'
    page.click('[data-action="save"]')
    page.wait_for_function('document.body.dataset.saved !== undefined')
    assert read_parameters_file(studio.path)['follower.offset'] == 1.5
    report = cli('report', studio.path)
    assert page.locator('#report').text_content() + '\n' == report.stdout
    verdict = report.stdout.strip().splitlines()[-1]
    assert verdict == 'Verdict: VIOLATES its limits'  # a pressure angle over 30 deg
    assert page.locator('[data-verdict]').text_content().startswith(f'{verdict}: pressure angle')
    comments = [line for line in (CONFIG_DIR / 'default.yaml').read_text().splitlines()
                if '#' in line]
    assert comments == [line for line in studio.path.read_text().splitlines() if '#' in line]


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_speed_edit_redraws_s_v_a_j_and_leaves_the_geometry_plot_as_drawn(
        page, studio: Studio) -> None:
    open_page(page, studio)
    velocity = trace(page, 'svaj', 1)[1]
    page.evaluate("window.geometryDrawn = document.getElementById('geometry').data")
    type_value(page, 'cam_speed', repr(2.0 * 6.283185307179586))
    # V = ds/dtheta * omega: twice the speed, twice every velocity
    assert np.allclose(trace(page, 'svaj', 1)[1], 2.0 * velocity, rtol=1e-12, atol=0.0)
    assert page.evaluate("document.getElementById('geometry').data === window.geometryDrawn")
    type_value(page, 'limits.pressure_angle_deg', '25.0')  # the geometry plot's own data
    assert not page.evaluate("document.getElementById('geometry').data === window.geometryDrawn")
    limits = page.evaluate("document.getElementById('geometry').layout.shapes.map(s => s.y0)")
    assert 25.0 in limits and -25.0 in limits and 30.0 not in limits


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_dragging_a_joint_on_the_s_plot_moves_the_segment_boundary(page, studio: Studio
                                                                   ) -> None:
    open_page(page, studio)
    where = page.evaluate("""() => {
        const plot = document.getElementById('svaj'), layout = plot._fullLayout;
        const box = plot.getBoundingClientRect();
        const x = deg => box.left + layout._size.l + layout.xaxis.l2p(deg);
        const y = box.top + layout._size.t + layout._size.h * (1 - 0.87);
        return {from: x(90.0), to: x(120.0), y};
    }""")
    before = seq(page)
    page.mouse.move(where['from'], where['y'])
    page.mouse.down()
    page.mouse.move((where['from'] + where['to']) / 2, where['y'], steps=5)
    page.mouse.move(where['to'], where['y'], steps=5)
    page.mouse.up()
    answered(page, before)
    end = float(page.locator('[data-key="motion.end_deg[0]"]').input_value())
    start = float(page.locator('[data-key="motion.start_deg[1]"]').input_value())
    assert end == start
    assert abs(end - 120.0) < 1.0  # a pixel of the plot is about 0.5 deg
    joints = page.evaluate("document.getElementById('svaj').layout.shapes.map(s => s.x0)")
    assert joints[0] == end
    # the rise now starts at the dragged joint: S is 0 up to it, 2 cm at 180 deg
    angle, position = trace(page, 'svaj', 0)
    assert np.all(position[angle <= end] == 0.0) and position[angle > end][0] > 0.0
    assert np.interp(180.0, angle, position) == pytest.approx(2.0, abs=1e-9)
