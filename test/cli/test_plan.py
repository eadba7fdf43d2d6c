"""`cam_ros plan`: the moves onto the cams from given positions, their peaks, order and pairs."""
from __future__ import annotations

import json
import math

import pytest
from cli_support import assert_one_error_line, CONFIG_DIR, DEFAULT_CONFIG, run_cli
from machine_support import edited_machine, MACHINE

from cam_ros.core import read_parameters_file
from cam_ros.core.ecam.moves import AxisState, MasterMotion
from cam_ros.core.machine.move_check import plan_moves, sequence_moves
from cam_ros.core.machine.served import machine_from_values

DEG = math.pi / 180.0


def test_the_knife_and_the_jaw_are_ordered_and_every_figure_is_printed(capsys):
    run = run_cli(capsys, 'plan', MACHINE, '--position', 'knife=300', '--position', 'jaw=0mm',
                  '--master-position', '240')
    assert run.code == 0, run
    lines = run.out.splitlines()
    assert lines[0] == 'Moves onto the cams: ' + str(MACHINE) + ', master at 240 deg, at rest'
    # the figures are the core's (plan_moves, sequence_moves) for the same positions
    shop = machine_from_values(read_parameters_file(MACHINE))
    master = MasterMotion(240.0 * DEG)
    moves = plan_moves(shop, {'knife': AxisState(300.0 * DEG), 'jaw': AxisState(0.0)}, master)
    found = sequence_moves(shop, moves, master)
    knife, jaw = found.moves['knife'], found.moves['jaw']
    assert (f'Axis knife: from 5.23599 rad (300 deg) onto its cam at 8.24019 rad (472.128 deg), '
            f'+1 turn: moves {knife.duration:.6g} s') in lines
    assert (f'Axis jaw: from 0 m (0 mm) onto its cam at 0.08 m (80 mm): waits '
            f'{jaw.delay:.6g} s, moves {jaw.duration - jaw.delay:.6g} s (on its cam '
            f'{jaw.duration:.6g} s after the start)') in lines
    assert (f'  velocity      peak {knife.peaks.velocity:.6g} rad/s '
            f'({math.degrees(knife.peaks.velocity):.6g} deg/s), no limit (off its cam within the '
            'cam\'s own peaks at cam_speed)') in lines
    assert lines.count('Order: knife, then jaw, each waiting at its start until the one before '
                       'is on its cam (together they would collide)') == 1
    assert f'  {found.checks[1].line("mm")}' in lines
    assert lines[-1] == 'Verdict: the moves keep every limit and no pair collides'


def test_json_gives_the_same_figures(capsys):
    run = run_cli(capsys, 'plan', MACHINE, '--position', 'knife=300', '--position', 'jaw=0',
                  '--master-position', '240', '--json')
    assert run.code == 0, run
    data = json.loads(run.out)
    assert data['ok'] and data['refused'] is None and data['order'] == ['knife', 'jaw']
    assert data['axes']['knife']['turns'] == 1
    assert data['axes']['knife']['start'] == pytest.approx(300.0 * DEG)
    assert data['axes']['jaw']['delay_s'] == pytest.approx(data['axes']['knife']['duration_s'])
    assert data['axes']['jaw']['peaks']['velocity']['limit'] is None
    assert [pair['pair'] for pair in data['pairs']] == ['clearance feeder-jaw', 'zones jaw-knife']
    assert all(pair['ok'] for pair in data['pairs'])


def test_limits_are_set_against_the_peaks_and_a_one_way_axis_never_backs(capsys, tmp_path):
    config = edited_machine(tmp_path, 'limited', lambda values: values['knife'].update(
        slave={'offset': -20.0, 'max_velocity': 720.0, 'max_acceleration': 6000.0,
               'max_jerk': 1e6, 'direction': 'positive'}))
    run = run_cli(capsys, 'plan', config, '--position', 'knife=0.5rad')
    assert run.code == 0, run
    assert '  velocity      peak ' in run.out
    assert 'limit 12.5664 rad/s (720 deg/s): ok' in run.out
    assert 'limit 104.72 rad/s^2 (6000 deg/s^2): ok' in run.out
    assert 'limit 17453.3 rad/s^3 (1e+06 deg/s^3): ok' in run.out
    assert '  direction     positive only: never against it: ok' in run.out


def test_a_refusal_exits_1_naming_the_pair(capsys):
    run = run_cli(capsys, 'plan', MACHINE, '--position', 'feeder=240', '--position', 'jaw=80',
                  '--master-position', '100')
    assert run.code == 1
    verdict = run.out.splitlines()[-1]
    assert verdict.startswith('Verdict: REFUSED: the moves collide together or one after '
                              'another: clearance feeder-jaw: smallest gap -')
    assert 'COLLIDES' in verdict


def test_a_move_refused_by_its_limits_exits_1_naming_the_axis(capsys, tmp_path):
    config = edited_machine(tmp_path, 'slow', lambda values: values['knife'].update(
        slave={'offset': -20.0, 'max_velocity': 300.0}))
    run = run_cli(capsys, 'plan', config, '--position', 'knife=10', '--master-speed',
                  '10.471975511965978')
    assert run.code == 1
    assert run.out.splitlines()[-1].startswith(
        'Verdict: REFUSED: axis knife: its cam itself at master speed 10.472 rad/s: velocity ')


def test_a_single_cam_is_a_machine_of_one_axis(capsys):
    bare = run_cli(capsys, 'plan', DEFAULT_CONFIG, '--position', '1')
    named = run_cli(capsys, 'plan', DEFAULT_CONFIG, '--position', 'follower=10mm')
    assert bare.code == named.code == 0
    assert bare.out == named.out
    assert 'Axis follower: from 0.01 m (1 cm) onto its cam at 0 m (0 cm): moves ' in bare.out


@pytest.mark.parametrize('argv, fragments', [
    (['--position', 'pusher=3'], ['--position', "'pusher=3'", 'AXIS one of feeder, knife, jaw']),
    (['--position', 'jaw=3', '--position', 'jaw=4'], ['gives jaw twice']),
    (['--position', 'jaw=3deg'], ['must be a length here']),
    (['--position', 'jaw=x'], ['must be a finite number']),
    (['--position', 'knife=0', '--master-position', '3mm'], ['--master-position',
                                                             'must be an angle here']),
])
def test_bad_input_is_one_line_naming_the_option(capsys, argv, fragments):
    assert_one_error_line(run_cli(capsys, 'plan', MACHINE, *argv), 'plan', *fragments)


def test_the_rotary_knife_alone_engages_311_deg_behind_in_half_a_second(capsys, tmp_path):
    values = (CONFIG_DIR / 'rotary_knife.yaml').read_text().replace(
        '      scaling: 0.1', '      scaling: 0.1\n    slave:\n      max_velocity: 720.0\n'
        '      max_acceleration: 6000.0\n      direction: positive')
    config = tmp_path / 'knife.yaml'
    config.write_text(values)
    run = run_cli(capsys, 'plan', config, '--position', '-311')
    assert run.code == 0, run
    assert 'onto its cam at 0 rad (0 deg): moves 0.551945 s' in run.out  # 311/720 + 720/6000
