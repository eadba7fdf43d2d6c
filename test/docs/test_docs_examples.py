"""Every example in README.md and docs/ runs or parses against the code (see docs_support)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from docs_support import example_id, examples, LANGUAGES, PAGES, REPO

EXAMPLES = examples()
DIRECTIVES = ('{toctree}', '{eval-rst}')


@pytest.mark.parametrize('example', EXAMPLES, ids=example_id)
def test_example_matches_the_code(example, tmp_path: Path) -> None:
    example.namespace['tmp_path'] = tmp_path
    example.evaluate()


@pytest.mark.parametrize('page', PAGES, ids=lambda page: str(page.relative_to(REPO)))
def test_every_code_block_names_a_checked_language(page: Path) -> None:
    fences = re.findall(r'^\s*```(\S*)', page.read_text(), flags=re.M)
    openings = fences[::2]  # a fence opens, the next one closes it (no nested fences here)
    assert all(fence == '' for fence in fences[1::2]), (page, fences)
    unchecked = [fence for fence in openings if fence not in LANGUAGES + DIRECTIVES]
    assert not unchecked, f'{page.name}: blocks whose examples no test checks: {unchecked}'
    found = sum(1 for example in EXAMPLES if Path(example.path) == page)
    assert found == sum(fence in LANGUAGES for fence in openings), (
        f'{page.name}: Sybil found {found} examples, the page has {len(openings)} blocks')
