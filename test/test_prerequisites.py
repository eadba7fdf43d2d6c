"""The rule for a missing prerequisite: skip locally, fail with one line under CI=true."""
from __future__ import annotations

import sys

import pytest
from prerequisites import require

MISSING = 'no-such-tool-cam-ros'


@pytest.mark.parametrize('ci', ['', 'false'])
def test_a_missing_tool_skips_locally_naming_it(monkeypatch, ci):
    monkeypatch.setenv('CI', ci)
    with pytest.raises(pytest.skip.Exception) as skipped:
        require(MISSING, 'a test needs it (apt-get install it)')
    assert str(skipped.value) == (f'missing prerequisite {MISSING}: a test needs it '
                                  '(apt-get install it)')


@pytest.mark.parametrize('ci', ['true', 'TRUE', '1'])
def test_a_missing_prerequisite_fails_in_one_line_under_ci(monkeypatch, ci):
    monkeypatch.setenv('CI', ci)
    with pytest.raises(pytest.fail.Exception) as failed:
        require('root', 'network namespaces need it', present=False)
    message = str(failed.value)
    assert message.splitlines() == [message]
    assert message.startswith('missing prerequisite root: network namespaces need it')
    assert not failed.value.pytrace


@pytest.mark.parametrize('ci', ['', 'true'])
def test_a_present_prerequisite_lets_the_test_run(monkeypatch, ci):
    monkeypatch.setenv('CI', ci)
    require(sys.executable, 'the interpreter itself')  # a path on disk, found by shutil.which
    require('root', 'given as present', present=True)
