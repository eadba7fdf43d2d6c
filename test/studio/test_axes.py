"""Adding and removing a machine's axis in the studio: in Chromium, through its API, in the file.

The page's answers are compared with the CLI's on the saved file (`cam_ros report`) or on the
same edit made by hand in the file's text; every wait is on the page's own state.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from .studio_support import cli, CONFIG_DIR, edited_file, Studio
from .test_browser import answered, open_page, seq

from cam_ros.core import read_parameters_file

MACHINE = CONFIG_DIR / 'machine.yaml'
OK_VERDICT = 'Verdict: no pair collides, every axis meets its limits'
#: `cam_ros report`'s verdict line of a machine where no check fails.
OK_REPORT_VERDICT = 'Verdict: every axis meets its limits, no pair collides'


def click_and_wait(page, hook: str) -> None:
    """Click a button and wait for the answer to the edit it makes."""
    before = seq(page)
    page.click(f'[{hook}]')
    answered(page, before)


def timing_names(page) -> list[str]:
    """Return the axes drawn on the timing diagram, one panel each."""
    return page.evaluate("document.getElementById('timing').data.map(t => t.name.split(' ')[0])")


def comment_lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip().startswith('#')]


def save(page) -> None:
    page.evaluate('delete document.body.dataset.saved')
    page.click('[data-action="save"]')
    page.wait_for_function('document.body.dataset.saved !== undefined')


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_an_axis_is_added_as_a_copy_saved_undone_and_one_removed_with_its_pairs(
        page, studio: Studio) -> None:
    open_page(page, studio)
    assert timing_names(page) == ['feeder', 'knife', 'jaw']
    page.fill('[data-new-axis]', 'tucker')
    page.select_option('[data-copy-of]', 'feeder')
    click_and_wait(page, 'data-action="add-axis"')
    assert timing_names(page) == ['feeder', 'knife', 'jaw', 'tucker']
    timing = page.evaluate("document.getElementById('timing').data.map(t => t.y)")
    assert np.array_equal(timing[3], timing[0])  # a copy of the feeder moves as the feeder
    assert page.locator('[data-verdict]').text_content() == OK_VERDICT
    assert page.locator('[data-key="tucker.motion.end_position[0]"]').input_value() == '200.0'

    save(page)
    saved = read_parameters_file(studio.path)
    original = read_parameters_file(MACHINE)
    assert saved['axes'] == ['feeder', 'knife', 'jaw', 'tucker']
    assert {key[7:]: value for key, value in saved.items() if key.startswith('tucker.')} == \
        {key[7:]: value for key, value in original.items() if key.startswith('feeder.')}
    report = cli('report', studio.path)
    assert report.returncode == 0
    assert '4 axes on one master (feeder, knife, jaw, tucker)' in report.stdout
    assert report.stdout.strip().splitlines()[-1] == OK_REPORT_VERDICT
    assert page.locator('#report').text_content() + '\n' == report.stdout
    text = studio.path.read_text()
    assert comment_lines(text) == comment_lines(MACHINE.read_text())  # none copied, none lost
    assert text.index('\n    tucker:') > text.index('\n    jaw:')  # after the last axis,
    assert text.index('\n    tucker:') < text.index('# Pair 0')  # before the pairs' heading

    click_and_wait(page, 'data-action="undo"')
    assert timing_names(page) == ['feeder', 'knife', 'jaw']
    assert page.locator('[data-axis="tucker"]').count() == 0
    assert page.locator('[data-key^="tucker."]').count() == 0

    click_and_wait(page, 'data-axis="jaw"')
    assert page.locator('[data-action="remove-axis"]').text_content() == 'Remove axis jaw'
    assert page.locator('[data-pair="feeder-jaw"]').count() == 1
    click_and_wait(page, 'data-action="remove-axis"')
    assert page.locator('[data-pair]').count() == 0  # both pairs named the jaw
    assert timing_names(page) == ['feeder', 'knife']
    assert page.locator('[data-verdict]').text_content() == OK_VERDICT
    save(page)
    saved = read_parameters_file(studio.path)
    assert saved['axes'] == ['feeder', 'knife']
    assert not [key for key in saved if key.startswith(('jaw.', 'tucker.', 'interference.'))]
    report = cli('report', studio.path)
    assert report.returncode == 0 and '2 axes on one master (feeder, knife)' in report.stdout
    assert not re.search(r'^  (clearance|zones) ', report.stdout, re.M)
    assert report.stdout.strip().splitlines()[-1] == OK_REPORT_VERDICT
    # the jaw's heading goes with it, and the pairs' with the emptied interference section
    gone = comment_lines(MACHINE.read_text())
    gone = gone[:gone.index('# End-sealing jaw: 80 mm stroke toward the pusher over 150-220 deg '
                            '(modified sine), seals')]
    assert comment_lines(studio.path.read_text()) == gone


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
@pytest.mark.parametrize('name', ['jaw', 'tucker-1', 'motion'])
def test_a_bad_axis_name_shows_the_cores_line_and_changes_nothing(
        page, studio: Studio, tmp_path: Path, name: str) -> None:
    open_page(page, studio)
    before = seq(page)
    page.fill('[data-new-axis]', name)
    page.click('[data-action="add-axis"]')
    page.wait_for_function("document.body.dataset.axisAnswers === '1'")
    shown = page.locator('#axis-edit [data-error-for="axes"]').text_content()
    by_hand = edited_file(MACHINE, tmp_path / 'machine.yaml', [(
        'axes: [feeder, knife, jaw]', f'axes: [feeder, knife, jaw, {name}]')])
    assert cli('report', by_hand).stderr == f'cam_ros report: {shown}\n'
    assert shown.startswith(f"axes[3] = '{name}': ")
    assert seq(page) == before and timing_names(page) == ['feeder', 'knife', 'jaw']
    assert page.locator('[data-action="undo"]').is_disabled()


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_removing_an_axis_removes_its_entry_of_every_pair_array(studio: Studio) -> None:
    texts = studio.texts()
    answer = studio.post('api/axes', {'values': texts, 'remove': 'feeder'})
    assert answer.status == 200
    left = answer.json()['values']
    assert left['axes'] == ['knife', 'jaw']
    assert not [key for key in left if key.startswith('feeder.')]
    for key in [key for key in texts if key.startswith('interference.')]:
        assert left[key] == texts[key][1:], key  # pair 0 named the feeder, pair 1 is kept
    assert {key: value for key, value in left.items() if not key.startswith('interference.')
            and key != 'axes'} == {key: value for key, value in texts.items()
                                   if not key.startswith(('feeder.', 'interference.', 'axes'))}


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_the_last_axis_is_not_removed(studio: Studio, tmp_path: Path) -> None:
    texts = studio.texts()
    for name in ('feeder', 'knife'):
        texts = studio.post('api/axes', {'values': texts, 'remove': name}).json()['values']
    answer = studio.post('api/axes', {'values': texts, 'remove': 'jaw'})
    assert answer.status == 422
    by_hand = edited_file(MACHINE, tmp_path / 'machine.yaml',
                          [('axes: [feeder, knife, jaw]', 'axes: []')])
    assert cli('report', by_hand).stderr == f"cam_ros report: {answer.json()['error']['text']}\n"
    assert studio.post('api/axes', {'values': texts, 'remove': 'knife'}).json()['error'][
        'text'].startswith("axis = 'knife': is not an axis of the machine (axes: jaw)")


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_single_cam_has_no_axes_to_edit(page, studio: Studio) -> None:
    open_page(page, studio)
    assert page.locator('#axis-edit').is_hidden()
    answer = studio.post('api/axes', {'values': studio.texts(), 'add': 'b', 'copy_of': 'a'})
    assert answer.status == 422 and answer.json()['error']['key'] == 'axes'


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_a_removed_axis_takes_its_heading_and_leaves_the_next_ones(studio: Studio) -> None:
    texts = studio.post('api/axes', {'values': studio.texts(), 'remove': 'knife'}).json()
    assert studio.post('api/save', texts).status == 200
    # the jaw's heading follows the knife's last key (ruamel keeps it there): it stays
    knife = [line for line in comment_lines(MACHINE.read_text())
             if line.startswith(('# Rotary knife drum', "# with the web's speed", '# (12.7',
                                 '# slave.offset -20', '# blade is within'))]
    assert len(knife) == 5
    assert comment_lines(studio.path.read_text()) == [
        line for line in comment_lines(MACHINE.read_text()) if line not in knife]
    saved = read_parameters_file(studio.path)
    assert saved['axes'] == ['feeder', 'jaw'] and saved['interference.axis_b'] == ['jaw']
