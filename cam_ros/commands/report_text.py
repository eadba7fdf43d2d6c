"""The design report as `cam_ros report` prints it: readable text, or one JSON object (SI).

Angles in degrees; lengths in m (rad of arm angle for oscillating followers).
"""
from __future__ import annotations

import math
from typing import Any

from cam_ros.commands.closure_text import closure_data, closure_rows, LIMIT_STATES
from cam_ros.commands.common import degrees, format_table, number
from cam_ros.commands.dynamics_text import (dynamics_data, dynamics_rows, vibration_data,
                                            vibration_rows)
from cam_ros.commands.slave_limits_text import slave_limits_data, slave_limits_lines
from cam_ros.core import CamDesign
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.machine.served import SINGLE_AXIS
from cam_ros.core.report import DesignReport

PEAK_KEYS = ('peak_velocity', 'peak_acceleration', 'peak_jerk')
ORDER_NAMES = ('s', 'ds/dtheta', 'd2s/dtheta2', 'd3s/dtheta3')  # derivatives per rad of cam


def report_data(report: DesignReport, config: str) -> dict[str, Any]:
    """Return the report as the JSON object `cam_ros report --json` prints (SI, angles deg)."""
    design = report.design
    cfg = design.config
    unit = design.config.position_unit
    estimate = report.quick_estimate
    omega = cfg.cam_speed
    return {
        'config': str(config),
        'ok': report.ok,
        'warnings': list(report.warnings),
        'follower': {'type': cfg.follower.type,
                     **(vars(design.follower) if design.follower is not None else {})},
        'rotation': 'clockwise' if cfg.clockwise else 'counterclockwise',
        'cam_speed': cfg.cam_speed,
        'position_unit': unit,
        'advance': design.program.advance,
        'limits': {'pressure_angle_deg': degrees(cfg.pressure_angle_limit),
                   'pressure_angle_return_deg': degrees(cfg.pressure_angle_return_limit),
                   'min_radius_of_curvature': cfg.min_radius_of_curvature},
        'pressure_angle_max_deg': degrees(report.pressure_angle_max),
        'pressure_angle_max_at_deg': cam_degrees(report.pressure_angle_max_at),
        'pressure_angle_min_deg': degrees(report.pressure_angle_min),
        'pressure_angle_min_at_deg': cam_degrees(report.pressure_angle_min_at),
        'pressure_angle_rise_max_deg': degrees(report.pressure_angle_rise[0]),
        'pressure_angle_rise_max_at_deg': cam_degrees(report.pressure_angle_rise[1]),
        'pressure_angle_return_max_deg': degrees(report.pressure_angle_return[0]),
        'pressure_angle_return_max_at_deg': cam_degrees(report.pressure_angle_return[1]),
        'pressure_angle_ok': None if design.follower is None else design.check.pressure_angle_ok,
        'radius_of_curvature_min': report.radius_of_curvature_min,
        'radius_of_curvature_min_at_deg': cam_degrees(report.radius_of_curvature_min_at),
        'radius_of_curvature_ok': None if design.follower is None else design.check.radius_ok,
        'undercut': report.undercut,
        'cusp_angles_deg': [cam_degrees(angle) for angle in report.cusp_angles],
        'min_base_radius': report.min_base_radius,
        'min_base_radius_governing': report.min_base_radius_governing,
        'max_base_radius': report.max_base_radius,
        'max_base_radius_governing': report.max_base_radius_governing or None,
        'smallest_cam': None if report.smallest_cam is None else {
            'base_radius': report.smallest_cam.base_radius,
            'offset': report.smallest_cam.offset,
            'prime_radius': report.smallest_cam.prime_radius,
            'governing': report.smallest_cam.governing},
        'max_roller_radius': report.max_roller_radius,
        **closure_data(design),
        'face_width': None if report.face_range is None else list(report.face_range),
        'segments': [{
            'index': s.index, 'law': s.law, 'start_deg': degrees(s.start),
            'end_deg': degrees(s.end), 'start_position': s.s_start,
            'end_position': s.s_end, 'task': s.task, 'inflection': s.inflection,
            'cv': s.cv, 'ca': s.ca, 'cj': s.cj,
            **dict(zip(PEAK_KEYS, s.peaks_at_speed(omega))),
            'velocity_overshoot': s.overshoot * omega} for s in report.segments],
        'continuity': [{
            'angle_deg': cam_degrees(jump.angle), 'order': jump.order,
            'derivative': ORDER_NAMES[jump.order], 'jump': jump.jump, 'left': jump.left,
            'right': jump.right, 'unit': f'{unit}/rad^{jump.order}' if jump.order else unit,
            'segment': jump.segment} for jump in report.continuity],
        'quick_estimate': None if estimate is None else {
            'segment': estimate.segment, 'mean_radius': estimate.estimate.mean_radius,
            'prime_radius': estimate.estimate.prime_radius, 'base_radius': estimate.base_radius,
            'size_index': estimate.estimate.size_index, 'big_cam': estimate.estimate.big_cam},
        **dynamics_data(report.dynamics, form_closed=design.closure is not None),
        'vibration': vibration_data(report.design.vibration_check),
        'slave_limits': slave_limits_data(report.slave_limits, unit),
    }


def _limit_state(ok: bool | None) -> str:
    return LIMIT_STATES[ok]


def _follower_line(design: CamDesign) -> str:
    """Describe the follower and its lengths in one line."""
    fields = ', '.join(f'{name.replace("_", " ")} ' + (
        ('yes' if value else 'no') if isinstance(value, bool) else f'{number(value)} m')
        for name, value in vars(design.follower).items())
    return f'{design.config.follower.type.replace("_", " ")}: {fields}'


def _segment_table(report: DesignReport) -> str:
    unit, omega = report.design.config.position_unit, report.design.config.cam_speed
    headers = ('#', 'law', 'task', 'start deg', 'end deg', f'from {unit}', f'to {unit}', 'Cv',
               'Ca', 'Cj', f'peak v {unit}/s', f'peak a {unit}/s^2', f'peak j {unit}/s^3')
    rows = [(str(s.index), s.law + ('' if s.inflection == 0.5 else f' ({s.inflection:g})'),
             s.task, f'{math.degrees(s.start):.2f}', f'{math.degrees(s.end):.2f}',
             number(s.s_start), number(s.s_end), number(s.cv, 5), number(s.ca, 5),
             number(s.cj, 5), *(number(peak, 5) for peak in s.peaks_at_speed(omega)))
            for s in report.segments]
    return format_table(headers, rows)


def _continuity_table(report: DesignReport) -> str:
    unit = report.design.config.position_unit
    if not report.continuity:
        return '  none: s and its first three derivatives are continuous'
    rows = [(f'{cam_degrees(j.angle, 2):.2f}', ORDER_NAMES[j.order], number(j.left),
             number(j.right), f'{j.jump:+.6g}', f'{unit}/rad^{j.order}' if j.order else unit)
            for j in report.continuity]
    table = format_table(('at deg', 'of', 'left', 'right', 'jump', 'unit'), rows)
    return '\n'.join('  ' + line for line in table.splitlines())


def _pressure_limit_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the pressure-angle limit line(s): one limit, or the rise's and the return's."""
    cfg, check = report.design.config, report.design.check
    if cfg.pressure_angle_limit == cfg.pressure_angle_return_limit:
        return [('', f'limit |pressure angle| <= {math.degrees(cfg.pressure_angle_limit):g} deg: '
                     f'{_limit_state(check.pressure_angle_ok)}')]
    return [('', f'{side}: max |pressure angle| {math.degrees(peak):.2f} deg at '
                 f'{cam_degrees(at, 1):.1f} deg, limit {math.degrees(limit):g} deg: '
                 f'{_limit_state(peak <= limit)}')
            for side, (peak, at), limit in (
                ('rise', report.pressure_angle_rise, cfg.pressure_angle_limit),
                ('return', report.pressure_angle_return, cfg.pressure_angle_return_limit))]


def _sizing_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the jointly sized cam and the largest roller (rollers only)."""
    rows = []
    cam = report.smallest_cam
    if cam is not None:
        base = 'none needed' if cam.base_radius is None else f'{number(cam.base_radius)} m'
        rows.append(('Smallest cam', f'base radius {base} with offset {number(cam.offset)} m '
                                     f'(prime radius {number(cam.prime_radius)} m, set by '
                                     f'{cam.governing.replace("_", " ")})'))
    if report.max_roller_radius is not None:
        rows.append(('Largest roller', f'{number(report.max_roller_radius)} m on this pitch '
                                       'curve (its smallest convex radius: undercut beyond)'))
    return rows


def format_report(report: DesignReport, config: str, axis: str | None = SINGLE_AXIS) -> str:
    """Return the readable report `cam_ros report` prints.

    axis names the design in its Slave limits line; None leaves the section out (a machine's
    report puts every axis's line in one section).
    """
    rows = _cam_rows(report) if report.design.follower is not None else _motion_only_rows(report)
    width = max(len(label) for label, _ in rows) + 2
    lines = [f'Cam design report: {config}', '']
    lines += [f'{label:<{width}}{text}' for label, text in rows]
    lines += ['', 'Segments (peaks at the cam speed)', _segment_table(report)]
    lines += ['', 'Discontinuities', _continuity_table(report)]
    if axis is not None:
        lines += slave_limits_lines([(axis, report.design.config.position_unit,
                                      report.slave_limits)])
    if report.warnings:
        lines += ['', 'Warnings'] + [f'  - {warning}' for warning in report.warnings]
    lines += ['', 'Verdict: ' + ('meets its limits' if report.ok else 'VIOLATES its limits')]
    return '\n'.join(lines)


def _motion_only_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the lines of a motion-only design (follower.type none): the master and advance."""
    cfg, program = report.design.config, report.design.program
    unit, factor = cfg.file_position_unit
    return [('Motion only', 'follower.type none: no cam, so no geometry, sizing or forces'),
            ('Master', f'{number(cfg.cam_speed)} rad/s of cam angle '
                       f'({number(cfg.cam_speed * 30.0 / math.pi)} rpm); positions in SI '
                       f'({cfg.position_unit}; config: {cfg.length_unit})'),
            ('Advance', f'{number(program.advance)} {cfg.position_unit} '
                        f'({number(program.advance * factor)} {unit}) per cycle'
                        if program.advance else 'none: the motion returns to its start')]


def _cam_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the lines on the cam: follower, pressure angle, curvature, sizing, forces."""
    design = report.design
    cfg = design.config
    check = design.check
    sense = 'clockwise' if cfg.clockwise else 'counter-clockwise'
    rows = [
        ('Follower', _follower_line(design)),
        ('Cam', f'{sense} at {number(cfg.cam_speed)} rad/s '
                f'({number(cfg.cam_speed * 30.0 / math.pi)} rpm); lengths in SI (config: '
                f'{cfg.length_unit})'),
        ('Pressure angle', f'max {math.degrees(report.pressure_angle_max):.2f} deg at '
                           f'{cam_degrees(report.pressure_angle_max_at, 1):.1f} deg, min '
                           f'{math.degrees(report.pressure_angle_min):.2f} deg at '
                           f'{cam_degrees(report.pressure_angle_min_at, 1):.1f} deg'),
        *_pressure_limit_rows(report),
        ('Radius of curvature', f'min {number(report.radius_of_curvature_min)} m '
                                f'at {cam_degrees(report.radius_of_curvature_min_at, 1):.1f} deg'),
        ('', f'limit >= {number(cfg.min_radius_of_curvature)} m: '
             f'{_limit_state(check.radius_ok)}'),
        ('Undercut', 'YES, cusps at ' + ', '.join(
            f'{cam_degrees(a, 1):.1f}' for a in report.cusp_angles) + ' deg'
            if report.undercut else 'none'),
        ('Base radius', f'{number(design.follower.base_radius)} m; smallest meeting the limits: '
                        + (f'{number(report.min_base_radius)} m (set by '
                           f'{report.min_base_radius_governing.replace("_", " ")})'
                           if report.min_base_radius is not None else 'none found')),
    ]
    rows += _sizing_rows(report)
    if report.max_base_radius is not None:
        rows.append(('', f'largest meeting the limits: {number(report.max_base_radius)} m (set by '
                         f'{report.max_base_radius_governing.replace("_", " ")})'))
    if report.face_range is not None:
        low, high = report.face_range
        rows.append(('Face width', f'contact from {number(low)} to {number(high)} m along the '
                                   f'face: at least {number(high - low)} m long'))
    estimate = report.quick_estimate
    if estimate is not None:
        rows.append(('Quick estimate', f'from the steepest rise (segment {estimate.segment}) at '
                                       'the pressure-angle limit, without offset:'))
        if estimate.base_radius is None:
            rows.append(('', 'does not apply: this limit needs no base radius at mid-rise (the '
                             'smallest base radius above is exact)'))
        else:
            rows.append(('', f'base radius {number(estimate.base_radius)} m (roller centre '
                             f'{number(estimate.estimate.mean_radius)} m from the cam centre at '
                             f'mid-rise, {estimate.estimate.size_index:.3g} times the rise'
                             + (': a large cam)' if estimate.estimate.big_cam else ')')))
    return rows + closure_rows(design) + dynamics_rows(report) + vibration_rows(report)
