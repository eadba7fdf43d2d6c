"""`cam_ros export --switches`: CSV and ST read back (csv module, a regex) equal the config."""
from __future__ import annotations

import csv
import re

import pytest
from cli_support import (assert_one_error_line, DEFAULT_CONFIG, load_parameters, run_cli,
                         write_config)

#: Tracks with a wrap through 0, on at 360 (= 0), a name with quotes, a comma and a '#'.
TRACKS = {'names': ['glue', 'it\'s, "x"', '#knife'], 'on_deg': [40.0, 350.5, 360.0],
          'off_deg': [100.0, 10.25, 300.0], 'lead_time': [0.002, 0.0, 0.0105],
          'hysteresis_deg': 0.25}
ST_ITEM = re.compile(r"\(TrackNumber := (\d+), Name := '((?:[^'$]|\$.)*)', "
                     r'FirstOnPosition := ([-0-9.]+), LastOnPosition := ([-0-9.]+), '
                     r'OnCompensation := ([-0-9.]+), OffCompensation := ([-0-9.]+), '
                     r'Hysteresis := ([-0-9.]+)\)')


def switch_config(tmp_path, tracks=TRACKS):
    """Write seed 000's config with the given switches.* mapping."""
    return write_config(tmp_path, 'switches', lambda p: p.update(switches=dict(tracks)))


def export(capsys, tmp_path, file_format):
    """Run export --switches and return the file's text and the config's switches."""
    config = switch_config(tmp_path)
    target = tmp_path / f'tracks.{file_format}'
    run = run_cli(capsys, 'export', config, '--switches', '--format', file_format, '-o', target)
    assert run.code == 0 and run.err == '', run
    assert run.out == f'wrote {target}: 3 cam switch tracks ({file_format})\n'
    return target.read_text(), load_parameters(config)['switches']


def expected_rows(switches):
    """Return the config's tracks as (name, on, off, lead, hysteresis), angles modulo 360."""
    return [(name, on % 360.0, off % 360.0, lead, switches['hysteresis_deg'])
            for name, on, off, lead in zip(switches['names'], switches['on_deg'],
                                           switches['off_deg'], switches['lead_time'])]


def test_csv_rows_equal_the_config_with_a_header_and_the_wrap_said(tmp_path, capsys):
    text, switches = export(capsys, tmp_path, 'csv')
    comments = [line for line in text.splitlines() if line.startswith('# ')]
    table = list(csv.reader(line for line in text.splitlines() if not line.startswith('# ')))
    assert table[0] == ['name', 'on_deg', 'off_deg', 'lead_time_s', 'hysteresis_deg']
    rows = [(name, *map(float, values)) for name, *values in table[1:]]
    assert rows == expected_rows(switches)
    assert any('off < on wraps through 0 (TrackNumber 2)' in line for line in comments)


def test_st_structs_equal_the_config_in_plcopen_names(tmp_path, capsys):
    text, switches = export(capsys, tmp_path, 'st')
    items = ST_ITEM.findall(text)
    assert [int(item[0]) for item in items] == [1, 2, 3]
    names = [re.sub(r'\$(.)', r'\1', item[1]) for item in items]
    values = [tuple(map(float, item[2:])) for item in items]
    expected = expected_rows(switches)
    assert names == [row[0] for row in expected]
    assert values == [(on, off, -lead, -lead, hysteresis)
                      for _, on, off, lead, hysteresis in expected]
    assert re.search(r'CamSwitches : ARRAY\[1\.\.3\] OF CamRosSwitchTrack := \[', text)
    for field in ('TrackNumber : INT;', 'FirstOnPosition : LREAL;', 'LastOnPosition : LREAL;'):
        assert field in text
    assert text.count('STRUCT') == 2 and text.rstrip().endswith('END_VAR')


def test_lead_time_defaults_to_zero(tmp_path, capsys):
    config = switch_config(tmp_path, {key: value for key, value in TRACKS.items()
                                      if key != 'lead_time'})
    run = run_cli(capsys, 'export', config, '--switches', '-o', tmp_path / 'tracks.csv')
    assert run.code == 0, run
    rows = list(csv.reader(line for line in (tmp_path / 'tracks.csv').read_text().splitlines()
                           if not line.startswith('# ')))[1:]
    assert [float(row[3]) for row in rows] == [0.0] * len(TRACKS['names'])


@pytest.mark.parametrize('options, fragments', [
    ((), ('switches.names = []', 'at least one track')),
    (('--format', 'sew'), ("--format = 'sew'", 'csv, st')),
    (('--cam-table',), ('--cam-table', 'cannot go with --switches')),
    (('--points', '10'), ('--points = 10', 'cannot go with --switches')),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, options, fragments):
    target = tmp_path / 'tracks.csv'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '--switches', *options, '-o', target)
    assert_one_error_line(run, 'export', *fragments)
    assert not target.exists()
