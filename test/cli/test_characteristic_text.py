"""A cam table's characteristic-value lines say what the law is: a constant once, as the law
gives it, and an extreme at a segment's end at that end (not 1e-11 deg beside it)."""
from __future__ import annotations

import re

import pytest
from cli_support import CONFIG_DIR, run_cli

MACHINE = CONFIG_DIR / 'machine.yaml'


def segment_line(path, number: int) -> str:
    return next(line for line in path.read_text().splitlines()
                if line.startswith(f'# segment {number} '))


@pytest.mark.parametrize('number', [0, 2])
def test_a_constant_velocity_segment_states_its_velocity_once(tmp_path, capsys, number):
    target = tmp_path / 'knife.csv'
    assert run_cli(capsys, 'export', MACHINE, '--axis', 'knife', '--cam-table', '-o',
                   target).code == 0
    line = segment_line(target, number)  # 5 deg of knife over 6.25 deg of master: 0.8
    assert 'velocity 0.8 deg/deg (constant)' in line
    assert 'acceleration 0 deg/deg^2 (constant)' in line
    assert 'jerk 0 deg/deg^3 (constant)' in line


def test_an_extreme_at_a_segment_end_is_printed_at_that_end(tmp_path, capsys):
    target = tmp_path / 'feeder.csv'
    assert run_cli(capsys, 'export', MACHINE, '--axis', 'feeder', '--cam-table', '-o',
                   target).code == 0
    line = segment_line(target, 0)  # cycloid 0-140 deg: jerk ~ cos(2 pi u), largest at u = 0
    assert re.search(r'jerk -0\.00287744 @ 70 \.\. 0\.00287744 @ 0 mm/deg\^3', line), line
    assert 'e-' not in line
    assert 'velocity 0 mm/deg (constant)' in segment_line(target, 1)  # the dwell
