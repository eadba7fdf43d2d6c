"""Write a cutter path: ISO/Fanuc G-code, the nominal contour as CSV with normals, or DXF.

Coordinates are the cam frame of the surface export (origin at the cam centre, the cam at
theta = 0 as the DXF export draws it), in mm (G21) or, for a config in inches, in inches
(G20), written to MACHINING_DECIMALS digits (the core rounds the points to that grid and counts
it in the worst deviation). The contour runs clockwise around the cam (an outside contour
with the cutter on the left of its path: climb milling with a spindle turning M3), or
counter-clockwise with --compensation right (G42: the cutter on the right).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from cam_ros.core.geometry.machining import ToolPath

MACHINING_FORMATS = ('gcode', 'csv', 'dxf')
#: Per output unit: factor from m, G-code unit word, decimals written.
UNITS = {'mm': (1000.0, 'G21', 4), 'in': (1.0 / 0.0254, 'G20', 5)}
LAYERS = {False: 'CUTTER_PATH', True: 'CAM_NOMINAL'}


def resolution(unit: str) -> float:
    """Return the length (m) of the last digit written in unit."""
    per_metre, _, decimals = UNITS[unit]
    return 10.0 ** -decimals / per_metre


@dataclass(frozen=True)
class PathFile:
    """What the header of a cutter-path file states (lengths in m)."""

    name: str  # the config file the cam comes from
    unit: str  # 'mm' or 'in'
    cutter_radius: Optional[float]
    nominal: bool  # True: the nominal contour (CSV, or G-code with compensation)
    compensation: Optional[str] = None  # 'left' (G41), 'right' (G42) or None


def _oriented(path: ToolPath, counterclockwise: bool) -> tuple[np.ndarray, np.ndarray]:
    """Return the points and normals running the wanted way round, the first point first."""
    x, y = path.points[:, 0], path.points[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if (area > 0.0) == counterclockwise:
        return path.points, path.normals
    order = np.concatenate(([0], np.arange(len(x) - 1, 0, -1)))
    return path.points[order], path.normals[order]


def _xy(unit: str, point: np.ndarray) -> str:
    per_metre, _, decimals = UNITS[unit]
    x, y = (f'{value * per_metre + 0.0:.{decimals}f}' for value in point)
    return f'X{x} Y{y}'.replace('-0.' + '0' * decimals, '0.' + '0' * decimals)


def _length(unit: str, value: float, up: bool = False) -> str:
    """Return a length in unit with the file's decimals (up: rounded up, two digits more)."""
    per_metre, _, decimals = UNITS[unit]
    if up:
        decimals += 2
        value = math.ceil(value * per_metre * 10.0 ** decimals) / 10.0 ** decimals / per_metre
    return f'{value * per_metre:.{decimals}f} {unit.upper()}'


def gcode_text(path: ToolPath, about: PathFile) -> str:
    """Return the G-code program of one closed contour (see the module doc)."""
    unit = about.unit
    points, normals = _oriented(path, about.compensation == 'right')
    radius = about.cutter_radius or 0.0
    if about.compensation:
        kind = f'NOMINAL CONTOUR, CUTTER COMPENSATION {about.compensation.upper()}'
        tool = f'SET D1 = CUTTER RADIUS {_length(unit, radius)}'
        approach = points[0] + 2.0 * radius * normals[0]
        on, off = f'{"G41" if about.compensation == "left" else "G42"} D1 G1', 'G40 G1'
    else:
        kind = 'CAM SURFACE OFFSET BY THE CUTTER RADIUS, CUTTER CENTRE'
        tool = f'CUTTER RADIUS {_length(unit, radius)}'
        approach = points[0] + radius * normals[0]
        on, off = 'G1', 'G1'
    lines = ['%', f'(CAM_ROS CUTTER PATH OF {about.name.upper()})', f'({kind})', f'({tool})',
             f'(CHORDAL TOLERANCE {_length(unit, path.tolerance)}, WORST DEVIATION '
             f'{_length(unit, path.worst_deviation, up=True)})',
             '(ORIGIN AT THE CAM CENTRE, THE CAM AT THETA = 0 AS IN THE DXF EXPORT)',
             '(2D CONTOUR: SET THE DEPTH AND THE FEED BEFORE IT)',
             f'{UNITS[unit][1]} G17 G90', f'G0 {_xy(unit, approach)}',
             f'{on} {_xy(unit, points[0])}']
    lines += [f'G1 {_xy(unit, point)}' for point in points[1:]]
    lines += [f'G1 {_xy(unit, points[0])}', f'{off} {_xy(unit, approach)}', 'M30', '%']
    return '\n'.join(lines) + '\n'


def write_path(target: Path, file_format: str, path: ToolPath, about: PathFile) -> None:
    """Write the path as gcode, csv (x, y and the unit normal per point) or dxf."""
    from cam_ros.output.drawing import write_dxf

    if file_format == 'gcode':
        target.write_text(gcode_text(path, about), encoding='ascii')
        return
    points, normals = _oriented(path, False)
    scaled = points * UNITS[about.unit][0]
    if file_format == 'csv':
        unit = about.unit
        np.savetxt(target, np.column_stack((scaled, normals)), fmt='%.9f', delimiter=',',
                   header=f'x_{unit},y_{unit},nx,ny', comments='')
    else:
        write_dxf(target, scaled, about.unit, LAYERS[about.nominal])
