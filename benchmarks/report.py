"""Figures, their targets, and the markdown table and JSON they are reported as."""
from __future__ import annotations

import json
import math
import operator
import os
import platform
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Iterable

import numpy as np

COMPARISONS = {'<=': operator.le, '>=': operator.ge}


@dataclass(frozen=True)
class Target:
    """A bound the issue sets on a figure's ratio (on='ratio') or on its measured value."""

    op: str
    bound: float
    on: str = 'ratio'

    def met(self, figure: Figure) -> bool:
        """Return whether the figure meets the bound."""
        value = figure.ratio if self.on == 'ratio' else figure.value
        return bool(COMPARISONS[self.op](value, self.bound))

    def text(self, unit: str) -> str:
        """Describe the bound for the table, e.g. 'ratio <= 4' or '>= 20000 msg/s'."""
        return (f'ratio {self.op} {self.bound:g}' if self.on == 'ratio'
                else f'{self.op} {self.bound:g} {unit}')


@dataclass(frozen=True)
class Figure:
    """
    One measured figure and the reference measured in the same run that it is divided by.

    ratio = value / reference_value, or reference_value / value when `inverse` (a speed-up).
    `extra` holds further numbers worth keeping in the JSON (p99, counts, ...).
    """

    key: str
    name: str
    value: float
    unit: str
    reference: str
    reference_value: float
    target: Target | None = None
    note: str = ''
    inverse: bool = False
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def ratio(self) -> float:
        """Return the figure over its reference (or the reverse for a speed-up)."""
        numerator, denominator = self.value, self.reference_value
        if self.inverse:
            numerator, denominator = denominator, numerator
        return numerator / denominator if denominator else math.nan

    @property
    def met(self) -> bool | None:
        """Return whether the target is met, or None without a target."""
        return None if self.target is None else self.target.met(self)

    def as_json(self) -> dict[str, Any]:
        """Return the figure as a JSON-ready mapping (ratio and verdict included)."""
        data = asdict(self)
        data['target'] = None if self.target is None else self.target.text(self.unit)
        data.update(ratio=self.ratio if math.isfinite(self.ratio) else None, met=self.met)
        return data


def number(value: float) -> str:
    """Format a measured number with 3 significant digits, thousands grouped."""
    if value >= 1000:
        return f'{value:,.0f}'
    return f'{value:.3g}'


def markdown_table(figures: Iterable[dict[str, Any]]) -> str:
    """Return figures (as_json mappings) as a markdown table, their notes numbered below it."""
    lines = ['| Figure | Measured | Reference (same run) | Ratio | Target | Met |',
             '|---|---|---|---|---|---|']
    notes: list[str] = []
    for figure in figures:
        mark = ''
        if figure['note']:
            notes.append(figure['note'])
            mark = f' [{len(notes)}]'
        met = {None: '', True: 'yes', False: '**no**'}[figure['met']]
        unit, ratio = figure['unit'], figure['ratio']  # None: no ratio (a zero reference)
        lines.append(f"| {figure['name']}{mark} | {number(figure['value'])} {unit} | "
                     f"{figure['reference']}: {number(figure['reference_value'])} {unit} | "
                     f"{'nan' if ratio is None else format(ratio, '.3g')} | "
                     f"{figure['target'] or ''} | {met} |")
    lines.append('')
    lines.extend(f'[{index}] {note}' for index, note in enumerate(notes, start=1))
    return '\n'.join(lines) + '\n'


def machine() -> dict[str, Any]:
    """Describe the machine: CPU model, cores, Python, NumPy and RMW."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path('/proc/cpuinfo').read_text().splitlines():
            if line.startswith('model name'):
                cpu = line.split(':', 1)[1].strip()
                break
    except OSError:
        pass
    return {'cpu': cpu, 'cores': os.cpu_count(), 'python': platform.python_version(),
            'numpy': np.__version__, 'platform': platform.platform(),
            'rmw': os.environ.get('RMW_IMPLEMENTATION', 'rmw_fastrtps_cpp (default)')}


def write_results(figures: list[Figure], header: dict[str, Any], json_path: Path,
                  markdown_path: Path) -> str:
    """Write the figures to JSON and the markdown table to its file; return the table."""
    table = markdown_table(figure.as_json() for figure in figures)
    results = {**header, 'figures': {figure.key: figure.as_json() for figure in figures}}
    json_path.write_text(json.dumps(results, indent=2, allow_nan=False) + '\n')
    markdown_path.write_text(table)
    return table
