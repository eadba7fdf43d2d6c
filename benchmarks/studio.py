"""
The studio in a real browser: from an edit to the updated plots and verdict (issue 48).

A studio serves the design in a thread; headless Chromium (Debian's, /usr/bin/chromium) loads
the page. Two edits per design: a phase shift of the axis shown (`<axis>.master.offset_deg`:
its coupling, the pairs and the timing diagram change) and cam_speed (every axis's velocity,
acceleration, jerk and checks change). In the page, each edit types a value and fires the
field's change event, as a user's Enter does; the time runs until the page has drawn the answer
(body[data-seq] moved on, state ready) and the browser has painted the next frame. Every edit
is to a value not given before, so the studio has no answer kept for it (studio/memory.py).
The floor, measured the same way in the same page, is a round trip of GET /api/design and a
painted frame: what any answer costs without the core. Designs: config/machine.yaml, and a
16-axis machine of config/default.yaml's cam with 15 clearance pairs between neighbours.

Run alone (not in `make bench`): ``.venv/bin/python -m benchmarks.studio``; ``--write`` puts its
figures into benchmarks/results.json and results.md as ``benchmarks.cli --write`` does (each
carries the date and load average of its run), then ``python tools/docs_tables.py``.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import tempfile
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from benchmarks.cli import write_into
from benchmarks.machine import machine_values
from benchmarks.report import Figure, markdown_table, Target
from benchmarks.ros import BENCH_DIR, REPO
from cam_ros.recording.parameters import params_file
from cam_ros.studio.document import DesignDocument
from cam_ros.studio.server import run_in_thread

CHROMIUM = '/usr/bin/chromium'
#: The issue's bounds on the p50 from an edit to the updated plots and verdict (ms).
MACHINE_TARGET, LARGE_TARGET = Target('<=', 100.0, on='value'), Target('<=', 250.0, on='value')
LARGE_AXES = 16

#: In the page: time an edit of key to each of values (and as many floor round trips), in ms.
TIME_EDITS = """async ([key, values]) => {
  const frame = () => new Promise(done => requestAnimationFrame(() => done()));
  const box = () => document.querySelector(`[data-key="${key}"]`);
  const edits = [], floor = [];
  for (const value of values) {
    const seq = Number(document.body.dataset.seq);
    const start = performance.now();
    box().value = value;
    box().dispatchEvent(new Event('change'));
    while (!(Number(document.body.dataset.seq) > seq && document.body.dataset.state === 'ready')) {
      if (document.body.dataset.state === 'error') throw new Error('the edit was refused');
      await frame();
    }
    await frame();
    edits.push(performance.now() - start);
    const before = performance.now();
    await (await fetch('api/design')).json();
    await frame();
    floor.push(performance.now() - before);
  }
  return [edits, floor];
}"""


@dataclass(frozen=True)
class StudioSizes:
    """How many edits are timed per design, after how many unmeasured ones."""

    edits: int = 41
    warmup: int = 5


def large_machine(directory: Path) -> Path:
    """Write a machine of LARGE_AXES copies of default.yaml's cam, neighbours checked in pairs."""
    values = machine_values(LARGE_AXES)
    pairs = LARGE_AXES - 1
    values.update({
        'interference.axis_a': [f'a{index}' for index in range(pairs)],
        'interference.axis_b': [f'a{index + 1}' for index in range(pairs)],
        'interference.type': ['clearance'] * pairs,
        'interference.offset': [10.0] * pairs, 'interference.gain_a': [-1.0] * pairs,
        'interference.gain_b': [1.0] * pairs, 'interference.min_clearance': [1.0] * pairs,
        'interference.zone_a': [0.0] * pairs, 'interference.zone_b': [0.0] * pairs,
        'interference.min_margin_deg': [0.0] * pairs})
    path = directory / f'machine_{LARGE_AXES}_axes.yaml'
    path.write_text(params_file(values, f'{LARGE_AXES} axes of default.yaml, '
                                        f'{pairs} clearance pairs'))
    return path


def time_edits(page: Any, path: Path, edits: Sequence[tuple[str, str]],
               sizes: StudioSizes) -> list[tuple[np.ndarray, np.ndarray]]:
    """Return the ms of each timed edit and of each floor round trip on a studio of path.

    edits: (the axis whose tab is shown, the key edited) of each kind of edit.
    """
    server, thread, url = run_in_thread(DesignDocument(path))
    timed = []
    try:
        page.set_default_timeout(120_000)
        page.goto(url)
        page.wait_for_function("document.body.dataset.state === 'ready'")
        for axis, key in edits:
            seq = int(page.evaluate('document.body.dataset.seq'))
            page.click(f'[data-axis="{axis}"]')
            page.wait_for_function(f"Number(document.body.dataset.seq) > {seq} && "
                                   "document.body.dataset.state === 'ready'")
            value = float(page.locator(f'[data-key="{key}"]').input_value())
            values = [repr(value * (1.0 + 1e-3 * step) if key == 'cam_speed'
                           else value + 0.5 * step)
                      for step in range(1, sizes.warmup + sizes.edits + 1)]
            page.evaluate(TIME_EDITS, [key, values[:sizes.warmup]])
            edit, floor = page.evaluate(TIME_EDITS, [key, values[sizes.warmup:]])
            timed.append((np.asarray(edit), np.asarray(floor)))
    finally:
        server.should_exit = True
        thread.join(timeout=30)
    return timed


def studio_figures(sizes: StudioSizes = StudioSizes()) -> list[Figure]:
    """Measure the edit-to-drawn p50 of config/machine.yaml and of the 16-axis machine.

    Two edits each: a phase shift of the axis shown (`<axis>.master.offset_deg`: one axis's
    coupling, the pairs and the timing diagram change) and cam_speed (every axis changes).
    """
    from playwright.sync_api import sync_playwright

    figures = []
    date = datetime.now(timezone.utc).isoformat(timespec='seconds')
    load = os.getloadavg()[0]  # others' work on the machine slows the page and the studio
    with tempfile.TemporaryDirectory(prefix='cam_ros_studio_bench_') as folder, \
            sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=['--no-sandbox'])
        page = browser.new_page(viewport={'width': 1500, 'height': 950})
        shutil.copy(REPO / 'config' / 'machine.yaml', Path(folder) / 'machine.yaml')
        for key, name, path, axis, target in (
                ('studio_edit_machine', 'config/machine.yaml', Path(folder) / 'machine.yaml',
                 'knife', MACHINE_TARGET),
                ('studio_edit_16_axes', f'{LARGE_AXES} axes, {LARGE_AXES - 1} pairs',
                 large_machine(Path(folder)), 'a0', LARGE_TARGET)):
            edits = ((axis, f'{axis}.master.offset_deg'), (axis, 'cam_speed'))
            for (_, edited), (times, floor) in zip(edits, time_edits(page, path, edits, sizes)):
                what = 'cam_speed' if edited == 'cam_speed' else 'phase shift'
                figures.append(Figure(
                    f'{key}_{"speed" if edited == "cam_speed" else "phase"}_p50_ms',
                    f'studio: {what} to drawn, {name}, p50', float(np.median(times)), 'ms',
                    'GET /api/design round trip and a frame, p50', float(np.median(floor)),
                    target, note=f'in headless Chromium, edit of {edited}; plots drawn and '
                                 f'painted. Run of {date[:16]}, load average {load:.1f}.',
                    extra={'p90_ms': float(np.percentile(times, 90)), 'edits': len(times),
                           'date': date, 'load_average': load}))
        browser.close()
    return figures


def main(argv: Sequence[str] | None = None) -> int:
    """Measure and print the studio's figures (and write them as JSON with --json)."""
    parser = argparse.ArgumentParser(prog='python -m benchmarks.studio', description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--json', type=Path, default=None, help='write the figures here')
    parser.add_argument('--edits', type=int, default=StudioSizes.edits)
    parser.add_argument('--write', action='store_true',
                        help='put the figures into benchmarks/results.json and results.md')
    args = parser.parse_args(argv)
    figures = studio_figures(StudioSizes(edits=args.edits))
    data = [figure.as_json() for figure in figures]
    if args.json is not None:
        args.json.write_text(json.dumps(data, indent=2) + '\n')
    print(markdown_table(data))
    if args.write:
        write_into(BENCH_DIR / 'results.json', BENCH_DIR / 'results.md', figures)
    return 0 if all(figure.met for figure in figures) else 1


if __name__ == '__main__':
    raise SystemExit(main())
