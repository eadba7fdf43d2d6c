"""The studio's API against the CLI: the same errors, reports and files, and its security."""
from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from .studio_support import cli, CONFIG_DIR, edited_file, Studio

from cam_ros.core import read_parameters_file
from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS
from cam_ros.studio.document import DesignDocument
from cam_ros.studio.server import run_in_thread

MACHINE = CONFIG_DIR / 'machine.yaml'
DEFAULT = CONFIG_DIR / 'default.yaml'

#: Bad edits: (file, key, entry index or None, text typed, the same edit in the file's text).
BAD_EDITS = [
    ('default.yaml', 'motion.start_deg', 1, '95.0',
     ('start_deg: [0.0, 90.0,', 'start_deg: [0.0, 95.0,')),
    ('default.yaml', 'follower.base_radius', None, '4', ('base_radius: 4.0', 'base_radius: 4')),
    ('default.yaml', 'follower.offset', None, '5.0', ('offset: 0.5', 'offset: 5.0')),
    ('machine.yaml', 'knife.motion.laws', 1, 'cycloidl',
     ('laws: [constant_velocity, cycloidal,', 'laws: [constant_velocity, cycloidl,')),
    ('machine.yaml', 'jaw.motion.start_deg', 2, '230.0',
     ('start_deg: [0.0, 150.0, 220.0,', 'start_deg: [0.0, 150.0, 230.0,')),
    ('machine.yaml', 'interference.type', 1, 'zone',
     ('type: [clearance, zones]', 'type: [clearance, zone]')),
]


def edit(texts: dict, key: str, index: int | None, text: str) -> dict:
    """Return texts with one value (or one entry) typed anew."""
    if index is None:
        texts[key] = text
    else:
        texts[key][index] = text
    return texts


@pytest.mark.parametrize('name, key, index, text, by_hand', BAD_EDITS)
def test_a_bad_edit_is_refused_at_its_field_with_the_cli_line(
        tmp_path: Path, name: str, key: str, index: int | None, text: str,
        by_hand: tuple[str, str]) -> None:
    folder = tmp_path / 'designs'
    folder.mkdir()
    shutil.copy(CONFIG_DIR / name, folder / name)
    server, thread, url = run_in_thread(DesignDocument(folder / name))
    try:
        studio = Studio(url, folder / name)
        answer = studio.post('api/view', {'values': edit(studio.texts(), key, index, text)})
    finally:
        server.should_exit = True
        thread.join(timeout=30)
    assert answer.status == 422
    error = answer.json()['error']
    field = key if index is None else f'{key}[{index}]'
    assert error['key'] == field
    run = cli('report', edited_file(CONFIG_DIR / name, tmp_path / name, [by_hand]))
    assert run.returncode == 2
    assert run.stderr == f'cam_ros report: {error["text"]}\n'


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_the_view_of_a_machine_holds_the_cores_figures(studio: Studio) -> None:
    view = studio.post('api/view', {'values': studio.texts(), 'axis': 'jaw'}).json()
    assert view['verdict'] == 'Verdict: no pair collides, every axis meets its limits'
    report = cli('report', studio.path).stdout
    assert [pair['line'] for pair in view['pairs']] == re.findall(
        r'^  ((?:clearance|zones) .*)$', report, re.M)
    assert [pair['pair'] for pair in view['pairs']] == ['feeder-jaw', 'jaw-knife']
    # the jaw's modified sine closing 80 mm over 150-220 deg, written out: at its middle, 40 mm
    curves = view['curves']
    angle = np.asarray(curves['angle_deg'])
    assert curves['unit'] == 'mm'
    assert np.interp(185.0, angle, curves['position']) == pytest.approx(40.0, abs=1e-9)
    assert np.interp(100.0, angle, curves['position']) == 0.0
    # the timing diagram: the knife modulo a turn, in deg; the feeder's cycloid at 70 deg: 100 mm
    timing = view['timing']
    knife = np.asarray(timing['positions']['knife'])
    assert knife.min() >= 0.0 and knife.max() < 360.0
    assert np.interp(70.0, timing['angle_deg'], timing['positions']['feeder']) == \
        pytest.approx(100.0, abs=1e-9)
    assert timing['spans'] == {'feeder-jaw': [], 'jaw-knife': []}


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_a_collision_is_in_the_verdict_and_shaded(studio: Studio) -> None:
    texts = edit(studio.texts(), 'interference.min_clearance', 0, '40.0')
    view = studio.post('api/view', {'values': texts}).json()
    assert view['verdict'] == 'Verdict: clearance feeder-jaw COLLIDES'
    assert not view['ok'] and not view['pairs'][0]['ok']
    # the gap 310 - feeder - jaw (mm) is below 40 mm where the shading is, on a 0.5 deg grid
    spans = view['timing']['spans']['feeder-jaw']
    assert spans
    gap_at = 310.0 - 200.0 - 80.0  # both at their stroke's end (feeder dwell, jaw sealing)
    assert gap_at < 40.0
    assert any(start <= 215.0 <= end for start, end, _ in spans)


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_save_keeps_comments_and_order_and_gives_the_reports_shown(studio: Studio) -> None:
    before = studio.path.read_text()
    texts = studio.texts()
    edit(texts, 'jaw.motion.end_deg', 1, '225.0')
    edit(texts, 'jaw.motion.start_deg', 2, '225.0')
    texts['feeder.slave.max_velocity'] = '3000.0'  # a key the file did not have
    shown = studio.post('api/report', {'values': texts}).json()['text']
    shown_json = studio.post('api/report', {'values': texts, 'json': True}).json()['text']
    saved = studio.post('api/save', {'values': texts}).json()
    assert saved['saved'] == str(studio.path)
    after = studio.path.read_text()
    comments = [line for line in before.splitlines() if line.lstrip().startswith('#')]
    assert comments == [line for line in after.splitlines() if line.lstrip().startswith('#')]
    assert after.count('\n') == before.count('\n') + 2  # slave: and its max_velocity
    assert 'end_deg: [150.0, 225.0, 270.0, 330.0, 360.0]' in after
    values = read_parameters_file(studio.path)
    assert [key for key in values if key != 'feeder.slave.max_velocity'] == \
        list(read_parameters_file(MACHINE))
    assert values['feeder.slave.max_velocity'] == 3000.0
    run = cli('report', studio.path)
    assert run.stdout == shown + '\n' == saved['report'] + '\n'
    assert cli('report', studio.path, '--json').stdout == shown_json + '\n'
    assert 'smallest gap 34.3959 mm' in shown  # the jaw closes 5 deg later: a wider gap


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_refused_design_is_never_saved(studio: Studio) -> None:
    before = studio.path.read_bytes()
    answer = studio.post('api/save', {'values': edit(studio.texts(), 'follower.offset', None,
                                                     '5.0')})
    assert answer.status == 422
    assert answer.json()['error']['key'] == 'follower.offset'
    assert studio.path.read_bytes() == before


DOWNLOADS = [
    *[('cam-table', {'file_format': name, **({'tolerance': '1um'} if name ==
                                             'twincat-functions' else {})},
       ['--cam-table', '--format', name] + (['--tolerance', '1um'] if name ==
                                            'twincat-functions' else []))
      for name in TABLE_FORMATS],
    ('cam-table', {'tolerance': '1um'}, ['--cam-table', '--tolerance', '1um']),
    ('surface', {'file_format': 'dxf'}, []),
    ('surface', {'file_format': 'svg'}, []),
    ('surface', {'file_format': 'csv'}, []),
    ('machining', {'tolerance': '0.001', 'cutter_radius': '0.5'},
     ['--machining', '--tolerance', '0.001', '--cutter-radius', '0.5']),
]


def comparable(name: str, data: bytes) -> bytes:
    """Return what of a file two runs of the CLI write alike: a DXF's ENTITIES section.

    ezdxf stamps its header with dates and GUIDs and orders some objects differently on each
    run; the drawing itself is the entities.
    """
    if not name.endswith('.dxf'):
        return data
    entities = data.split(b'\nENTITIES\n', 1)[1].split(b'\nENDSEC\n', 1)[0]
    assert entities.count(b'LWPOLYLINE') >= 1
    return entities


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_downloads_are_the_files_the_cli_writes(studio: Studio, tmp_path: Path) -> None:
    texts = edit(studio.texts(), 'follower.base_radius', None, '4.5')
    assert studio.post('api/save', {'values': texts}).status == 200
    for number, (kind, options, argv) in enumerate(DOWNLOADS):
        answer = studio.post('api/export', {'values': texts, 'kind': kind, 'options': options})
        assert answer.status == 200, (kind, options, answer.body)
        name = re.search(r'filename="(.*)"', answer.headers['content-disposition'])[1]
        target = tmp_path / f'{number}-{name}'
        run = cli('export', studio.path, '-o', target, *argv)
        assert run.returncode == 0, run.stderr
        assert comparable(name, answer.body) == comparable(name, target.read_bytes()), kind
        assert answer.headers['x-cam-ros-message'] == run.stdout.strip().replace(
            str(target), name).replace('\n', ' | ')
    assert sorted(path.name for path in studio.path.parent.iterdir()) == ['default.yaml']


@pytest.mark.parametrize('studio', ['machine.yaml'], indirect=True)
def test_a_machines_downloads_are_the_files_the_cli_writes(studio: Studio,
                                                           tmp_path: Path) -> None:
    texts = studio.texts()
    for kind, axis, options, argv in (
            ('timing', None, {}, ['--timing-diagram']),
            ('switches', None, {'file_format': 'st'}, ['--switches', '--format', 'st']),
            ('cam-table', 'knife', {}, ['--axis', 'knife', '--cam-table'])):
        answer = studio.post('api/export', {'values': texts, 'kind': kind, 'axis': axis,
                                            'options': options})
        assert answer.status == 200, answer.body
        run = cli('export', studio.path, '-o', tmp_path / 'out.csv', *argv)
        assert answer.body == (tmp_path / 'out.csv').read_bytes()
        assert run.returncode == 0
    whole = studio.post('api/export', {'values': texts, 'kind': 'cam-table', 'options': {}})
    assert whole.status == 422  # the CLI writes a folder of tables: a download takes one axis
    assert whole.json()['error']['text'].startswith('--axis = None: is needed')
    assert sorted(path.name for path in studio.path.parent.iterdir()) == ['machine.yaml']


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_bad_download_option_is_the_cli_line(studio: Studio, tmp_path: Path) -> None:
    answer = studio.post('api/export', {'values': studio.texts(), 'kind': 'cam-table',
                                        'options': {'file_format': 'twincat-functions',
                                                    'points': 100}})
    assert answer.status == 422
    run = cli('export', studio.path, '-o', tmp_path / 'x.st', '--cam-table', '--format',
              'twincat-functions', '--points', '100')
    assert run.stderr == f'cam_ros export: {answer.json()["error"]["text"]}\n'


@pytest.mark.parametrize('studio', ['default.yaml'], indirect=True)
def test_a_split_segments_middle_is_the_motions_position(studio: Studio) -> None:
    answer = studio.post('api/position', {'values': studio.texts(), 'deg': 135.0}).json()
    # the cycloidal rise of 2 cm over 90-180 deg, at its middle: half the rise
    assert answer == {'position': pytest.approx(1.0, abs=1e-12), 'unit': 'cm'}


def test_the_page_and_its_assets_come_from_the_studio(tmp_path: Path) -> None:
    shutil.copy(DEFAULT, tmp_path / 'default.yaml')
    server, thread, url = run_in_thread(DesignDocument(tmp_path / 'default.yaml'))
    try:
        studio = Studio(url, tmp_path / 'default.yaml')
        page = studio.get('').body.decode()
        sources = re.findall(r'(?:src|href)="([^"]+)"', page)
        assert sources and all(not re.match(r'\w+:', source) for source in sources)
        for source in sources:
            assert studio.get(source).status == 200
        plotly = studio.get('assets/plotly.min.js').body
        assert len(plotly) > 1_000_000 and b'plotly' in plotly[:2000].lower()
        for hook in ('data-verdict', 'data-action="save"', 'data-action="undo"',
                     'data-action="redo"'):
            assert hook in page
        assert studio.get('assets/../document.py').status == 404
    finally:
        server.should_exit = True
        thread.join(timeout=30)


def test_local_studio_answers_only_loopback_hosts_and_json_posts(tmp_path: Path) -> None:
    shutil.copy(DEFAULT, tmp_path / 'default.yaml')
    server, thread, url = run_in_thread(DesignDocument(tmp_path / 'default.yaml'))
    try:
        studio = Studio(url, tmp_path / 'default.yaml')
        assert studio.get('api/design').status == 200
        assert studio.get('api/design', {'Host': 'evil.example:80'}).status == 403
        form = studio.post('api/save', {'values': studio.texts()},
                           {'Content-Type': 'text/plain'})
        assert form.status == 403
    finally:
        server.should_exit = True
        thread.join(timeout=30)


def test_another_host_needs_the_token(tmp_path: Path) -> None:
    shutil.copy(DEFAULT, tmp_path / 'default.yaml')
    token = 'x' * 32
    server, thread, url = run_in_thread(DesignDocument(tmp_path / 'default.yaml'),
                                        token=token)
    try:
        base = url.split('?')[0]
        assert url.endswith(f'?token={token}')
        studio = Studio(base, tmp_path / 'default.yaml')
        assert studio.get('').status == 403
        assert studio.get('api/design').status == 403
        assert studio.get(f'api/design?token={"y" * 32}').status == 403
        page = studio.get(f'?token={token}')
        assert page.status == 200
        cookie = page.headers['set-cookie'].split(';')[0]
        assert 'httponly' in page.headers['set-cookie'].lower()
        assert studio.get('api/design', {'Cookie': cookie}).status == 200
    finally:
        server.should_exit = True
        thread.join(timeout=30)


def test_the_command_refuses_a_bad_file_with_the_cli_line(tmp_path: Path) -> None:
    bad = edited_file(DEFAULT, tmp_path / 'bad.yaml', [('offset: 0.5', 'offset: 5.0')])
    run = cli('studio', bad, '--port', '0')
    assert run.returncode == 2
    assert run.stderr == cli('report', bad).stderr.replace('cam_ros report:', 'cam_ros studio:')
    assert math.isfinite(read_parameters_file(DEFAULT)['follower.offset'])
