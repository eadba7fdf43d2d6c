"""Write a cutter path: ISO/Fanuc G-code, the nominal contour as CSV with normals, or DXF.

Coordinates are the cam frame of the surface export (origin at the cam centre, the cam at
theta = 0 as the DXF export draws it), in mm (G21) or, for a config in inches, in inches
(G20), written to the decimals of UNITS (the core rounds the points to that grid and counts it
in the worst deviation). Each contour is cut with the cutter on the left of its path (climb
milling with a spindle turning M3): an outside contour runs clockwise, one cut from inside (a
groove's outer flank) counter-clockwise; --compensation right (G42) puts the cutter on the
right and reverses both. A groove or a conjugate pair has two contours, one after the other.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from cam_ros.core.geometry.arcs import ArcPath, Move
from cam_ros.core.geometry.machining import ToolPath

MACHINING_FORMATS = ('gcode', 'csv', 'dxf')
#: Per output unit: factor from m, G-code unit word, decimals written.
UNITS = {'mm': (1000.0, 'G21', 4), 'in': (1.0 / 0.0254, 'G20', 5)}
TITLES = {'surface': 'CAM SURFACE', 'inner': 'INNER FLANK', 'outer': 'OUTER FLANK',
          'pitch': 'PITCH CURVE, A CUTTER OF THE GROOVE WIDTH', 'first': 'FIRST CAM',
          'second': 'SECOND CAM'}


def resolution(unit: str) -> float:
    """Return the length (m) of the last digit written in unit."""
    per_metre, _, decimals = UNITS[unit]
    return 10.0 ** -decimals / per_metre


@dataclass(frozen=True)
class PathFile:
    """What a cutter-path file states and how it leads in (lengths in m).

    lead: how far along the first point's normal the cutter starts (clear of the cam, or in
    the middle of a groove).
    """

    name: str  # the config file the cam comes from
    unit: str  # 'mm' or 'in'
    cutter_radius: Optional[float]
    nominal: bool  # True: the nominal contour (CSV, or G-code with compensation)
    compensation: Optional[str] = None  # 'left' (G41), 'right' (G42) or None
    lead: float = 0.0


def _reversed(path: ToolPath, right: bool) -> bool:
    """Return whether the path must run against its point order (see the module doc).

    The normals point to the cutter's side: away from the enclosed area on an outside contour.
    """
    points, normals = path.points, path.normals
    x, y = points[:, 0], points[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    inside = float(np.sum((points - points.mean(axis=0)) * normals)) < 0.0
    return (area > 0.0) != (right != inside)


def _oriented(path: ToolPath, right: bool) -> tuple[np.ndarray, np.ndarray]:
    """Return points and normals in cutting order, the first point first."""
    if not _reversed(path, right):
        return path.points, path.normals
    order = np.concatenate(([0], np.arange(len(path.points) - 1, 0, -1)))
    return path.points[order], path.normals[order]


def _moves(fitted: ArcPath, right: bool) -> tuple[Move, ...]:
    """Return the moves in cutting order, indices into _oriented's points."""
    if not _reversed(fitted.path, right):
        return fitted.moves
    count = len(fitted.path.points)
    return tuple(Move((count - move.end) % count, (count - move.start) % count, move.centre)
                 for move in reversed(fitted.moves))


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


def _move(unit: str, move: Move, points: np.ndarray) -> str:
    """Return the block of one move: G1 to its end, or G2/G3 with the centre as I, J."""
    end = points[move.end]
    if move.centre is None:
        return f'G1 {_xy(unit, end)}'
    start, middle, centre = points[move.start], points[move.start + 1], np.array(move.centre)
    turn = (middle - start)[0] * (end - middle)[1] - (middle - start)[1] * (end - middle)[0]
    per_metre, _, decimals = UNITS[unit]
    i, j = ((centre - start) * per_metre + 0.0).tolist()
    return (f'{"G3" if turn > 0.0 else "G2"} {_xy(unit, end)} I{i:.{decimals}f} '
            f'J{j:.{decimals}f}').replace(f'-0.{"0" * decimals} ', f'0.{"0" * decimals} ')


def gcode_text(paths: dict[str, ArcPath], about: PathFile) -> str:
    """Return the G-code program of the closed contours (see the module doc)."""
    unit, radius = about.unit, about.cutter_radius or 0.0
    first = next(iter(paths.values())).path
    worst = max(fitted.worst_deviation for fitted in paths.values())
    side = about.compensation or ''
    code = {'left': 'G41', 'right': 'G42'}.get(side, '')
    if code:
        kind = f'NOMINAL CONTOUR, CUTTER COMPENSATION {side.upper()}'
        tool = f'SET D1 = CUTTER RADIUS {_length(unit, radius)}'
        on, off = f'{code} D1 G1', 'G40 G1'
    else:
        kind = 'CAM SURFACE OFFSET BY THE CUTTER RADIUS, CUTTER CENTRE'
        tool = f'CUTTER RADIUS {_length(unit, radius)}'
        on, off = 'G1', 'G1'
    lines = ['%', f'(CAM_ROS CUTTER PATH OF {about.name.upper()})', f'({kind})', f'({tool})',
             f'(CHORDAL TOLERANCE {_length(unit, first.tolerance)}, WORST DEVIATION '
             f'{_length(unit, worst, up=True)})',
             '(ORIGIN AT THE CAM CENTRE, THE CAM AT THETA = 0 AS IN THE DXF EXPORT)',
             '(2D CONTOUR: SET THE DEPTH AND THE FEED BEFORE IT)',
             f'{UNITS[unit][1]} G17 G90']
    right = about.compensation == 'right'
    for name, fitted in paths.items():
        points, normals = _oriented(fitted.path, right)
        approach = points[0] + about.lead * normals[0]
        if len(paths) > 1:
            lines.append(f'({TITLES[name]})')
        lines += [f'G0 {_xy(unit, approach)}', f'{on} {_xy(unit, points[0])}']
        lines += [_move(unit, move, points) for move in _moves(fitted, right)]
        lines.append(f'{off} {_xy(unit, approach)}')
    return '\n'.join(lines + ['M30', '%']) + '\n'


def write_path(target: Path, file_format: str, paths: dict[str, ArcPath],
               about: PathFile) -> None:
    """Write the paths as gcode (arcs as G2/G3), csv (x, y and the unit normal per point) or
    dxf (the points).

    Two or more paths: a CSV names each point's curve in a fifth column, a DXF puts each on
    its layer.
    """
    from cam_ros.output.drawing import write_dxf

    if file_format == 'gcode':
        target.write_text(gcode_text(paths, about), encoding='ascii')
        return
    scale, unit = UNITS[about.unit][0], about.unit
    ordered = {name: _oriented(fitted.path, False) for name, fitted in paths.items()}
    if file_format == 'csv':
        header = f'x_{unit},y_{unit},nx,ny' + (',curve' if len(paths) > 1 else '')
        rows = [','.join(f'{value:.9f}' for value in (*point * scale, *normal))
                + (f',{name}' if len(paths) > 1 else '')
                for name, (points, normals) in ordered.items()
                for point, normal in zip(points, normals)]
        target.write_text('\n'.join([header, *rows]) + '\n', encoding='utf-8')
        return
    base = 'CAM_NOMINAL' if about.nominal else 'CUTTER_PATH'
    write_dxf(target, {(base if len(paths) == 1 else f'{base}_{name.upper()}'): points * scale
                       for name, (points, _) in ordered.items()}, unit)
