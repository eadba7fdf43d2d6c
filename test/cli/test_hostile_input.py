"""Files that are no design at all get one line naming the file and what is wrong, exit 2."""
from __future__ import annotations

import pytest
from cli_support import assert_one_error_line, run_cli


@pytest.mark.parametrize('content, where', [
    (b'abc\x00\x01\x02def\n', 'U+0000 at line 1, column 4'),
    (bytes(range(128)) * 4, 'U+0000 at line 1, column 1'),
    (b'/**:\n  ros__parameters:\n    cam_speed: 1.0\x07\n', 'U+0007 at line 3, column 19'),
])
@pytest.mark.parametrize('command', ['report', 'sample'])
def test_a_binary_file_as_a_design_is_refused_in_one_line(tmp_path, capsys, content, where,
                                                          command):
    path = tmp_path / 'some.bin'
    path.write_bytes(content)
    run = run_cli(capsys, command, path)
    assert_one_error_line(run, command, f"config = '{path}'", 'is not text (a binary file?)',
                          where)


def test_a_file_that_is_not_utf8_is_refused_in_one_line(tmp_path, capsys):
    path = tmp_path / 'latin1.yaml'
    path.write_bytes('/**:\n  ros__parameters:\n    length_unit: \xb5m\n'.encode('latin-1'))
    run = run_cli(capsys, 'report', path)
    assert_one_error_line(run, 'report', f"config = '{path}'", 'is not UTF-8 text (byte 41)')
