"""`make docs` builds: Sphinx with MyST Markdown, warnings as errors, the API from docstrings."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from docs_support import DOCS, REPO


def test_docs_build_without_warnings_and_document_the_public_api(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, '-m', 'sphinx', '-W', '--keep-going', '-q', '-E',
                           '-b', 'html', str(DOCS), str(tmp_path)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stderr == '', done.stderr
    api = (tmp_path / 'api.html').read_text()
    from cam_ros import core
    for name in core.__all__ + ['CamClient', 'CamClient.evaluate', 'CamClientError']:
        assert re.search(rf'id="cam_ros\.(core|client)\.{re.escape(name)}"', api), name
    for page in DOCS.glob('*.md'):
        assert (tmp_path / f'{page.stem}.html').exists(), page.name


def test_make_docs_runs_the_same_build() -> None:
    makefile = (REPO / 'Makefile').read_text()
    recipe = makefile.split('\ndocs: setup\n', 1)[1].split('\n', 1)[0]
    assert '-m sphinx -W' in recipe and ' docs docs/_build/html' in recipe, recipe
