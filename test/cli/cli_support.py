"""Shared helpers of the CLI tests: configs, in-process runs, the installed console script."""
from __future__ import annotations

import math
import shutil
import struct
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest
import yaml

from cam_ros.cli import main

REPO = Path(__file__).resolve().parents[2]
CONFIG_DIR = REPO / 'config'
DEFAULT_CONFIG = CONFIG_DIR / 'default.yaml'
#: Every config file shipped with the package (others are being added: glob them).
SHIPPED_CONFIGS = sorted(path for path in CONFIG_DIR.glob('*.yaml')
                         if '\n    axes:' not in path.read_text())  # not machine files
#: The shipped configs that shape a cam (not the motion-only ones, follower.type none).
SHIPPED_CAMS = [path for path in SHIPPED_CONFIGS if 'type: none' not in path.read_text()]

# Seed 000 (config/default.yaml), written out independently of the code under test.
CM = 0.01
RISE = 2 * CM  # m, cycloidal rise over 90-180 deg
RISE_START, RISE_SPAN = math.pi / 2, math.pi / 2
RETURN_START, RETURN_SPAN = 4 * math.pi / 3, 2 * math.pi / 3  # simple harmonic return
BASE_RADIUS, ROLLER_RADIUS, OFFSET = 4 * CM, 1 * CM, 0.5 * CM
OMEGA = 2 * math.pi  # rad/s
SIGMA = -1  # clockwise
PRESSURE_LIMIT_DEG = 30.0
MIN_RADIUS = 0.5 * CM

# Follower sections (config units: cm; oscillating positions in deg) replacing seed 000's
# translating roller, so that every follower kind runs through every command.
FOLLOWERS: dict[str, dict[str, Any]] = {
    'translating_roller': {'type': 'translating_roller', 'base_radius': 4.0,
                           'roller_radius': 1.0, 'offset': 0.5},
    'translating_flat': {'type': 'translating_flat', 'base_radius': 4.0},
    'oscillating_roller': {'type': 'oscillating_roller', 'base_radius': 4.0,
                           'roller_radius': 1.0, 'pivot_distance': 9.0, 'arm_length': 7.0},
    'oscillating_flat': {'type': 'oscillating_flat', 'base_radius': 4.0,
                         'pivot_distance': 12.0, 'face_offset': -1.0},
}
OSCILLATING_STROKE_DEG = 15.0


@dataclass
class Run:
    """Exit code and captured output of one in-process `cam_ros` run."""

    code: int
    out: str
    err: str


def run_cli(capsys: pytest.CaptureFixture, *argv: object) -> Run:
    """Run main(argv) in this process and capture what it printed."""
    code = main([str(arg) for arg in argv])
    captured = capsys.readouterr()
    return Run(code, captured.out, captured.err)


def assert_one_error_line(run: Run, command: str, *fragments: str) -> None:
    """Check an exit-2 run: nothing on stdout, one line 'cam_ros <command>: ...' on stderr."""
    assert run.code == 2, run
    assert run.out == ''
    lines = run.err.splitlines()
    assert len(lines) == 1, run.err
    assert lines[0].startswith(f'cam_ros {command}: '), lines[0]
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


def load_parameters(path: Path = DEFAULT_CONFIG) -> dict[str, Any]:
    """Return the ros__parameters mapping of a config file."""
    return yaml.safe_load(path.read_text())['/**']['ros__parameters']


def write_config(directory: Path, name: str, edit: Callable[[dict[str, Any]], None]) -> Path:
    """Write seed 000's config after edit(parameters) changed it; return its path."""
    parameters = load_parameters()
    edit(parameters)
    path = directory / f'{name}.yaml'
    path.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    return path


def follower_config(directory: Path, kind: str) -> Path:
    """Write seed 000's motion with the given follower kind."""
    def edit(parameters: dict[str, Any]) -> None:
        parameters['follower'] = dict(FOLLOWERS[kind])
        if kind.startswith('oscillating'):
            motion = parameters['motion']
            for key in ('start_position', 'end_position'):
                motion[key] = [OSCILLATING_STROKE_DEG * value / 2.0 for value in motion[key]]
    return write_config(directory, kind, edit)


def console_script() -> str:
    """Return the installed `cam_ros` executable of this environment."""
    places = [Path(sys.executable).parent, Path(sys.prefix) / 'lib' / 'cam_ros']
    found = shutil.which('cam_ros', path=':'.join(str(place) for place in places))
    assert found, f'cam_ros console script not installed in {places}'
    return found


def seed_000_motion(theta: np.ndarray, rise: float = RISE) -> tuple[np.ndarray, ...]:
    """Return s, ds/dtheta, d2s/dtheta2, d3s/dtheta3 of seed 000 in closed form (theta in rad)."""
    theta = np.mod(theta, 2 * math.pi)
    s, ds, d2s, d3s = (np.zeros_like(theta) for _ in range(4))
    up = (theta >= RISE_START) & (theta < RISE_START + RISE_SPAN)
    u = (theta[up] - RISE_START) / RISE_SPAN
    s[up] = rise * (u - np.sin(2 * math.pi * u) / (2 * math.pi))
    ds[up] = rise / RISE_SPAN * (1 - np.cos(2 * math.pi * u))
    d2s[up] = 2 * math.pi * rise / RISE_SPAN ** 2 * np.sin(2 * math.pi * u)
    d3s[up] = 4 * math.pi ** 2 * rise / RISE_SPAN ** 3 * np.cos(2 * math.pi * u)
    s[(theta >= RISE_START + RISE_SPAN) & (theta < RETURN_START)] = rise
    back = theta >= RETURN_START
    x = math.pi * (theta[back] - RETURN_START) / RETURN_SPAN
    k = math.pi / RETURN_SPAN
    s[back] = rise / 2 * (1 + np.cos(x))
    ds[back] = -rise / 2 * k * np.sin(x)
    d2s[back] = -rise / 2 * k ** 2 * np.cos(x)
    d3s[back] = rise / 2 * k ** 3 * np.sin(x)
    return s, ds, d2s, d3s


def seed_000_roller(theta: np.ndarray, base_radius: float = BASE_RADIUS
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Return pressure angle (rad) and surface radius of curvature (m) of seed 000's roller.

    Closed forms of the kinematics notes: tan phi = (v - sigma e) / (d + s); pitch radius
    W^3 / ((d+s)^2 + (v - sigma e)(2v - sigma e) - a (d+s)), W = hypot(d + s, v - sigma e).
    """
    s, v, a, _ = seed_000_motion(theta)
    d = math.sqrt((base_radius + ROLLER_RADIUS) ** 2 - OFFSET ** 2)
    along, across = d + s, v - SIGMA * OFFSET
    pitch = np.hypot(along, across) ** 3 / (
        along ** 2 + across * (2 * v - SIGMA * OFFSET) - a * along)
    return np.arctan2(across, along), pitch - ROLLER_RADIUS


def png_size(data: bytes) -> tuple[int, int]:
    """Return (width, height) from a PNG's IHDR chunk."""
    assert data[:8] == b'\x89PNG\r\n\x1a\n'
    assert data[12:16] == b'IHDR'
    return struct.unpack('>II', data[16:24])
