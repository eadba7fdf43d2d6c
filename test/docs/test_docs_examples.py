"""Every example in README.md and docs/ runs or parses against the code (see docs_support)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from docs_support import document, example_id, examples, LANGUAGES, PAGES, REPO

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


FAILING_DESIGN = {
    'sh': ('cam_ros report too_steep.yaml', 'exit 1'),
    'console': ('$ cam_ros report too_steep.yaml\n...\nVerdict: VIOLATES its limits', None),
    'console-hidden': ('$ cam_ros report too_steep.yaml\nCam design report: too_steep.yaml',
                       'exit 1'),
}


@pytest.mark.parametrize('kind', FAILING_DESIGN)
def test_an_example_of_a_failing_design_passes_only_where_the_page_shows_it(kind, tmp_path):
    """A design that breaks its limits (exit 1) passes in a console block showing its verdict."""
    default = (REPO / 'config' / 'default.yaml').read_text()
    steep = default.replace('pressure_angle_deg: 30.0', 'pressure_angle_deg: 20.0')
    assert steep != default  # its pressure angle reaches 27.34 deg
    (tmp_path / 'too_steep.yaml').write_text(steep)
    block, error = FAILING_DESIGN[kind]
    page = tmp_path / 'page.md'
    page.write_text(f'```{kind.partition("-")[0]}\n{block}\n```\n')
    [example] = list(document(page))
    example.namespace['tmp_path'] = tmp_path
    if error is None:
        example.evaluate()
    else:
        with pytest.raises(AssertionError, match=error):
            example.evaluate()
