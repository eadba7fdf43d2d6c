"""Every kind of bad config file, through the core and through `cam_ros report`: one clear error.

One table of cases. Each names the parameter, the value as written and a fragment of the rule that
the error message must carry. The core (load_config + build_design) raises InvalidParameter with
exactly that; `cam_ros report FILE` exits 2 with one line on stderr, nothing on stdout and no file
written. The CLI runs in-process for every case and as a real subprocess for a sample of them (all
of them with --heavy).
"""
from __future__ import annotations

import copy
import math
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import pytest
import yaml
from conftest import CONFIG_DIR

from cam_ros.cli import main
from cam_ros.core import InvalidParameter, build_design, load_config

DEFAULT = CONFIG_DIR / 'default.yaml'
DEFAULT_TEXT = DEFAULT.read_text()
FOLLOWER_LINE = DEFAULT_TEXT.splitlines().index('    follower:') + 1
ROLLER_LINE = DEFAULT_TEXT.splitlines().index('      roller_radius: 1.0') + 1
START_DEG_LINE = DEFAULT_TEXT.splitlines().index('      start_deg: [0.0, 90.0, 180.0, 240.0]') + 1
#: Longest one-line error of any case: parameter, a value quoted in at most 100 characters
#: (plus its size), and the rule.
MESSAGE_LIMIT = 400
SUBPROCESS_TIMEOUT_S = 60.0
SUBPROCESS_WORKERS = 4
#: Without --heavy, every SUBPROCESS_STRIDE-th case also runs as a subprocess.
SUBPROCESS_STRIDE = 8

Edit = Callable[[dict], Any]  # edits the ros__parameters mapping in place, or returns file text


def change(**dotted: Any) -> Edit:
    """Set parameters, e.g. change(follower__base_radius=4): '__' separates the sections."""
    def edit(params: dict) -> None:
        for name, value in dotted.items():
            *sections, leaf = name.split('__')
            node = params
            for section in sections:
                node = node.setdefault(section, {})
            node[leaf] = value
    return edit


def change_item(name: str, index: int, value: Any) -> Edit:
    """Set one entry of an array parameter, e.g. change_item('motion__start_deg', 2, 185.0)."""
    def edit(params: dict) -> None:
        section, leaf = name.split('__')
        params[section][leaf][index] = value
    return edit


def remove(section: str, leaf: str) -> Edit:
    """Delete one parameter."""
    def edit(params: dict) -> None:
        del params[section][leaf]
    return edit


def rename(section: str, old: str, new: str) -> Edit:
    """Rename a key (a misspelling); section '' renames a top-level section."""
    def edit(params: dict) -> None:
        node = params[section] if section else params
        node[new] = node.pop(old)
    return edit


def text(content: str) -> Edit:
    """Replace the whole file."""
    return lambda params: content


def inserted(after: str, lines: str) -> Edit:
    """Insert lines into the default file's text after the line after."""
    assert after in DEFAULT_TEXT, after
    return text(DEFAULT_TEXT.replace(after, after + lines))


def alias_bomb(indent: str, levels: int = 8) -> str:
    """Return lines of nested anchors &a0..&a{levels}, each a list of nine aliases of the last.

    Expanded, the last one holds 9**(levels + 1) strings (387 million for 8 levels).
    """
    rows = [f'{indent}lol0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]']
    rows += [f'{indent}lol{i}: &a{i} [{", ".join([f"*a{i - 1}"] * 9)}]'
             for i in range(1, levels + 1)]
    return '\n'.join(rows) + '\n'


def both(*edits: Edit) -> Edit:
    """Apply several edits."""
    def edit(params: dict) -> None:
        for one in edits:
            one(params)
    return edit


OSCILLATING_ROLLER = change(follower__type='oscillating_roller', follower__pivot_distance=10.0,
                            follower__arm_length=2.0)


@dataclass(frozen=True)
class Case:
    """A broken config: what to change, and the parameter, value and rule the error names."""

    id: str
    edit: Edit
    parameter: str
    value: str
    rule: str


CASES = [
    # Keys: missing, misspelled (in a section and a whole section).
    Case('missing_key', remove('follower', 'base_radius'), 'follower.base_radius', 'None',
         'is required'),
    Case('missing_array', remove('motion', 'end_position'), 'motion.end_position', 'None',
         'is required'),
    Case('misspelled_key', rename('follower', 'roller_radius', 'rollr_radius'),
         'follower.rollr_radius', '1.0', 'did you mean follower.roller_radius'),
    Case('misspelled_section', rename('', 'limits', 'limit'), 'limit.pressure_angle_deg', '30.0',
         'did you mean limits.pressure_angle_deg'),
    # Types.
    Case('int_for_double', change(follower__base_radius=4), 'follower.base_radius', '4',
         'must be a double (write 1.0, not 1)'),
    Case('string_for_double', change(follower__base_radius='big'), 'follower.base_radius',
         "'big'", 'must be a double'),
    Case('list_for_double', change(follower__base_radius=[4.0]), 'follower.base_radius', '[4.0]',
         'must be a double'),
    Case('ints_in_double_array', change(motion__start_deg=[0, 90, 180, 240]), 'motion.start_deg',
         '[0, 90, 180, 240]', 'must be a list of doubles (write 1.0, not 1)'),
    Case('double_for_integer', change(output__sample_count=360.0), 'output.sample_count',
         '360.0', 'must be an integer'),
    Case('bool_for_integer', change(output__sample_count=True), 'output.sample_count', 'True',
         'must be an integer'),
    Case('string_for_bool', change(recording__enabled='sure'), 'recording.enabled', "'sure'",
         'must be a bool'),
    Case('string_for_array', change(motion__laws='cycloidal'), 'motion.laws', "'cycloidal'",
         'must be a list of strings'),
    # Choices: units, laws, followers, rotation, compression.
    Case('unknown_unit', change(length_unit='furlong'), 'length_unit', "'furlong'",
         'must be one of m, cm, mm, in'),
    Case('unknown_law', change_item('motion__laws', 1, 'cycloid'),
         'motion.laws[1] (cycloid): law', "'cycloid'", 'must be one of dwell, constant_velocity'),
    Case('misspelt_law', change_item('motion__laws', 1, 'cycloydal'),
         'motion.laws[1] (cycloydal): law', "'cycloydal'", '(did you mean cycloidal?)'),
    Case('misspelt_follower', change(follower__type='translating_rolller'), 'follower.type',
         "'translating_rolller'", '(did you mean translating_roller?)'),
    Case('unknown_follower', change(follower__type='rocker'), 'follower.type', "'rocker'",
         'must be one of translating_roller, translating_flat'),
    Case('unknown_rotation', change(rotation='sideways'), 'rotation', "'sideways'",
         'must be one of clockwise, counterclockwise'),
    Case('unknown_compression', change(recording__compression='gzip'), 'recording.compression',
         "'gzip'", 'must be one of zstd, lz4, none'),
    # Radii and offsets.
    Case('negative_radius', change(follower__roller_radius=-1.0), 'follower.roller_radius',
         '-1.0', 'must be >= 0'),
    # Rules quote lengths in the file's unit (cm here), never in SI.
    Case('zero_base_radius', change(follower__base_radius=0.0), 'follower.base_radius', '0.0',
         'must be > 0 (cm)'),
    Case('zero_roller_radius', change(follower__roller_radius=0.0), 'follower.roller_radius',
         '0.0', 'must be > 0 (cm)'),
    Case('offset_at_prime_circle', change(follower__offset=5.0), 'follower.offset', '5.0',
         'needs |offset| < base_radius + roller_radius = 5 cm'),
    Case('offset_beyond_prime_circle', change(follower__offset=-6.0), 'follower.offset', '-6.0',
         'needs |offset| < base_radius + roller_radius'),
    # Oscillating followers that cannot reach the cam.
    Case('roller_arm_cannot_reach', OSCILLATING_ROLLER, 'follower.base_radius', '4.0',
         'base_radius + roller_radius = 5 cm must lie in (|pivot_distance - arm_length|, '
         'pivot_distance + arm_length) = (8, 12) cm so that the roller reaches the cam'),
    Case('roller_arm_missing', change(follower__type='oscillating_roller',
                                      follower__pivot_distance=9.0),
         'follower.arm_length', '0.0', 'must be > 0 (cm)'),
    Case('flat_face_cannot_touch', change(follower__type='oscillating_flat',
                                          follower__pivot_distance=4.0,
                                          follower__face_offset=1.0),
         'follower.face_offset', '1.0', 'base_radius + face_offset = 5 cm must lie in (0, '
         'pivot_distance = 4 cm) so that the face touches the base circle'),
    # Segments: gaps, overlaps, total, zero span, position mismatch, moving dwell, lengths.
    # Segment rules quote the other entries as written (deg), never in rad.
    Case('gap', change_item('motion__start_deg', 2, 185.0), 'motion.start_deg[2]', '185.0',
         'must equal motion.end_deg[1] = 180.0 (leaves a gap of 5 deg)'),
    Case('overlap', change_item('motion__start_deg', 1, 85.0), 'motion.start_deg[1]', '85.0',
         'must equal motion.end_deg[0] = 90.0 (leaves an overlap of 5 deg)'),
    Case('total_short', change_item('motion__end_deg', 3, 350.0), 'motion.end_deg[3]', '350.0',
         'must cover 360 deg from motion.start_deg[0] = 0.0, not 350 deg'),
    Case('total_long', change_item('motion__end_deg', 3, 370.0), 'motion.end_deg[3]', '370.0',
         'not 370 deg'),
    Case('zero_span', change(motion__start_deg=[0.0, 90.0, 90.0, 240.0],
                             motion__end_deg=[90.0, 90.0, 240.0, 360.0]),
         'motion.end_deg[1]', '90.0', 'must exceed motion.start_deg[1] = 90.0'),
    Case('position_jump', change_item('motion__start_position', 3, 2.5),
         'motion.start_position[3]', '2.5', 'must equal motion.end_position[2] = 2.0: the '
         'follower cannot jump'),
    Case('wrap_jump', change_item('motion__end_position', 3, 0.5), 'motion.start_position[0]',
         '0.0', '(the wrap joint 360 -> 0 deg): the follower cannot jump'),
    Case('moving_dwell', change_item('motion__end_position', 2, 2.5), 'motion.end_position[2]',
         '2.5', 'a dwell must end where it starts (motion.start_position[2] = 2.0)'),
    Case('arrays_of_two_lengths', change(motion__end_deg=[90.0, 180.0, 360.0]), 'motion.end_deg',
         '[90.0, 180.0, 360.0]', 'must have 4 entries, one per entry of motion.laws'),
    Case('no_segments', change(motion__laws=[], motion__start_deg=[], motion__end_deg=[],
                               motion__start_position=[], motion__end_position=[]),
         'motion (segments)', '[]', 'must hold at least one segment'),
    # Laws that need parameters: errors name the config entries, not the law's own names.
    Case('scca_without_fractions', change_item('motion__laws', 1, 'scca'),
         'motion.scca_fractions', '[]', 'needs 3 entries b, c, d for the scca law of segment 1'),
    Case('scca_fractions_sum', both(change_item('motion__laws', 1, 'scca'),
                                    change(motion__scca_fractions=[0.5, 0.5, 0.5])),
         'motion.scca_fractions', '[0.5, 0.5, 0.5]',
         'b + c + d = 1.5: the fractions must add up to 1 (scca law of segment 1)'),
    Case('scca_fraction_negative', both(change_item('motion__laws', 1, 'scca'),
                                        change(motion__scca_fractions=[-0.5, 1.0, 0.5])),
         'motion.scca_fractions', '[-0.5, 1.0, 0.5]', 'b = -0.5: must be a fraction in [0, 1]'),
    Case('via_point_without_point', change_item('motion__laws', 1, 'via_point'),
         'motion.laws[1]', "'via_point'", 'needs exactly one via point'),
    Case('via_point_outside_segment', both(
        change_item('motion__laws', 1, 'via_point'),
        change(motion__via_segment=[1], motion__via_deg=[300.0], motion__via_position=[1.0])),
        'motion.via_deg[0]', '300.0', 'must lie strictly inside segment 1, between '
        'motion.start_deg[1] = 90.0 and motion.end_deg[1] = 180.0'),
    Case('via_point_above_the_rise', both(
        change_item('motion__laws', 1, 'via_point'),
        change(motion__via_segment=[1], motion__via_deg=[135.0], motion__via_position=[2.5])),
        'motion.via_position[0]', '2.5', 'must lie strictly between motion.start_position[1] = '
        '0.0 and motion.end_position[1] = 2.0'),
    Case('via_point_without_a_rise', both(
        change_item('motion__laws', 2, 'via_point'),
        change(motion__via_segment=[2], motion__via_deg=[200.0], motion__via_position=[2.0])),
        'motion.via_position[0]', '2.0', 'must lie strictly between motion.start_position[2] = '
        '2.0 and motion.end_position[2] = 2.0'),
    Case('polynomial_via_outside_segment', both(
        change_item('motion__laws', 1, 'polynomial'),
        change(motion__via_segment=[1], motion__via_deg=[45.0], motion__via_position=[1.0])),
        'motion.via_deg[0]', '45.0', 'must lie strictly inside segment 1'),
    Case('via_point_on_a_dwell', change(motion__via_segment=[2], motion__via_deg=[200.0],
                                        motion__via_position=[2.0]),
         'motion.via_segment[0]', '2', 'law dwell takes no via points'),
    Case('table_not_rising', both(change_item('motion__laws', 1, 'table'),
                                  change(motion__table_u=[0.0, 0.7, 0.5, 1.0],
                                         motion__table_y=[0.0, 0.5, 0.6, 1.0])),
         'motion.table_u', '[0.0, 0.7, 0.5, 1.0]',
         'must rise strictly from 0 to 1 (2 or more points) (table law of segment 1)'),
    # Non-finite numbers and ranges.
    Case('nan_radius', change(follower__base_radius=math.nan), 'follower.base_radius', 'nan',
         'must be finite'),
    Case('inf_offset', change(follower__offset=math.inf), 'follower.offset', 'inf',
         'must be finite'),
    Case('nan_in_array', change_item('motion__start_deg', 1, math.nan), 'motion.start_deg',
         '[0.0, nan, 180.0, 240.0]', 'must be finite'),
    Case('minus_inf_speed', change(cam_speed=-math.inf), 'cam_speed', '-inf', 'must be finite'),
    Case('zero_speed', change(cam_speed=0.0), 'cam_speed', '0.0', 'must be >= 1e-09'),
    Case('pressure_limit_too_big', change(limits__pressure_angle_deg=95.0),
         'limits.pressure_angle_deg', '95.0', 'must be <= 89'),
    Case('zero_pressure_limit', change(limits__pressure_angle_deg=0.0),
         'limits.pressure_angle_deg', '0.0', 'must be >= 1'),
    Case('huge_radius', change(follower__base_radius=1e300), 'follower.base_radius', '1e+300',
         'must not exceed 100000 cm in magnitude'),
    Case('huge_position', change_item('motion__end_position', 1, 1e200),
         'motion.end_position', '1e+200', 'must not exceed 100000 cm in magnitude'),
    Case('huge_arm_swing', change(follower__type='oscillating_roller',
                                  follower__pivot_distance=9.0, follower__arm_length=8.0,
                                  motion__start_position=[0.0, 0.0, 200.0, 200.0],
                                  motion__end_position=[0.0, 200.0, 200.0, 0.0]),
         'motion.start_position', '200.0', 'must not exceed 180 deg in magnitude'),
    # d = sqrt((4 + 1)^2 - 0.5^2) = 4.97494 cm: at s = -6 the roller centre is under the cam.
    Case('roller_under_the_cam_centre', change(motion__start_position=[-6.0, -6.0, -4.0, -4.0],
                                               motion__end_position=[-6.0, -4.0, -4.0, -6.0]),
         'motion.laws[0] (dwell): s at 0.00 deg', '-6.0',
         'roller centre must stay above the cam centre (s > -4.97494 cm)'),
    Case('arm_beyond_the_pivot_line', change(
        follower__type='oscillating_roller', follower__pivot_distance=9.0,
        follower__arm_length=8.0, motion__start_position=[0.0, 0.0, 170.0, 170.0],
        motion__end_position=[0.0, 170.0, 170.0, 0.0]),
        # psi0 = acos((9^2 + 8^2 - 5^2) / (2 * 9 * 8)) = 33.557 deg; the arm reaches 180 deg at
        # s = 146.44 deg: first on the 0.05 deg check grid at 153.75 deg, u = 63.75 / 90,
        # s = 170 (u - sin(2 pi u) / 2 pi) = 146.551 deg (quoted in deg, not rad).
        'motion.laws[1] (cycloidal): s at 153.75 deg', '146.551',
        'arm angle psi0 + s must stay in (0, 180) deg; '
        f'psi0 = {math.degrees(math.acos((81 + 64 - 25) / 144)):g} deg'),
    Case('via_segment_out_of_range', change(motion__via_segment=[4], motion__via_deg=[100.0],
                                            motion__via_position=[1.0]),
         'motion.via_segment[0]', '4', 'must be a segment index in [0, 3]'),
    Case('too_few_samples', change(output__sample_count=2), 'output.sample_count', '2',
         'must be >= 8'),
    # Whole files.
    Case('empty_file', text(''), 'config', 'default.yaml', 'must be a mapping with a node name'),
    Case('yaml_syntax', text('/**:\n  ros__parameters: {length_unit: [m\n'), 'config',
         'default.yaml', 'is not valid YAML'),
    Case('no_node_section', text('cam_node:\n  ros__parameters:\n    length_unit: m\n'), 'config',
         'default.yaml', 'needs one of cam, /cam, /** with ros__parameters under it'),
    Case('parameters_not_a_mapping', text('/**:\n  ros__parameters: 5\n'), 'config',
         'default.yaml', 'needs one of cam, /cam, /**'),
    # Careless and hostile files: refused while the file is read, before any value is built.
    Case('duplicate_key', inserted('      roller_radius: 1.0\n', '      roller_radius: 3.5\n'),
         'follower.roller_radius', '3.5',
         f'is given twice, at lines {ROLLER_LINE} and {ROLLER_LINE + 1}'),
    Case('duplicate_section', inserted('    output:\n', '      sample_count: 36\n'),
         'output.sample_count', '360', 'is given twice'),
    Case('alias_bomb_in_follower', inserted('    follower:\n', alias_bomb(' ' * 6)), 'config',
         'default.yaml', f'uses the YAML anchor or alias &a0 at line {FOLLOWER_LINE + 1}: '
         'parameters files may not use anchors or aliases'),
    Case('alias_bomb_as_start_deg', text(DEFAULT_TEXT.replace(
        '      start_deg: [0.0, 90.0, 180.0, 240.0]\n',
        alias_bomb(' ' * 6) + '      start_deg: *a8\n')), 'config', 'default.yaml',
        f'uses the YAML anchor or alias &a0 at line {START_DEG_LINE}'),
    Case('huge_array', change(motion__start_deg=[0.0] * 2000), 'motion.start_deg',
         '[0.0, 0.0, 0.0, ...]', 'must have at most 1000 entries'),
    Case('long_array_quoted_short', change(motion__start_deg=[float(i) for i in range(999)]),
         'motion.start_deg', '(999 items)', 'must have 4 entries, one per entry of motion.laws'),
    Case('huge_string', change(recording__directory='d' * 5000), 'recording.directory',
         "ddd' (5000 characters)", 'must have at most 4096 characters'),
    Case('huge_file', text(DEFAULT_TEXT + '#' * (1 << 20)), 'config', 'default.yaml',
         'is larger than 1048576 bytes, the most a parameters file may hold'),
    Case('deep_nesting', text(DEFAULT_TEXT + 'deep: ' + '[' * 1000 + ']' * 1000 + '\n'),
         'config', 'default.yaml', 'nests deeper than 16 levels at line'),
    Case('too_many_values', text('/**: {' + ', '.join(f'k{i}: 1' for i in range(30000)) + '}\n'),
         'config', 'default.yaml', 'holds more than 20000 values'),
    Case('not_utf8', text('/**:\n  ros__parameters:\n    length_unit: \udce9\n'), 'config',
         'default.yaml', 'is not UTF-8 text'),
]
CASE_IDS = [case.id for case in CASES]
assert len(set(CASE_IDS)) == len(CASE_IDS)


def write_case(case: Case, folder: Path) -> Path:
    """Write the default config with the case's edit applied; the file is named default.yaml."""
    document = yaml.safe_load(DEFAULT.read_text())
    params = copy.deepcopy(document['/**']['ros__parameters'])
    content = case.edit(params)
    if content is None:
        content = yaml.safe_dump({'/**': {'ros__parameters': params}}, sort_keys=False)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / 'default.yaml'
    path.write_bytes(content.encode('utf-8', 'surrogateescape'))  # lone surrogates: raw bytes
    return path


def assert_names(message: str, case: Case) -> None:
    """Check that a message leads with the parameter, then gives the value and the rule."""
    assert len(message) <= MESSAGE_LIMIT, message
    assert message.startswith(f'{case.parameter} = '), message
    assert case.value in message, message
    assert case.rule in message, message


def test_the_default_config_is_valid(tmp_path):
    path = write_case(Case('none', lambda params: None, '', '', ''), tmp_path)
    assert build_design(load_config(path)).check.ok


@pytest.mark.parametrize('case', CASES, ids=CASE_IDS)
def test_core_rejects_with_parameter_value_and_rule(case, tmp_path):
    path = write_case(case, tmp_path)
    before = path.read_bytes()
    with pytest.raises(InvalidParameter) as caught:
        build_design(load_config(path))
    assert_names(str(caught.value), case)
    assert path.read_bytes() == before


@pytest.mark.parametrize('case', CASES, ids=CASE_IDS)
def test_cli_report_exits_2_with_one_line(case, tmp_path, capsys, monkeypatch):
    path = write_case(case, tmp_path / 'config')
    monkeypatch.chdir(tmp_path)
    assert main(['report', str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == ''
    assert err.endswith('\n') and err.count('\n') == 1, err
    assert_names(err.removeprefix('cam_ros report: ').rstrip('\n'), case)
    assert sorted(p.name for p in tmp_path.rglob('*')) == ['config', 'default.yaml']


def test_missing_file_is_one_line_too(tmp_path, capsys):
    missing = tmp_path / 'nowhere.yaml'
    assert main(['report', str(missing)]) == 2
    out, err = capsys.readouterr()
    assert out == '' and err.count('\n') == 1
    assert err.startswith(f'cam_ros report: config = {str(missing)!r}: cannot be read'), err


def run_report(path: Path) -> subprocess.CompletedProcess:
    """Run `python -m cam_ros.cli report PATH` in PATH's folder."""
    return subprocess.run([sys.executable, '-m', 'cam_ros.cli', 'report', str(path)],
                          capture_output=True, text=True, cwd=path.parent,
                          timeout=SUBPROCESS_TIMEOUT_S)


def test_cli_subprocess_exits_2_with_one_line(tmp_path, effort, report):
    cases = CASES if effort.heavy else CASES[::SUBPROCESS_STRIDE]
    paths = [write_case(case, tmp_path / case.id) for case in cases]
    with ThreadPoolExecutor(SUBPROCESS_WORKERS) as pool:
        runs = list(pool.map(run_report, paths))
    for case, path, run in zip(cases, paths, runs):
        assert run.returncode == 2, (case.id, run.returncode, run.stderr)
        assert run.stdout == '', (case.id, run.stdout)
        lines = run.stderr.splitlines()
        assert len(lines) == 1, (case.id, run.stderr)
        assert_names(lines[0].removeprefix('cam_ros report: '), case)
        assert sorted(p.name for p in path.parent.iterdir()) == ['default.yaml'], case.id
    report('bad config cases (core + in-process CLI)', len(CASES))
    report('bad config cases run as a cam_ros subprocess', len(cases))
