"""
Draw docs/line_shaft.png: config/machine.yaml's line, limited, through a master loss and its
return, as the line shaft runs it (cam_ros.core.ecam.line_shaft, stepped as cam_node does).

    .venv/bin/python tools/line_shaft_figure.py [-o docs/line_shaft.png]

The master runs at cam speed, falls silent at 1.0 s (the node coasts, then stops the line shaft
on the cams once master.timeout has passed) and returns at 2.2 s elsewhere: the line shaft
catches up with its phase, then follows it exactly.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cam_ros.core.ecam.line_shaft import LineShaft, LOST  # noqa: E402
from cam_ros.core.ecam.master_tracker import MasterState  # noqa: E402
from cam_ros.core.ecam.path_limits import PathLimits  # noqa: E402
from cam_ros.core.ecam.slave_limits import SlaveLimits  # noqa: E402
from cam_ros.core.machine.machine import load_machine  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
NOMINAL, DT, TIMEOUT = 10.471975511965978, 0.004, 0.3
LIMITS = (SlaveLimits(2.5, 40.0), SlaveLimits(15.0, 30.0, 1, 2 * math.pi), SlaveLimits(2.0, 55.0))


def simulate():
    """Return times, master positions (nan while silent), virtual master positions and every
    axis's commands."""
    machine = load_machine(REPO / 'config' / 'machine.yaml')
    cams = [axis.cam for axis in machine.axes]
    shaft = LineShaft(PathLimits.of(cams, LIMITS, NOMINAL, math.radians(30.0)), one_way=True)
    times, master, virtual = [], [], []
    for k in range(round(5.5 / DT)):
        t = k * DT
        q = NOMINAL * t + (1.7 if t >= 2.2 else 0.0)  # back elsewhere (a new phase)
        silent = 1.0 <= t < 2.2
        if silent:
            if t >= 1.0 + TIMEOUT:
                shaft.halt(LOST)
            state = shaft.tick(round(t * 1e9))
        else:
            if t >= 2.2 and shaft.why:
                shaft.follow()
            state = shaft.master(MasterState(round(t * 1e9), q, NOMINAL, 0.0, 0.0, q))
        times.append(t)
        master.append(np.nan if silent else q)
        virtual.append(state.theta)
    theta = np.array(virtual)
    commands = np.stack([np.asarray(cam.derivatives(theta).y, dtype=float) for cam in cams], 1)
    return np.array(times), np.array(master), theta, commands, [a.name for a in machine.axes]


def draw(path: Path) -> None:
    """Draw the figure to path."""
    t, master, theta, commands, names = simulate()
    figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9, 6))
    top.plot(t, np.degrees(master) % 360, '.', markersize=2, label='master (silent: none)')
    top.plot(t, np.degrees(theta) % 360, linewidth=1.2, label='line shaft θv')
    top.set_ylabel('machine angle (deg)')
    top.legend(loc='upper left', fontsize=8)
    scale = {'feeder': 1e3, 'knife': 180 / math.pi, 'jaw': 1e3}
    units = {'feeder': 'mm', 'knife': 'deg / 10 (mod 360)', 'jaw': 'mm'}
    for column, name in enumerate(names):
        values = commands[:, column] * scale[name]
        if name == 'knife':
            values = (values % 360.0) / 10.0
        bottom.plot(t, values, label=f'{name} ({units[name]})')
    for axis in (top, bottom):
        axis.axvspan(1.0, 1.0 + TIMEOUT, color='0.92', label=None)
        axis.axvspan(1.0 + TIMEOUT, 2.2, color='0.85')
    bottom.set_xlabel('time (s): silent from 1.0 s, lost at 1.3 s (stop on the cams), back '
                      'at 2.2 s (catch-up)')
    bottom.set_ylabel('commands')
    bottom.legend(loc='upper left', fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('-o', '--output', type=Path, default=REPO / 'docs' / 'line_shaft.png')
    draw(parser.parse_args().output)


if __name__ == '__main__':
    main()
