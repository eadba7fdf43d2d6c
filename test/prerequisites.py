"""The one rule for a test whose prerequisite (a tool, root, a browser) is missing.

Locally the test skips, saying what is missing; with CI=true (as .ci/run sets it) it fails with
one line naming the prerequisite, so a CI machine that lacks it never passes by skipping.
Import it as `from prerequisites import require` (test/ is on sys.path, as for conftest).
"""
from __future__ import annotations

import os
import shutil

import pytest


def under_ci() -> bool:
    """Return whether this run is a CI run (CI=true, as CI services and .ci/run set it)."""
    return os.environ.get('CI', '').strip().lower() in ('true', '1', 'yes')


def require(prerequisite: str, why: str, present: bool | None = None) -> None:
    """
    Go on if prerequisite is there; otherwise skip (locally) or fail (CI=true), naming it.

    prerequisite: a program looked up on PATH (or a path to one), unless present says whether
    it is there (root, a capability). why: what needs it and how to get it, in a few words.
    """
    if present is None:
        present = shutil.which(prerequisite) is not None
    if present:
        return
    line = f'missing prerequisite {prerequisite}: {why}'
    if under_ci():
        pytest.fail(f'{line} (CI=true: a missing prerequisite fails)', pytrace=False)
    pytest.skip(line)
