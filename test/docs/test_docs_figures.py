"""Measured figures in the docs match the files that hold them; the map reaches every page."""
from __future__ import annotations

import json
import re
import runpy
from pathlib import Path
from typing import Any

import pytest
from docs_support import DOCS, REPO

TABLES = runpy.run_path(str(REPO / 'tools' / 'docs_tables.py'), run_name='docs_tables')


def figures(name: str) -> dict[str, Any]:
    """Return a benchmark results file (benchmarks/NAME.json)."""
    return json.loads((REPO / 'benchmarks' / f'{name}.json').read_text())


def g3(value: float) -> str:
    """Format as the tables do: 3 significant digits."""
    return f'{value:.3g}'


def verdict(figure: dict[str, Any]) -> str:
    """Return a targeted figure's bound and whether the run met it, as the prose states them."""
    return f"target {figure['target'].split()[-1]}: {'met' if figure['met'] else 'missed'}"


def against(figure: dict[str, Any], unit: str) -> str:
    """Return 'value against reference unit' with 3 significant digits."""
    return f"{g3(figure['value'])} against {g3(figure['reference_value'])} {unit}"


def benchmark_quotes() -> list[str]:
    """Return the run's figures as docs/benchmarks.md quotes them in its prose."""
    run = figures('results')
    f = run['figures']
    machine = run['machine']
    service, ecam, dynamics = (f['service_p50_ms'], f['ecam_latency_p50_ms'],
                               f['design_evaluate_dynamics_ms'])
    recording = f['recording_publish_overhead']
    p50, p99, cpu = (f['machine_latency_p50_ms'], f['machine_latency_p99_ms'],
                     f['machine_cpu_us_per_message'])
    return [
        f"Run of {run['date'][:10]} {run['date'][11:16]}",
        f"{machine['cores']} cores, Python {machine['python'][:4]}, "
        f"NumPy {machine['numpy'][:3]}; {run['run_time_s']:.0f} s)",
        f"Service p50 {g3(service['ratio'])}× SetBool ({against(service, 'ms')}; "
        f"{verdict(service)})",
        f"p99 is {'met' if f['service_p99_ms']['met'] else 'missed'} "
        f"({f['service_p99_ms']['ratio']:.2f}×",
        f"E-cam p50 {g3(ecam['ratio'])}× the relay ({against(ecam, 'ms')}; {verdict(ecam)}",
        f"Publish loop with recording on {g3(recording['ratio'])}× off ({verdict(recording)}",
        f"This run: off {g3(recording['reference_value'])} us",
        f"the recording on {g3(recording['value'])} us",
        f"Evaluate with dynamics {g3(dynamics['ratio'])}× without ({against(dynamics, 'ms')}; "
        f"{verdict(dynamics)}",
        f"compares `design_report` with one 7,200-sample geometry pass: "
        f"{f['design_report_ms']['ratio']:.0f}× here",
        f"p50 at 16 axes {g3(p50['ratio'])}× the single axis ({against(p50, 'ms')}; "
        f"{verdict(p50)})",
        f"p99 at 16 axes {g3(p99['ratio'])}× ({against(p99, 'ms')}; {verdict(p99)})",
        f"CPU at 32 axes {g3(cpu['ratio'])}× ({cpu['value']:.0f} against "
        f"{cpu['reference_value']:.0f} µs a master message; {verdict(cpu)})",
    ]


def middleware_quotes() -> list[str]:
    """Return the middleware run's figures as docs/across-machines.md quotes them."""
    f = figures('middleware_results')['figures']

    def pair(key: str, digits: str = '.3g') -> tuple[str, str, str]:
        figure = f[key]
        return (format(figure['reference_value'], digits), format(figure['value'], digits),
                f"{figure['ratio']:.2f}")

    p50, p99, cpu = pair('profile_p50_ms'), pair('profile_p99_ms', '.2g'), pair(
        'profile_call_cpu_ms')
    size, idle_cpu = pair('profile_call_bytes', '.0f'), pair('profile_idle_cpu_percent')
    idle = [format(f['profile_idle_bytes_per_s'][key] / 1000, '.1f')
            for key in ('reference_value', 'value')]
    return [
        f'| p50 {p50[0]} ms, p99 {p99[0]} ms; node + client CPU {cpu[0]} ms per call; '
        f'{size[0]} B per call |',
        f'| p50 {p50[1]} ms ({p50[2]}×), p99 {p99[1]} ms ({p99[2]}×); CPU {cpu[1]} ms '
        f'({cpu[2]}×); {size[1]} B ({size[2]}×) |',
        f"| {idle[0]} kB/s, CPU {idle_cpu[0]} % | {idle[1]} kB/s "
        f"({f['profile_idle_bytes_per_s']['ratio']:.2f}×: heartbeats), CPU {idle_cpu[1]} % |",
    ]


def cli_quotes() -> list[str]:
    """Return the command line's round trips as docs/cli.md quotes them."""
    f = figures('results')['figures']
    rows = [figure for key, figure in f.items() if key.startswith('cli_')]
    first = rows[0]
    return [f"run of {first['extra']['date'][:10]} {first['extra']['date'][11:16]}",
            f"a bare rclpy process making the same call {first['reference_value']:.2f} s",
            f"`python -c pass` {first['extra']['python_s']:.2f} s",
            *(f"`{row['name']}` {row['value']:.2f} s (slowest {row['extra']['max_s']:.2f} s)"
              for row in rows)]


@pytest.mark.parametrize('page, quotes', [('benchmarks.md', benchmark_quotes),
                                          ('across-machines.md', middleware_quotes),
                                          ('cli.md', cli_quotes)])
def test_quoted_measurements_match_their_results_file(page: str, quotes) -> None:
    text = re.sub(r'\s*\n\s*', ' ', (DOCS / page).read_text())  # quotes may wrap
    missing = [quote for quote in quotes() if re.sub(r'\s*\n\s*', ' ', quote) not in text]
    assert not missing, f'{page} no longer quotes its results file: {missing}'


def test_generated_benchmark_table_is_results_json_as_make_bench_writes_it() -> None:
    page = (DOCS / 'benchmarks.md').read_text()
    assert TABLES['generated']('docs/benchmarks.md', page) == page, (
        'docs/benchmarks.md: run python tools/docs_tables.py')
    table = TABLES['markdown_table'](figures('results')['figures'].values())
    assert table == (REPO / 'benchmarks' / 'results.md').read_text()
    assert table in page


def test_generated_table_follows_a_changed_results_file() -> None:
    run = figures('results')
    keys = list(run['figures'])
    figure = run['figures']['service_p50_ms']
    mark = sum(1 for key in keys[:keys.index('service_p50_ms') + 1] if run['figures'][key]['note'])
    reference = figure['reference_value']
    figure.update(value=9.87, ratio=9.87 / reference, met=False)
    table = TABLES['markdown_table'](run['figures'].values())
    row = (f"| {figure['name']} [{mark}] | 9.87 ms | {figure['reference']}: {g3(reference)} ms | "
           f"{g3(9.87 / reference)} | {figure['target']} | **no** |")
    assert row in table.splitlines()
    assert table not in (DOCS / 'benchmarks.md').read_text()


def test_readme_map_reaches_every_page_in_one_click() -> None:
    readme = (REPO / 'README.md').read_text()
    linked = set(re.findall(r'\]\(docs/([\w-]+)\.md(?:#[\w-]+)?\)', readme))
    pages = {page.stem for page in DOCS.glob('*.md')} - {'index'}
    assert linked == pages, (sorted(pages - linked), sorted(linked - pages))
    assert len(readme.splitlines()) <= 250


@pytest.mark.parametrize('page', sorted(DOCS.glob('*.md')), ids=lambda page: page.name)
def test_each_page_says_what_it_is_for_under_its_title(page: Path) -> None:
    title, blank, purpose, *_ = page.read_text().splitlines()
    assert title.startswith('# ') and blank == '' and len(purpose.split()) >= 8, page.name
