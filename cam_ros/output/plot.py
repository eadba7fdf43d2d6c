"""Draw a cam design: diagrams over cam angle and the cam with its follower.

Three columns: S-V-A-J; pressure angle and radius of curvature with their limits (and, for a
design with dynamics, contact force with the spring force and any jump marked, camshaft torque,
contact stress with its allowable); the cam drawing.

Uses matplotlib's object API (Figure + Agg canvas), never pyplot, so no display and no global
state are involved. The cam is drawn in the fixed frame (follower side up, +y) turned to the
chosen cam angle, in mm. Over cam angle in degrees: S-V-A-J in the config's position unit
(length_unit, or deg of arm angle) per s, s^2, s^3, the radius of curvature in length_unit.
Each joint is sampled on both sides, so a jump is drawn as one, and the unbounded derivative a
jump implies is marked.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, TYPE_CHECKING

import numpy as np

from cam_ros.core import (CamDesign, CamState, InvalidParameter, OscillatingFlat,
                          OscillatingRoller, TranslatingRoller, cam_geometry)
from cam_ros.core.config.parameters import LENGTH_UNITS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

PLOT_SAMPLES = 3601  # points of the S-V-A-J curves over 0..360 deg
DRAW_SAMPLES = 1440  # points of the cam curves
FACE_OFFSET_TINY = 1e-12  # m: a contact this close to a flat face's reference point gives no sense
FACE_MARGIN = 0.1  # the face is drawn this fraction of its needed length longer at each end
MM_PER_M = 1000.0
FORMATS = ('.png', '.svg')
DPI = 120
FIGURE_SIZE_IN = (20.0, 9.0)
RADIUS_CAP = 20.0  # radii of curvature beyond this many base radii are left out of the plot


def _rotation(angle: float) -> np.ndarray:
    """Return the 2x2 matrix turning vectors by angle (rad, counter-clockwise positive)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _revolution(design: CamDesign) -> np.ndarray:
    """Return PLOT_SAMPLES cam angles over 0..360 deg plus both sides of every joint and jump.

    The last angle is the left limit at 360 deg, not the wrap to 0; a joint's left limit is
    the float just below it, so a jump there is drawn vertical, not as a slope between samples.
    """
    program = design.program
    joints = np.array([segment.start for segment in program.segments]
                      + [jump.angle for jump in program.continuity_report()]) % (2.0 * math.pi)
    joints = joints[joints > 0.0]
    theta = np.concatenate((np.linspace(0.0, 2.0 * math.pi, PLOT_SAMPLES), joints,
                            np.nextafter(joints, 0.0)))
    theta = np.unique(theta)
    theta[-1] = np.nextafter(2.0 * math.pi, 0.0)
    return theta


def _frame(design: CamDesign, ax: Axes, angle: float, label: str) -> None:
    """Mark segment joints, the drawn cam angle and zero on a diagram over cam angle."""
    for segment in design.program.segments:
        ax.axvline(math.degrees(segment.start) % 360.0, color='0.75', linewidth=0.8,
                   linestyle=':')
    ax.axvline(math.degrees(angle) % 360.0, color='tab:orange', linewidth=1.0)
    ax.axhline(0.0, color='0.5', linewidth=0.6)
    ax.set_ylabel(label, fontsize=9)
    ax.grid(True, linewidth=0.3)
    ax.ticklabel_format(axis='y', style='sci', scilimits=(-3, 4))


def _angle_axis(axes: list[Axes]) -> None:
    """Share cam angle 0..360 deg along a column of diagrams, labelled on the lowest."""
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlim(0.0, 360.0)
    axes[-1].set_xticks(np.arange(0.0, 361.0, 30.0))
    axes[-1].set_xlabel('cam angle (deg)')


def _diagrams(design: CamDesign, axes: list[Axes], state: CamState, angle: float) -> None:
    """Plot position, velocity, acceleration and jerk over one revolution on four axes.

    Law names label the joints; a velocity jump is marked on the acceleration diagram and an
    acceleration jump on the jerk diagram (each is an unbounded value of that derivative).
    """
    unit, factor = design.config.file_position_unit
    rows = ((state.position, f'position ({unit})', 'tab:blue'),
            (state.velocity, f'velocity ({unit}/s)', 'tab:green'),
            (state.acceleration, f'acceleration ({unit}/s²)', 'tab:red'),
            (state.jerk, f'jerk ({unit}/s³)', 'tab:purple'))
    degrees = np.degrees(state.angle)
    for ax, (values, label, colour) in zip(axes, rows):
        ax.plot(degrees, values * factor, color=colour, linewidth=1.2)
        _frame(design, ax, angle, label)
    for segment in design.program.segments:
        axes[0].text(math.degrees(segment.start) % 360.0 + 1.0, 0.97, segment.law.name,
                     transform=axes[0].get_xaxis_transform(), rotation=90, fontsize=7,
                     va='top', color='0.3', bbox={'color': 'white', 'alpha': 0.7, 'pad': 1})
    continuity = design.program.continuity_report()
    for order, name in ((1, 'velocity'), (2, 'acceleration')):
        jumps = [jump.angle for jump in continuity if jump.order == order]
        for number, jump in enumerate(jumps):
            mark = axes[order + 1].axvline(math.degrees(jump) % 360.0, color='k',
                                           linewidth=1.4, linestyle=(0, (1, 1)),
                                           label=f'{name} jump: unbounded' if number == 0 else '_')
            mark.set_gid(f'{name} jump')
        if jumps:
            axes[order + 1].legend(loc='upper right', fontsize=7)
    axes[0].set_title(f'S-V-A-J at {design.config.cam_speed:g} rad/s', fontsize=10)


def _limit(ax: Axes, value: float, label: str) -> None:
    """Draw a limit as a dashed horizontal line."""
    ax.axhline(value, color='tab:red', linewidth=0.9, linestyle='--', label=label)


def _geometry_panels(design: CamDesign, axes: list[Axes], state: CamState,
                     angle: float) -> None:
    """Plot the pressure angle and the surface's radius of curvature with their limits."""
    degrees = np.degrees(state.angle)
    pressure, limit = np.degrees(state.pressure_angle), math.degrees(
        design.config.pressure_angle_limit)
    axes[0].plot(degrees, pressure, color='tab:blue', linewidth=1.2)
    back = math.degrees(design.config.pressure_angle_return_limit)
    _limit(axes[0], limit, f'limit ±{limit:g} deg' if back == limit
           else f'rise limit ±{limit:g} deg')
    _limit(axes[0], -limit, '_')
    if back != limit:  # the return's own limit (|angle| where ds/dtheta <= 0)
        for sign, label in ((1, f'return limit ±{back:g} deg'), (-1, '_')):
            axes[0].axhline(sign * back, color='tab:orange', linewidth=0.9, linestyle=':',
                            label=label)
    _frame(design, axes[0], angle, 'pressure angle (deg)')
    axes[0].legend(loc='upper right', fontsize=7)
    axes[0].set_title('Pressure angle and radius of curvature', fontsize=10)
    unit = design.config.length_unit
    per_metre = 1.0 / LENGTH_UNITS[unit]
    radius = state.radius_of_curvature * per_metre
    cap = RADIUS_CAP * design.follower.base_radius * per_metre  # an inflection's is unbounded
    axes[1].plot(degrees, np.where(np.abs(radius) <= cap, radius, np.nan), color='tab:green',
                 linewidth=1.2)
    _frame(design, axes[1], angle, f'radius of curvature ({unit})')
    if design.config.min_radius_of_curvature > 0.0:
        _limit(axes[1], design.config.min_radius_of_curvature * per_metre, 'smallest allowed')
        axes[1].legend(loc='upper right', fontsize=7)


def _dynamics_panels(design: CamDesign, axes: list[Axes], state: CamState,
                     angle: float) -> None:
    """Plot contact and spring force (jumps marked), camshaft torque and contact stress."""
    forces, config = state.dynamics, design.config.dynamics
    if forces is None or config is None:
        return
    degrees = np.degrees(state.angle)
    force_ax, torque_ax, stress_ax = axes
    force_ax.plot(degrees, forces.contact_force, color='tab:blue', linewidth=1.2,
                  label='contact force')
    if not design.config.oscillating:  # an oscillating arm's spring gives a moment (N m)
        force_ax.plot(degrees, forces.spring_force, color='tab:gray', linewidth=1.0,
                      label='spring force')
    leaves = forces.contact_force < 0.0
    if leaves.any():  # a form-closed cam cannot jump: there its second side takes the load
        force_ax.fill_between(degrees, 0.0, 1.0, where=leaves, color='tab:red', alpha=0.2,
                              transform=force_ax.get_xaxis_transform(),
                              label='follower leaves the cam' if design.closure is None
                              else 'the second side carries the load')
    _frame(design, force_ax, angle, 'force (N)')
    force_ax.legend(loc='best', fontsize=7)
    force_ax.set_title(f'Dynamics at {design.config.cam_speed:g} rad/s', fontsize=10)
    torque_ax.plot(degrees, forces.camshaft_torque, color='tab:purple', linewidth=1.2)
    _frame(design, torque_ax, angle, 'camshaft torque (N m)')
    stress_ax.plot(degrees, forces.contact_stress / 1e6, color='tab:brown', linewidth=1.2)
    if config.contact_stress_limit > 0.0:
        _limit(stress_ax, config.contact_stress_limit / 1e6, 'allowable')
        stress_ax.legend(loc='upper right', fontsize=7)
    _frame(design, stress_ax, angle, 'contact stress (MPa)')


def _face_direction(design: CamDesign, reference: np.ndarray, contact: np.ndarray,
                    offset: float) -> tuple[np.ndarray, bool]:
    """Return the unit vector e along a flat face with contact = reference + offset e (mm).

    The second value is False when only the face's line, not the sense of e, is known.
    """
    sigma = -1.0 if design.clockwise else 1.0
    follower = design.follower
    if not isinstance(follower, OscillatingFlat):
        return np.array([sigma, 0.0]), True
    if abs(offset) > FACE_OFFSET_TINY:
        return (contact - reference) / (offset * MM_PER_M), True
    arm = reference - np.array([0.0, follower.pivot_distance * MM_PER_M])
    return np.array([-arm[1], arm[0]]) / np.hypot(*arm), False


def _follower_lines(design: CamDesign, angle: float, turn: np.ndarray) -> dict:
    """Return the follower's drawing at cam angle (rad) in the fixed frame, in mm."""
    follower = design.follower
    theta = np.array([angle])
    motion = design.surface.evaluate(theta)  # the roller touches the cam: its input y
    shape = cam_geometry(follower, theta, motion.s, motion.ds, motion.d2s,
                         clockwise=design.clockwise)
    reference = turn @ np.array([shape.pitch_x[0], shape.pitch_y[0]]) * MM_PER_M
    contact = turn @ np.array([shape.surface_x[0], shape.surface_y[0]]) * MM_PER_M
    base = follower.base_radius * MM_PER_M
    lines: dict = {'contact': contact, 'reference': reference}
    if isinstance(follower, (TranslatingRoller, OscillatingRoller)):
        lines['roller'] = (reference, follower.roller_radius * MM_PER_M)
    else:
        check = design.check
        low, high = min(0.0, check.face_min or 0.0), max(0.0, check.face_max or 0.0)
        offset = 0.0 if shape.contact_offset is None else float(shape.contact_offset[0])
        direction, sensed = _face_direction(design, reference, contact, offset)
        if not sensed:
            low, high = -max(abs(low), abs(high)), max(abs(low), abs(high))
        margin = FACE_MARGIN * (high - low) + 0.05 * follower.base_radius  # m
        lines['face'] = np.stack((reference + ((low - margin) * MM_PER_M) * direction,
                                  reference + ((high + margin) * MM_PER_M) * direction), axis=1)
    if isinstance(follower, (OscillatingRoller, OscillatingFlat)):
        pivot = np.array([0.0, follower.pivot_distance * MM_PER_M])
        lines['arm'] = np.stack((pivot, reference), axis=1)
        lines['pivot'] = pivot
    else:
        offset_x = follower.offset * MM_PER_M if isinstance(follower, TranslatingRoller) else 0.0
        top = reference[1] + 0.8 * base
        lines['stem'] = np.array([[offset_x, offset_x], [reference[1], top]])
    return lines


def _drawing(design: CamDesign, ax: Axes, angle: float) -> None:
    """Draw the cam turned to angle (rad) with base circle, pitch curve and the follower."""
    sigma = -1.0 if design.clockwise else 1.0
    turn = _rotation(sigma * angle)
    geometry = design.geometry(DRAW_SAMPLES)
    surface = turn @ np.array([geometry.surface_x, geometry.surface_y]) * MM_PER_M
    pitch = turn @ np.array([geometry.pitch_x, geometry.pitch_y]) * MM_PER_M
    base = design.follower.base_radius * MM_PER_M
    circle = np.linspace(0.0, 2.0 * math.pi, 361)
    ax.fill(surface[0], surface[1], color='tab:blue', alpha=0.12, linewidth=0)
    ax.plot(*np.column_stack((surface, surface[:, :1])), color='tab:blue', linewidth=1.6,
            label='cam surface')
    if design.closure is not None:  # a groove's outer flank, a conjugate pair's second cam
        name, contour = list(design.contours().items())[-1]
        other = turn @ contour.evaluate(np.linspace(0.0, 2.0 * math.pi, DRAW_SAMPLES,
                                                    endpoint=False))[0] * MM_PER_M
        ax.plot(*np.column_stack((other, other[:, :1])), color='tab:purple', linewidth=1.6,
                label=f'{name} {"flank" if name == "outer" else "cam"}')
    roller = isinstance(design.follower, (TranslatingRoller, OscillatingRoller))
    ax.plot(*np.column_stack((pitch, pitch[:, :1])), color='tab:orange', linewidth=1.0,
            linestyle='--', label='pitch curve' if roller else 'face reference point path')
    ax.plot(base * np.cos(circle), base * np.sin(circle), color='0.5', linewidth=0.8,
            linestyle=':', label='base circle')
    mark = turn @ np.array([0.0, 0.35 * base])  # where the cam frame's +y axis points now
    ax.plot([0.0, mark[0]], [0.0, mark[1]], color='tab:blue', linewidth=1.0)
    ax.plot([0.0], [0.0], marker='+', color='k', markersize=10)
    lines = _follower_lines(design, angle, turn)
    follower_style: dict[str, Any] = {'color': 'tab:red', 'linewidth': 1.6}
    if 'roller' in lines:
        centre, radius = lines['roller']
        ax.plot(centre[0] + radius * np.cos(circle), centre[1] + radius * np.sin(circle),
                label='follower', **follower_style)
        ax.plot([centre[0]], [centre[1]], marker='.', color='tab:red')
    if 'face' in lines:
        ax.plot(*lines['face'], label='follower', **follower_style)
    for key in ('stem', 'arm'):
        if key in lines:
            ax.plot(*lines[key], color='tab:red', linewidth=1.0)
    if 'pivot' in lines:
        ax.plot(*lines['pivot'], marker='o', color='tab:red', markersize=6)
    ax.plot(*lines['contact'], marker='o', color='k', markersize=3, label='contact')
    ax.set_aspect('equal', adjustable='datalim')
    ax.grid(True, linewidth=0.3)
    ax.set_xlabel('x (mm)')
    ax.set_ylabel('y (mm)')
    sense = 'clockwise' if design.clockwise else 'counter-clockwise'
    kind = design.config.follower.type.replace('_', ' ')
    ax.set_title(f'{kind} follower, {sense} cam at {math.degrees(angle):g} deg', fontsize=10)
    ax.legend(loc='lower left', fontsize=8)


def design_figure(design: CamDesign, angle: float = 0.0, title: str = '') -> Figure:
    """Return the figure of the diagrams and the cam drawing at cam angle (rad)."""
    from matplotlib.figure import Figure

    if not math.isfinite(angle):
        raise InvalidParameter('angle', angle, 'must be a finite cam angle (rad)')
    motion_only = design.follower is None  # no cam: the four diagrams only
    figure = Figure(figsize=(FIGURE_SIZE_IN[0] / 3, FIGURE_SIZE_IN[1]) if motion_only
                    else FIGURE_SIZE_IN, layout='constrained')
    columns = figure.add_gridspec(1, 1) if motion_only else figure.add_gridspec(
        1, 3, width_ratios=(1.0, 1.0, 1.1))
    dynamic = design.dynamics is not None
    state = design.evaluate(_revolution(design))
    for column, count in ((0, 4),) if motion_only else ((0, 4), (1, 5 if dynamic else 2)):
        rows = columns[0, column].subgridspec(count, 1)
        first = figure.add_subplot(rows[0])
        axes = [first] + [figure.add_subplot(rows[row], sharex=first) for row in range(1, count)]
        _angle_axis(axes)
        if column == 0:
            _diagrams(design, axes, state, angle)
        else:
            _geometry_panels(design, axes[:2], state, angle)
            _dynamics_panels(design, axes[2:], state, angle)
    if not motion_only:
        _drawing(design, figure.add_subplot(columns[0, 2]), angle)
    if title:
        figure.suptitle(title)
    return figure


def plot_design(design: CamDesign, path: str | Path, angle: float = 0.0,
                title: str = '') -> Path:
    """Save the diagrams and the cam drawing at cam angle (rad) to a .png or .svg."""
    return save(lambda: design_figure(design, angle, title), path)


def save(figure: Callable[[], Figure], path: str | Path) -> Path:
    """Draw a figure and save it to a .png or .svg (checked before drawing)."""
    target = Path(path)
    if target.suffix.lower() not in FORMATS:
        raise InvalidParameter('path', str(path), 'must end in ' + ', '.join(FORMATS))
    figure().savefig(target, dpi=DPI)
    return target
