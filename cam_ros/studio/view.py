"""What the page shows of a design's values: curves, checks and the verdict, from the core.

A single cam is a machine of one axis (the core's machine_from_values, as cam_node serves it),
so one path serves both; memory.py keeps the core's answers about axes and pairs an edit left
alone. Every number comes from the core: the motion and geometry from
CamDesign.evaluate and CamDesign.geometry, the verdict from CamDesign.ok and warnings, a
machine's pairs from check_interference (refined figures, their lines as `cam_ros report`
prints them) and the timing diagram's curves and shaded spans from the CLI's timing-diagram
writer. Here they are only put into units the page draws in (the file's) and into JSON.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from cam_ros.commands.common import plain
from cam_ros.core import CamDesign
from cam_ros.core.cam_angles import TWO_PI
from cam_ros.core.config.parameters import UNITS
from cam_ros.core.machine import is_machine, Machine
from cam_ros.core.machine.served import pair_line, pair_name
from cam_ros.output.timing_diagram import checked_positions, conflict_spans, machine_angles
from cam_ros.studio.memory import machine_and_checks

#: Cam angles of the S-V-A-J, pressure-angle and curvature curves: every 0.5 deg.
CURVE_SAMPLES = 721
#: Points of the cam drawing's closed curves.
DRAWING_SAMPLES = 720
#: Machine angles of the timing diagram (plus both sides of every joint).
TIMING_SAMPLES = 721
#: A radius of curvature beyond this many base radii is drawn as a gap (an inflection's is
#: unbounded), as `cam_ros plot` does.
RADIUS_CAP = 10.0
MM_PER_M = 1000.0


def design_view(values: Mapping[str, Any], axis: str | None = None) -> dict[str, Any]:
    """Return everything the page draws for flat values (raises the core's InvalidParameter).

    axis: the machine axis whose curves to include (default the first); a single cam has one.
    """
    machine, checks = machine_and_checks(values)
    single = not is_machine(values)
    names = machine.config.names
    shown = machine.axes[names.index(axis) if axis in names else 0]
    judged = [(item.design.ok, list(item.design.warnings())) for item in machine.axes]
    view: dict[str, Any] = {
        'machine': not single,
        'axes': list(names),
        'axis': None if single else shown.name,
        'curves': curves(shown.design),
        'drawing': drawing(shown.design),
        'checks': [{'axis': None if single else item.name, 'ok': ok, 'warnings': warnings}
                   for item, (ok, warnings) in zip(machine.axes, judged)],
        'pairs': [pair_view(machine, check) for check in checks],
        'verdict': verdict_line(machine, judged, checks, single),
        'ok': all(ok for ok, _ in judged) and all(c.ok for c in checks),
    }
    if not single:
        view['timing'] = timing(machine, checks)
    return json_ready(view)


def json_ready(value: Any) -> Any:
    """Return value as JSON-ready data: arrays as lists, a non-finite float as None.

    As commands.common.plain, with a float array turned into a list in one pass (the page's
    curves are most of an answer).
    """
    if isinstance(value, np.ndarray) and value.dtype.kind == 'f':
        return [x if math.isfinite(x) else None for x in value.tolist()]
    if isinstance(value, dict):
        return {str(key): json_ready(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(item) for item in value]
    return plain(value)


def verdict_line(machine: Machine, judged: list[tuple[bool, list[str]]], checks: tuple,
                 single: bool) -> str:
    """Return the verdict: it ends in 'meets its limits' or names what fails.

    A single cam's is `cam_ros report`'s verdict line, with its warnings when it fails.
    """
    if single:
        ok, warnings = judged[0]
        return ('Verdict: meets its limits' if ok else
                'Verdict: VIOLATES its limits: ' + '; '.join(warnings))
    failing = [f'axis {item.name} violates its limits'
               for item, (ok, _) in zip(machine.axes, judged) if not ok]
    failing += [f'{pair_name(check)} COLLIDES' for check in checks if not check.ok]
    return ('Verdict: ' + '; '.join(failing) if failing else
            'Verdict: no pair collides, every axis meets its limits')


def curves(design: CamDesign) -> dict[str, Any]:
    """Return S-V-A-J (file unit), pressure angle (deg), radius of curvature (length_unit)."""
    config = design.config
    unit, factor = config.file_position_unit
    state = design.evaluate(np.linspace(0.0, TWO_PI, CURVE_SAMPLES)[:-1])
    degrees = np.linspace(0.0, 360.0, CURVE_SAMPLES)[:-1]
    segments = design.program.segments
    result: dict[str, Any] = {
        'angle_deg': degrees, 'unit': unit, 'cam_speed': config.cam_speed,
        'position': state.position * factor, 'velocity': state.velocity * factor,
        'acceleration': state.acceleration * factor, 'jerk': state.jerk * factor,
        'joints_deg': [math.degrees(segment.start) for segment in segments],
        'laws': [segment.law.name for segment in segments],
        'jumps': [{'deg': math.degrees(jump.angle) % 360.0, 'order': jump.order}
                  for jump in design.program.continuity_report()],
    }
    if design.follower is not None:
        length = config.length_unit
        radius = state.radius_of_curvature / UNITS[length]
        cap = RADIUS_CAP * design.follower.base_radius / UNITS[length]
        result.update({
            'pressure_angle_deg': np.degrees(state.pressure_angle),
            'pressure_limit_deg': math.degrees(config.pressure_angle_limit),
            'pressure_return_limit_deg': math.degrees(config.pressure_angle_return_limit),
            'radius': np.where(np.abs(radius) <= cap, radius, np.nan),
            'radius_unit': length,
            'radius_limit': config.min_radius_of_curvature / UNITS[length],
        })
    return result


def drawing(design: CamDesign) -> dict[str, Any] | None:
    """Return the cam's surface, pitch curve and base circle in mm (cam frame), None: no cam."""
    if design.follower is None:
        return None
    geometry = design.geometry(DRAWING_SAMPLES)
    contours = {name: contour.evaluate(np.linspace(0.0, TWO_PI, DRAWING_SAMPLES,
                                                   endpoint=False))[0] * MM_PER_M
                for name, contour in (design.contours().items() if design.closure else ())}
    return {
        'surface': [geometry.surface_x * MM_PER_M, geometry.surface_y * MM_PER_M],
        'pitch': [geometry.pitch_x * MM_PER_M, geometry.pitch_y * MM_PER_M],
        'others': {name: [points[0], points[1]] for name, points in contours.items()},
        'base_radius_mm': design.follower.base_radius * MM_PER_M,
        'roller_radius_mm': getattr(design.follower, 'roller_radius', 0.0) * MM_PER_M,
        'clockwise': design.clockwise,
    }


def pair_view(machine: Machine, check: Any) -> dict[str, Any]:
    """Return one pair's figures: its report line, its verdict and where it is worst."""
    pair = check.pair
    figure = (check.value / UNITS[machine.config.length_unit] if pair.type == 'clearance'
              else math.degrees(check.value))
    return {'pair': f'{pair.axis_a}-{pair.axis_b}', 'type': pair.type, 'ok': check.ok,
            'line': pair_line(check, machine.config.length_unit), 'value': figure,
            'unit': machine.config.length_unit if pair.type == 'clearance' else 'deg',
            'at_deg': math.degrees(check.at) % 360.0}


def timing(machine: Machine, checks: tuple) -> dict[str, Any]:
    """Return the timing diagram: each axis over the machine cycle and each pair's spans.

    Positions in each axis's file unit, a rotary axis modulo a turn, as the checks take it
    (the CLI's timing diagram); spans where a colliding pair collides or its margin is short.
    """
    theta = machine_angles(machine, TIMING_SAMPLES)
    factors = np.array([axis.design.config.file_position_unit[1] for axis in machine.axes])
    positions = checked_positions(machine, theta) * factors
    return {
        'angle_deg': np.degrees(theta),
        'positions': {axis.name: positions[:, index] for index, axis in enumerate(machine.axes)},
        'units': {axis.name: axis.design.config.file_position_unit[0] for axis in machine.axes},
        'spans': {f'{check.pair.axis_a}-{check.pair.axis_b}':
                  [] if check.ok else [list(s) for s in conflict_spans(machine, check, theta)]
                  for check in checks},  # as the CLI's diagram, only a pair that collides
    }
