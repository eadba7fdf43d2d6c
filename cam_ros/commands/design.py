"""Design commands on a config file: report, sample, plot, export (no ROS needed)."""
from __future__ import annotations

import csv
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from cam_ros.commands.common import (degrees, dump_json, DYNAMICS_FIELDS, end_progress,
                                     format_table, load_design, number, output_path, progress,
                                     verdict, writing)
from cam_ros.core import CamDesign, InvalidParameter
from cam_ros.core.design import cam_degrees
from cam_ros.core.dynamics.report import DynamicsReport
from cam_ros.core.report import (DesignReport, design_report, file_position_unit,
                                 position_unit)
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

#: Points of `export --cam-table` without --points or --tolerance: one per degree.
DEFAULT_TABLE_POINTS = 360
PEAK_KEYS = ('peak_velocity', 'peak_acceleration', 'peak_jerk')
ORDER_NAMES = ('s', 'ds/dtheta', 'd2s/dtheta2', 'd3s/dtheta3')  # derivatives per rad of cam
#: The arrays of `cam_ros sample`, in output order: (name, CamState field, unit; {p} = m or rad).
SAMPLE_FIELDS = (
    ('angle', 'angle', 'rad'),
    ('position', 'position', '{p}'),
    ('velocity', 'velocity', '{p}/s'),
    ('acceleration', 'acceleration', '{p}/s^2'),
    ('jerk', 'jerk', '{p}/s^3'),
    ('dposition_dangle', 'ds', '{p}/rad'),
    ('d2position_dangle2', 'd2s', '{p}/rad^2'),
    ('d3position_dangle3', 'd3s', '{p}/rad^3'),
    ('pressure_angle', 'pressure_angle', 'rad'),
    ('radius_of_curvature', 'radius_of_curvature', 'm'),
)


# ------------------------------------------------------------------------------------ report

def report_data(report: DesignReport, config: str) -> dict[str, Any]:
    """Return the report as the JSON object `cam_ros report --json` prints (SI, angles deg)."""
    design = report.design
    cfg = design.config
    unit = position_unit(design)
    estimate = report.quick_estimate
    omega = cfg.cam_speed
    return {
        'config': str(config),
        'ok': report.ok,
        'warnings': list(report.warnings),
        'follower': {'type': cfg.follower.type, **vars(design.follower)},
        'rotation': 'clockwise' if cfg.clockwise else 'counterclockwise',
        'cam_speed': cfg.cam_speed,
        'position_unit': unit,
        'limits': {'pressure_angle_deg': degrees(cfg.pressure_angle_limit),
                   'min_radius_of_curvature': cfg.min_radius_of_curvature},
        'pressure_angle_max_deg': degrees(report.pressure_angle_max),
        'pressure_angle_max_at_deg': cam_degrees(report.pressure_angle_max_at),
        'pressure_angle_min_deg': degrees(report.pressure_angle_min),
        'pressure_angle_min_at_deg': cam_degrees(report.pressure_angle_min_at),
        'pressure_angle_ok': design.check.pressure_angle_ok,
        'radius_of_curvature_min': report.radius_of_curvature_min,
        'radius_of_curvature_min_at_deg': cam_degrees(report.radius_of_curvature_min_at),
        'radius_of_curvature_ok': design.check.radius_ok,
        'undercut': report.undercut,
        'cusp_angles_deg': [cam_degrees(angle) for angle in report.cusp_angles],
        'min_base_radius': report.min_base_radius,
        'min_base_radius_governing': report.min_base_radius_governing,
        'max_base_radius': report.max_base_radius,
        'max_base_radius_governing': report.max_base_radius_governing or None,
        'face_width': None if report.face_range is None else list(report.face_range),
        'segments': [{
            'index': s.index, 'law': s.law, 'start_deg': degrees(s.start),
            'end_deg': degrees(s.end), 'start_position': s.s_start,
            'end_position': s.s_end, 'cv': s.cv, 'ca': s.ca, 'cj': s.cj,
            **dict(zip(PEAK_KEYS, s.peaks_at_speed(omega)))} for s in report.segments],
        'continuity': [{
            'angle_deg': cam_degrees(jump.angle), 'order': jump.order,
            'derivative': ORDER_NAMES[jump.order], 'jump': jump.jump, 'left': jump.left,
            'right': jump.right, 'unit': f'{unit}/rad^{jump.order}' if jump.order else unit,
            'segment': jump.segment} for jump in report.continuity],
        'quick_estimate': None if estimate is None else {
            'segment': estimate.segment, 'mean_radius': estimate.estimate.mean_radius,
            'prime_radius': estimate.estimate.prime_radius, 'base_radius': estimate.base_radius,
            'size_index': estimate.estimate.size_index, 'big_cam': estimate.estimate.big_cam},
        **dynamics_data(report.dynamics),
    }


def dynamics_data(dynamics: DynamicsReport | None) -> dict[str, Any]:
    """Return the report's dynamics keys (SI, angles deg); only 'dynamics': False without."""
    if dynamics is None:
        return {'dynamics': False}
    d = dynamics
    return {
        'dynamics': True,
        'contact_force_min': d.contact_force_min,
        'contact_force_min_deg': cam_degrees(d.contact_force_min_at),
        'contact_force_max': d.contact_force_max,
        'contact_force_max_deg': cam_degrees(d.contact_force_max_at),
        'jump': d.jump,
        'jump_angles_deg': [[cam_degrees(start), cam_degrees(end, end=True)]
                            for start, end in d.jump_angles],
        'jump_speed': d.jump_speed,
        'spring_preload': d.spring_preload,
        'spring_preload_needed': d.spring_preload_needed,
        'camshaft_torque_max': d.camshaft_torque_max,
        'camshaft_torque_max_deg': cam_degrees(d.camshaft_torque_max_at),
        'camshaft_torque_rms': d.camshaft_torque_rms,
        'power_max': d.power_max,
        'cycle_work': d.cycle_work,
        'contact_stress_max': d.contact_stress_max,
        'contact_stress_max_deg': cam_degrees(d.contact_stress_max_at),
        'contact_half_width': d.contact_half_width,
        'contact_stress_limit': d.contact_stress_limit,
        'contact_stress_ok': d.contact_stress_ok,
    }


def _limit_state(ok: bool | None) -> str:
    return {True: 'ok', False: 'VIOLATED', None: 'no limit'}[ok]


def _follower_line(design: CamDesign) -> str:
    """Describe the follower and its lengths in one line."""
    fields = ', '.join(f'{name.replace("_", " ")} ' + (
        ('yes' if value else 'no') if isinstance(value, bool) else f'{number(value)} m')
        for name, value in vars(design.follower).items())
    return f'{design.config.follower.type.replace("_", " ")}: {fields}'


def _segment_table(report: DesignReport) -> str:
    unit, omega = position_unit(report.design), report.design.config.cam_speed
    headers = ('#', 'law', 'start deg', 'end deg', f'from {unit}', f'to {unit}', 'Cv', 'Ca',
               'Cj', f'peak v {unit}/s', f'peak a {unit}/s^2', f'peak j {unit}/s^3')
    rows = [(str(s.index), s.law, f'{math.degrees(s.start):.2f}', f'{math.degrees(s.end):.2f}',
             number(s.s_start), number(s.s_end), number(s.cv, 5), number(s.ca, 5),
             number(s.cj, 5), *(number(peak, 5) for peak in s.peaks_at_speed(omega)))
            for s in report.segments]
    return format_table(headers, rows)


def _continuity_table(report: DesignReport) -> str:
    unit = position_unit(report.design)
    if not report.continuity:
        return '  none: s and its first three derivatives are continuous'
    rows = [(f'{cam_degrees(j.angle, 2):.2f}', ORDER_NAMES[j.order], number(j.left),
             number(j.right), f'{j.jump:+.6g}', f'{unit}/rad^{j.order}' if j.order else unit)
            for j in report.continuity]
    table = format_table(('at deg', 'of', 'left', 'right', 'jump', 'unit'), rows)
    return '\n'.join('  ' + line for line in table.splitlines())


def _dynamics_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the report's Dynamics lines (label, text); none without dynamics."""
    d, design = report.dynamics, report.design
    if d is None or design.dynamics is None:
        return []
    config, omega = design.dynamics.config, design.config.cam_speed
    oscillating = position_unit(design) == 'rad'
    force, rate, inertia = ('N m', 'N m/rad', 'kg m^2') if oscillating else ('N', 'N/m', 'kg')
    stays = ('LEAVES the cam at ' + ', '.join(
        f'{cam_degrees(a, 1):.1f}-{cam_degrees(b, 1, end=True):.1f}'
        for a, b in d.jump_angles) + ' deg') if d.jump else 'the follower stays on the cam'
    speed = 'never' if d.jump_speed is None else (
        f'{number(d.jump_speed, 5)} rad/s ({number(d.jump_speed * 30.0 / math.pi, 5)} rpm), '
        f'{d.jump_speed / omega:.3g} x the cam speed')
    limit = 'no limit' if d.contact_stress_limit is None else (
        f'limit {number(d.contact_stress_limit / 1e6)} MPa: {_limit_state(d.contact_stress_ok)}')
    return [
        ('Dynamics', f'{"arm inertia" if oscillating else "mass"} {number(config.inertia)} '
                     f'{inertia}, spring {number(config.spring_rate)} {rate}, damping '
                     f'{number(config.damping_ratio)} of critical, external load '
                     f'{number(config.external_force)} {force}'),
        ('Contact force', f'min {number(d.contact_force_min)} N at '
                          f'{cam_degrees(d.contact_force_min_at, 1):.1f} deg, max '
                          f'{number(d.contact_force_max)} N at '
                          f'{cam_degrees(d.contact_force_max_at, 1):.1f} deg'),
        ('', stays),
        ('Jump speed', speed),
        ('Spring preload', f'{number(d.spring_preload)} {force}; needed for safety factor '
                           f'{number(config.jump_safety_factor)}: '
                           f'{number(d.spring_preload_needed)} {force}'),
        ('Camshaft torque', f'max |T| {number(d.camshaft_torque_max)} N m at '
                            f'{cam_degrees(d.camshaft_torque_max_at, 1):.1f} deg, rms '
                            f'{number(d.camshaft_torque_rms)} N m'),
        ('', f'peak power {number(d.power_max)} W; net work per revolution '
             f'{number(d.cycle_work)} J (damping and friction)'),
        ('Contact stress', f'undefined (undercut) from '
                           f'{cam_degrees(d.contact_stress_max_at, 1):.1f} deg; {limit}'
                           if math.isnan(d.contact_stress_max) else
                           f'max {number(d.contact_stress_max / 1e6)} MPa at '
                           f'{cam_degrees(d.contact_stress_max_at, 1):.1f} deg, half-width '
                           f'{number(d.contact_half_width * 1e3)} mm; {limit}'),
    ]


def format_report(report: DesignReport, config: str) -> str:
    """Return the readable report `cam_ros report` prints."""
    design = report.design
    cfg = design.config
    check = design.check
    limit = math.degrees(cfg.pressure_angle_limit)
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
        ('', f'limit |pressure angle| <= {limit:g} deg: {_limit_state(check.pressure_angle_ok)}'),
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
    rows += _dynamics_rows(report)
    width = max(len(label) for label, _ in rows) + 2
    lines = [f'Cam design report: {config}', '']
    lines += [f'{label:<{width}}{text}' for label, text in rows]
    lines += ['', 'Segments (peaks at the cam speed)', _segment_table(report)]
    lines += ['', 'Discontinuities', _continuity_table(report)]
    if report.warnings:
        lines += ['', 'Warnings'] + [f'  - {warning}' for warning in report.warnings]
    lines += ['', 'Verdict: ' + ('meets its limits' if report.ok else 'VIOLATES its limits')]
    return '\n'.join(lines)


def report(config: str, json_output: bool = False) -> int:
    """Print the design report of a config; 1 if the design violates a limit."""
    design = load_design(config)
    progress('report', 'sizing the base radius')
    result = design_report(design)
    end_progress()
    print(dump_json(report_data(result, config)) if json_output else format_report(result, config))
    return EXIT_OK if result.ok else EXIT_FAILED


# ------------------------------------------------------------------------------------ sample

def sample_angles(step_deg: float) -> np.ndarray:
    """Return cam angles (rad) from 0 in steps of step_deg degrees, below 360 deg."""
    if not (math.isfinite(step_deg) and 0.0 < step_deg <= 360.0):
        raise InvalidParameter('--step-deg', step_deg, 'must be in (0, 360] deg')
    return np.radians(np.arange(0.0, 360.0 - 1e-9 * step_deg, step_deg))


def sample_units(design: CamDesign) -> dict[str, str]:
    """Return the unit of each sampled array for this design's follower (and dynamics)."""
    unit = position_unit(design)
    fields = SAMPLE_FIELDS + (DYNAMICS_FIELDS if design.dynamics else ())
    return {name: template.format(p=unit) for name, _, template in fields}


def sample(config: str, step_deg: float = 1.0, json_output: bool = False,
           csv_output: bool = False) -> int:
    """Print the design sampled every step_deg degrees (table, JSON or CSV)."""
    design = load_design(config)
    state = design.evaluate(sample_angles(step_deg))
    units = sample_units(design)
    columns = {name: getattr(state, field) for name, field, _ in SAMPLE_FIELDS}
    if state.dynamics is not None:
        columns.update((name, getattr(state.dynamics, field))
                       for name, field, _ in DYNAMICS_FIELDS)
    if json_output:
        print(dump_json({'config': str(config), 'units': units, **columns}))
    elif csv_output:
        writer = csv.writer(sys.stdout, lineterminator='\n')
        writer.writerow(f'{name}_{unit}'.replace('/', '_per_').replace('^', '')
                        for name, unit in units.items())
        writer.writerows(np.column_stack(list(columns.values())).tolist())
    else:
        headers = [f'{name} ({units[name]})' for name in columns]
        rows = [[number(value) for value in row]
                for row in np.column_stack(list(columns.values())).tolist()]
        print(format_table(headers, rows))
    return verdict('sample', design)


# ------------------------------------------------------------------------------------ plot/export

def plot(config: str, output: str, angle_deg: float = 0.0) -> int:
    """Draw S-V-A-J diagrams and the cam at angle_deg into a .png or .svg file."""
    from cam_ros.output.plot import FORMATS, plot_design

    target = output_path('-o', output, FORMATS)
    if not math.isfinite(angle_deg):
        raise InvalidParameter('--angle-deg', angle_deg, 'must be a finite angle (deg)')
    design = load_design(config)
    with writing('plot', f'drawing {target}', target):
        plot_design(design, target, math.radians(angle_deg), title=Path(config).name)
    print(f'wrote {target}')
    return verdict('plot', design)


def export(config: str, output: str, samples: int | None = None, cam_table: bool = False,
           points: int | None = None, tolerance: float | None = None,
           table_format: str | None = None, interpolation: str | None = None,
           end_point: bool | None = None, derivatives: bool = False) -> int:
    """Write the cam surface (mm) for manufacturing, or with cam_table a cam table for a PLC."""
    from cam_ros.output.drawing import EXPORT_SAMPLES, WRITERS, export_surface

    if cam_table:
        if samples is not None:
            raise InvalidParameter('--samples', samples, 'counts surface points; a cam table '
                                                         'takes --points or --tolerance')
        return export_cam_table(config, output, points, tolerance, table_format or 'csv',
                                interpolation or 'linear', end_point, derivatives)
    table_options = {'--points': points, '--tolerance': tolerance, '--format': table_format,
                     '--interpolation': interpolation, '--end-point': end_point,
                     '--derivatives': derivatives or None}
    for option, value in table_options.items():
        if value is not None:
            raise InvalidParameter(option, value, 'applies to cam tables only: add --cam-table')
    target = output_path('-o', output, tuple(WRITERS))
    design = load_design(config)
    with writing('export', f'writing {target}', target):
        count = export_surface(design, target, EXPORT_SAMPLES if samples is None else samples)
    print(f'wrote {target}: closed cam surface of {count} points (mm)')
    return verdict('export', design)


def export_cam_table(config: str, output: str, points: int | None, tolerance: str | None,
                     table_format: str, interpolation: str, end_point: bool | None,
                     derivatives: bool) -> int:
    """Write a cam table (master deg -> slave) of a config for a PLC or drive to import."""
    from cam_ros.output.cam_table_formats import cam_table_text, check_options, size_note
    from cam_ros.core.config.quantity import split_quantity
    from cam_ros.core.ecam.cam_table import equidistant_table, tolerance_table

    target = Path(output)
    with_derivatives = check_options(table_format, interpolation, derivatives)
    if tolerance is not None:
        split_quantity('--tolerance', tolerance)  # a typo is refused before the config is read
    design = load_design(config)
    unit, factor = file_position_unit(design)
    limit = None if tolerance is None else _table_tolerance(tolerance, design)
    try:
        table = (tolerance_table(design.program, limit, interpolation, unit=(unit, factor))
                 if limit is not None else
                 equidistant_table(design.program, DEFAULT_TABLE_POINTS if points is None
                                   else points, interpolation))
    except InvalidParameter as err:  # name the option and its value as typed
        value = tolerance if err.parameter == 'tolerance' else err.value
        raise InvalidParameter(f'--{err.parameter}', value, err.rule) from err
    text = cam_table_text(table, design, table_format, Path(config).name,
                          True if end_point is None else end_point, with_derivatives)
    with writing('export', f'writing {target}', target):
        target.write_text(text, encoding='utf-8')
    within = '' if table.tolerance is None else \
        f' within a tolerance of {number(table.tolerance * factor)} {unit}'
    print(f'wrote {target}: cam table of {len(table.master_deg) - (end_point is False)} '
          f'points ({table_format}, {interpolation} interpolation){within}, worst deviation '
          f'{number(table.max_error * factor)} {unit}')
    note = size_note(table_format, len(table.master_deg) - (end_point is False))
    if note:
        print(f'note: {note}')
    return verdict('export', design)


def _table_tolerance(text: str, design: CamDesign) -> float:
    """Return --tolerance in SI: a bare number is in the table's unit (see file_position_unit)."""
    from cam_ros.core.config.quantity import typed_quantity

    value = typed_quantity('--tolerance', text, design.config.length_unit,
                           angular=design.config.follower.type.startswith('oscillating'))
    if value <= 0.0:
        raise InvalidParameter('--tolerance', text, 'must be > 0')
    return value
