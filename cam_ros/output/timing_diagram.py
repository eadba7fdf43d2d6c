"""Draw a machine's timing diagram: every axis over one machine cycle on one angle axis.

Stacked panels over machine angle 0..360 deg: each axis's commanded position in its own file
unit (a rotary axis, length_unit deg, modulo a turn, as the interference checks take it), the
gap of each clearance pair in the machine's length_unit with its limit, and the switch tracks
(switches.*, on the machine angle) as bars. Every pair that collides (check_interference's
verdict) is shaded on its axes' panels: red where it collides (a clearance gap below its
min_clearance, both axes in their zones), orange where the machine angle from one leaving
the zone to the other entering is below min_margin (the min_margin after the one leaving,
with the other's entry inside it); the legend quotes the pair's refined figure (a smallest
gap or margin rounded down). The shading is found on the drawing's grid of DIAGRAM_SAMPLES
angles per cycle.

Uses matplotlib's object API (Figure + Agg canvas), never pyplot, as plot.py does.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from cam_ros.core.cam_angles import TWO_PI
from cam_ros.core.config.parameters import UNITS
from cam_ros.core.ecam.switches import switch_table
from cam_ros.core.machine import Machine, PairCheck
from cam_ros.output.plot import save
from cam_ros.core.rounding import ceil_sig, floor_sig

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Machine angles of the drawn curves over one cycle (plus both sides of every joint).
DIAGRAM_SAMPLES = 3601
PANEL_HEIGHT_IN = 1.9
FIGURE_WIDTH_IN = 13.0
COLLISION = 'tab:red'
NEAR_MISS = 'tab:orange'
SHADE_ALPHA = 0.25
#: Colours of the axes' curves: none red or orange, the colours of conflicts.
CURVES = ('tab:blue', 'tab:green', 'tab:purple', 'tab:brown', 'tab:cyan', 'tab:olive',
          'tab:pink', 'tab:gray')
#: Hatches telling apart the conflicts of different pairs on one panel (by pair index).
HATCHES = ('//', '\\\\', 'xx', '..', '++')


def machine_angles(machine: Machine, samples: int = DIAGRAM_SAMPLES) -> np.ndarray:
    """Return machine angles (rad) over one cycle: an even grid and both sides of every joint.

    The last angle is the left limit at 2 pi, so a jump of any axis is drawn vertical.
    """
    joints = np.concatenate([axis.cam.breaks(0.0, TWO_PI) for axis in machine.axes])
    joints = joints[(joints > 0.0) & (joints < TWO_PI)]
    theta = np.unique(np.concatenate((np.linspace(0.0, TWO_PI, samples), joints,
                                      np.nextafter(joints, 0.0))))
    theta[-1] = np.nextafter(TWO_PI, 0.0)
    return theta


def file_positions(machine: Machine, theta: np.ndarray) -> np.ndarray:
    """Return each axis's commanded position at machine angles in its file unit (mm, deg...).

    Shape theta's + (axes,), as Machine.positions but in each axis's file_position_unit.
    """
    factors = [axis.design.config.file_position_unit[1] for axis in machine.axes]
    return machine.positions(theta) * np.array(factors)


def _rotary(machine: Machine) -> np.ndarray:
    """Return which axes are rotary slaves (length_unit deg): drawn modulo a turn."""
    return np.array([axis.design.config.length_unit == 'deg' for axis in machine.axes])


def checked_positions(machine: Machine, theta: np.ndarray) -> np.ndarray:
    """Return the positions the interference checks take (SI; rotary axes modulo a turn)."""
    positions = machine.positions(theta)
    return np.where(_rotary(machine), np.mod(positions, TWO_PI), positions)


def _runs(mask: np.ndarray, degrees: np.ndarray) -> list[tuple[float, float]]:
    """Return the (start, end) angles of each run of True in mask over degrees."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(float(degrees[a]), float(degrees[b])) for a, b in zip(starts, ends)]


def _cyclic_span(start: float, length: float) -> list[tuple[float, float]]:
    """Return the arc from start (deg) of length (deg) as spans within 0..360."""
    start %= 360.0
    end = start + length
    return [(start, end)] if end <= 360.0 else [(start, 360.0), (0.0, end - 360.0)]


def conflict_spans(machine: Machine, check: PairCheck, theta: np.ndarray
                   ) -> list[tuple[float, float, str]]:
    """Return (start_deg, end_deg, colour) of where a pair collides or its margin is short.

    Clearance: where the gap is below min_clearance. Zones: where both axes are in their zone
    (collision), and the min_margin after one leaves wherever the other enters within it.
    """
    pair, names = check.pair, machine.config.names
    positions = checked_positions(machine, theta)
    y_a, y_b = positions[:, names.index(pair.axis_a)], positions[:, names.index(pair.axis_b)]
    degrees = np.degrees(theta)
    if pair.type == 'clearance':
        gap = pair.offset + pair.gain_a * y_a + pair.gain_b * y_b
        return [(a, b, COLLISION) for a, b in _runs(gap < pair.min_clearance, degrees)]
    inside_a, inside_b = y_a > pair.zone_a, y_b > pair.zone_b
    spans = [(a, b, COLLISION) for a, b in _runs(inside_a & inside_b, degrees)]
    margin = math.degrees(pair.min_margin)
    for leaving, entering in ((inside_a, inside_b), (inside_b, inside_a)):
        left = degrees[np.flatnonzero(~leaving & np.roll(leaving, 1))]
        entered = degrees[np.flatnonzero(entering & ~np.roll(entering, 1))]
        apart = np.mod(entered[np.newaxis, :] - left[:, np.newaxis], 360.0)
        for row in np.flatnonzero((apart < margin).any(axis=1)):
            spans += [(a, b, NEAR_MISS) for a, b in _cyclic_span(left[row], margin)]
    return spans


def verdict_label(machine: Machine, check: PairCheck) -> str:
    """Return a pair's refined figure and verdict, short, for the legend."""
    pair, state = check.pair, 'ok' if check.ok else 'COLLIDES'
    at = f'{math.degrees(check.at) % 360.0:.1f} deg'
    if pair.type == 'clearance':
        unit = machine.config.length_unit
        metre = UNITS[unit]
        return (f'{pair.axis_a}-{pair.axis_b} gap min {floor_sig(check.value / metre)} {unit} at '
                f'{at} (>= {pair.min_clearance / metre:g}): {state}')
    if check.value < 0.0:
        value = ('overlap: one never leaves' if math.isinf(check.value) else
                 f'overlap {ceil_sig(-math.degrees(check.value))} deg from')
    else:
        value = ('margin: one never enters, at' if math.isinf(check.value) else
                 f'margin {floor_sig(math.degrees(check.value))} deg at')
    return (f'{pair.axis_a}-{pair.axis_b} zones {value} {at} '
            f'(margin >= {math.degrees(pair.min_margin):g} deg): {state}')


def _angle_axis(axes: list[Axes]) -> None:
    """Share machine angle 0..360 deg along the column, labelled on the lowest panel."""
    for ax in axes:
        ax.grid(True, linewidth=0.3)
        ax.set_xlim(0.0, 360.0)
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xticks(np.arange(0.0, 361.0, 30.0))
    axes[-1].set_xlabel('machine angle (deg)')


def _draw_axes(machine: Machine, panels: list[Axes], theta: np.ndarray) -> None:
    """Plot each axis's position in its file unit (rotary modulo a turn, its wrap left open)."""
    degrees = np.degrees(theta)
    positions = file_positions(machine, theta)
    for index, (axis, ax) in enumerate(zip(machine.axes, panels)):
        values, x = positions[:, index], degrees
        unit = axis.design.config.file_position_unit[0]
        if _rotary(machine)[index]:
            values = np.mod(values, 360.0)
            wraps = np.flatnonzero(np.abs(np.diff(values)) > 180.0) + 1
            values, x = np.insert(values, wraps, np.nan), np.insert(x, wraps, np.nan)
            unit += ', mod 360'
        ax.plot(x, values, color=CURVES[index % len(CURVES)], linewidth=1.4)
        ax.set_ylabel(f'{axis.name}\n({unit})', fontsize=9)


def _draw_pairs(machine: Machine, checks: tuple[PairCheck, ...], panels: dict[str, Axes],
                gaps: list[Axes], theta: np.ndarray) -> None:
    """Draw each pair: its gap or zone levels, the located figure and any conflict shaded."""
    names, degrees = machine.config.names, np.degrees(theta)
    clearance = iter(gaps)
    unit = machine.config.length_unit
    for index, check in enumerate(checks):
        pair = check.pair
        own = [panels[pair.axis_a], panels[pair.axis_b]]
        if pair.type == 'clearance':
            ax = next(clearance)
            positions = checked_positions(machine, theta)
            gap = (pair.offset + pair.gain_a * positions[:, names.index(pair.axis_a)]
                   + pair.gain_b * positions[:, names.index(pair.axis_b)]) / UNITS[unit]
            ax.plot(degrees, gap, color='0.2', linewidth=1.4)
            ax.axhline(pair.min_clearance / UNITS[unit], color=COLLISION, linewidth=0.9,
                       linestyle='--', label=f'min_clearance {pair.min_clearance / UNITS[unit]:g}'
                                             f' {unit}')
            ax.set_ylabel(f'gap {pair.axis_a}-\n{pair.axis_b} ({unit})', fontsize=9)
            own.append(ax)
        else:
            for side, level in ((pair.axis_a, pair.zone_a), (pair.axis_b, pair.zone_b)):
                axis = machine.axis(side)
                factor = axis.design.config.file_position_unit[1]
                panels[side].axhline(level * factor, color='0.4', linewidth=0.9, linestyle='--',
                                     label=f'zone {pair.axis_a}-{pair.axis_b}: above '
                                           f'{level * factor:g}')
        label = verdict_label(machine, check)
        for number, ax in enumerate(own):
            ax.axvline(math.degrees(check.at) % 360.0, color=COLLISION if not check.ok
                       else '0.5', linewidth=1.0, linestyle=':',
                       label=label if number == 0 or ax in gaps else '_')
        if check.ok:
            continue
        _shade(machine, check, own, theta, HATCHES[index % len(HATCHES)])


def _shade(machine: Machine, check: PairCheck, own: list[Axes], theta: np.ndarray,
           hatch: str) -> None:
    """Shade a colliding pair's conflicts on its panels, each kind once in the legend."""
    from matplotlib.colors import to_rgba

    pair = check.pair
    name = f'{pair.axis_a}-{pair.axis_b}'
    kinds = {COLLISION: f'{name}: gap < min_clearance' if pair.type == 'clearance'
             else f'{name}: both in the zone', NEAR_MISS: f'{name}: enters within min_margin'}
    labelled: set[tuple[int, str]] = set()
    for start, end, colour in conflict_spans(machine, check, theta):
        for number, ax in enumerate(own):
            first = (number, colour) not in labelled
            labelled.add((number, colour))
            ax.axvspan(start, end, facecolor=to_rgba(colour, SHADE_ALPHA),
                       edgecolor=to_rgba(colour, 0.7), hatch=hatch, linewidth=0.0,
                       label=kinds[colour] if first else '_', gid=f'conflict {name}')


def _draw_switches(machine: Machine, ax: Axes) -> None:
    """Draw the switch tracks as bars from on to off (wrapping through 0), one row each."""
    table = switch_table(machine.config.parameters)
    for row, (on, off) in enumerate(zip(np.degrees(table.on), np.degrees(table.off))):
        spans = _cyclic_span(on, (off - on) % 360.0)
        ax.broken_barh([(a, b - a) for a, b in spans], (row - 0.35, 0.7), color='0.45',
                       alpha=0.8)
    ax.set_yticks(range(len(table.names)), table.names, fontsize=8)
    ax.set_ylim(len(table.names) - 0.5, -0.5)
    ax.set_ylabel('switches', fontsize=9)


def timing_figure(machine: Machine, checks: tuple[PairCheck, ...], title: str = '') -> Figure:
    """Return the timing diagram of a machine with its interference checks."""
    from matplotlib.figure import Figure

    gap_count = sum(check.pair.type == 'clearance' for check in checks)
    tracks = len(machine.config.parameters['switches.names'])
    heights = [1.0] * (len(machine.axes) + gap_count) + ([0.3 + 0.2 * tracks] if tracks else [])
    figure = Figure(figsize=(FIGURE_WIDTH_IN, PANEL_HEIGHT_IN * sum(heights) + 1.2),
                    layout='constrained')
    grid = figure.add_gridspec(len(heights), 1, height_ratios=heights)
    first = figure.add_subplot(grid[0])
    axes = [first] + [figure.add_subplot(grid[row], sharex=first)
                      for row in range(1, len(heights))]
    theta = machine_angles(machine)
    _draw_axes(machine, axes, theta)
    panels = dict(zip(machine.config.names, axes))
    gaps = axes[len(machine.axes):len(machine.axes) + gap_count]
    _draw_pairs(machine, checks, panels, gaps, theta)
    if tracks:
        _draw_switches(machine, axes[-1])
    for ax in axes[:len(machine.axes) + gap_count]:
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc='upper left', bbox_to_anchor=(1.005, 1.0), fontsize=7,
                      frameon=False)
    _angle_axis(axes)
    omega = float(machine.config.parameters['cam_speed'])
    figure.suptitle(f'{title + ": " if title else ""}timing diagram at {omega:.4g} rad/s '
                    f'({omega * 30.0 / math.pi:.4g} cycles/min); red: collides, orange: '
                    'margin too small', fontsize=10)
    return figure


def plot_timing(machine: Machine, checks: tuple[PairCheck, ...], path: str | Path,
                title: str = '') -> Path:
    """Save the timing diagram of a machine to a .png or .svg."""
    return save(lambda: timing_figure(machine, checks, title), path)


def timing_csv_text(machine: Machine, points: int) -> str:
    """Return the timing diagram's curves as CSV: points + 1 rows over machine angle 0..360.

    Columns: machine_angle_deg, then each axis's commanded position in its file unit (a rotary
    axis as commanded, not modulo a turn), the unit in each column's name.
    """
    degrees = np.arange(points + 1) * (360.0 / points)
    positions = file_positions(machine, np.radians(degrees))
    header = ['machine_angle_deg'] + [
        f'{axis.name}_position_{axis.design.config.file_position_unit[0]}'
        for axis in machine.axes]
    rows = [','.join(repr(float(value)) for value in row)
            for row in np.column_stack((degrees, positions))]
    return '\n'.join([','.join(header), *rows]) + '\n'
