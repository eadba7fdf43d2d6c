"""The studio's fixtures: a design copied into its own folder, a running studio, Chromium."""
from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any, Iterator

import pytest
from prerequisites import require

from .studio_support import CONFIG_DIR, Studio

from cam_ros.studio.document import DesignDocument
from cam_ros.studio.server import run_in_thread

#: Debian's Chromium (Playwright's own browser download cannot run here).
CHROMIUM = Path('/usr/bin/chromium')


@pytest.fixture
def studio(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[Studio]:
    """Serve a copy of config/<name> (indirect parameter; default machine.yaml) in its folder."""
    name = getattr(request, 'param', 'machine.yaml')
    folder = tmp_path / 'designs'
    folder.mkdir()
    path = folder / name
    shutil.copy(CONFIG_DIR / name, path)
    server, thread, url = run_in_thread(DesignDocument(path))
    yield Studio(url, path)
    server.should_exit = True
    thread.join(timeout=30)


@pytest.fixture(scope='session')
def browser_type_launch_args(browser_type_launch_args: dict[str, Any]) -> dict[str, Any]:
    """Launch Debian's Chromium, headless; without it the browser tests skip (CI=true: fail),
    saying why."""
    require(str(CHROMIUM), "the studio's browser tests need Debian's chromium "
            '(apt-get install chromium)')
    return {**browser_type_launch_args, 'executable_path': str(CHROMIUM),
            'args': ['--no-sandbox']}


@pytest.fixture(scope='session')
def browser_context_args(browser_context_args: dict[str, Any]) -> dict[str, Any]:
    """Pages as on a desktop screen (the docs' screenshot too)."""
    return {**browser_context_args, 'viewport': {'width': 1500, 'height': 950}}
