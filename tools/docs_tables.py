"""Write the documentation's measured tables from the files that hold the measurements.

`python tools/docs_tables.py` rewrites, between their markers, the tables in docs/ that are
generated (today the benchmark table of docs/benchmarks.md, from benchmarks/results.json);
`--check` only says whether they are current (test/docs/test_docs_figures.py runs the same
comparison in `make test`).
"""
from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from benchmarks.report import markdown_table  # noqa: E402 - the path above makes it importable

BEGIN = '<!-- generated from {source} by tools/docs_tables.py: edit that file, not this table -->'
END = '<!-- end of generated table -->'
#: page -> the measurement file its generated table comes from
TABLES = {'docs/benchmarks.md': 'benchmarks/results.json'}


def generated(page: str, text: str) -> str:
    """Return the page's text with its generated table rewritten from its source."""
    source = TABLES[page]
    begin = BEGIN.format(source=source)
    pattern = re.compile(re.escape(begin) + r'\n.*?' + re.escape(END), flags=re.S)
    if not pattern.search(text):
        raise SystemExit(f'{page}: no generated table (the line {begin!r} ... {END!r})')
    table = markdown_table(json.loads((REPO / source).read_text())['figures'].values())
    return pattern.sub(lambda _: f'{begin}\n\n{table}\n{END}', text)


def main(argv: list[str] | None = None) -> int:
    """Rewrite (or with --check, compare) every generated table; return the exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--check', action='store_true', help='only report stale tables (exit 1)')
    args = parser.parse_args(argv)
    stale = []
    for page in TABLES:
        path = REPO / page
        text = path.read_text()
        new = generated(page, text)
        if new != text:
            stale.append(page)
            if not args.check:
                path.write_text(new)
    verb = 'stale' if args.check else 'rewritten'
    print(f'{verb}: {", ".join(stale)}' if stale else 'generated tables are current')
    return 1 if stale and args.check else 0


if __name__ == '__main__':
    sys.exit(main())
