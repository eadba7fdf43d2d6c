"""The design report as `cam_ros report` prints it: readable text, or one JSON object (SI).

Angles in degrees; lengths in m (rad of arm angle for oscillating followers).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

from cam_ros.commands.closure_text import closure_data, closure_rows, LIMIT_STATES
from cam_ros.commands.common import degrees, format_table, number
from cam_ros.core import CamDesign
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.dynamics.report import DynamicsReport
from cam_ros.core.dynamics.vibration import VibrationReport
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
    }


def dynamics_data(dynamics: DynamicsReport | None, form_closed: bool = False) -> dict[str, Any]:
    """Return the report's dynamics keys (SI, angles deg); only 'dynamics': False without.

    A form-closed cam cannot jump and has no spring: its jump keys are false and null, its
    contact stress is per side (closure_data).
    """
    if dynamics is None:
        return {'dynamics': False}
    d = dynamics
    if form_closed:
        d = dataclasses.replace(d, jump_angles=(), jump_speed=None, spring_preload_needed=0.0,
                                contact_stress_max=math.nan, contact_half_width=math.nan)
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


def vibration_data(vibration: VibrationReport | None) -> dict[str, Any] | None:
    """Return the report's 'vibration' object (SI, angles deg), None for a rigid train.

    JSON has no infinity: an unbounded figure reads null, with resonance_harmonic (the output
    grows without bound) or peak_rigid_acceleration_unbounded_deg (the designed motion's
    velocity jumps there: its acceleration is an impulse) saying why.
    """
    if vibration is None:
        return None
    v = vibration
    return {
        'natural_frequency_hz': v.natural_frequency_hz,
        'damping_ratio': v.damping_ratio,
        'compensated': v.compensated,
        'frequency_ratio': v.frequency_ratio,
        'rigid_ok': v.rigid_ok,
        'resonance_harmonic': v.resonance,
        'segments': [{'index': s.index, 'r': s.r, 'residual_amplitude': s.residual_amplitude,
                      'residual_ratio': s.residual_ratio, 'law_amplitude': s.law_amplitude}
                     for s in v.segments],
        'max_output_deviation': v.max_output_deviation,
        'max_output_deviation_deg': cam_degrees(v.max_output_deviation_at),
        'peak_output_acceleration': v.peak_output_acceleration,
        'peak_output_acceleration_deg': cam_degrees(v.peak_output_acceleration_at),
        'peak_rigid_acceleration': v.peak_rigid_acceleration,
        'peak_rigid_acceleration_unbounded_deg': [cam_degrees(a) for a in v.velocity_jumps],
        'elastic_force_min': v.elastic_force_min,
        'elastic_force_min_deg': None if v.elastic_force_min_at is None
        else cam_degrees(v.elastic_force_min_at),
    }


def _vibration_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the report's Vibration lines (label, text); none for a rigid train."""
    v, design = report.design.vibration_check, report.design
    if v is None:
        return []
    unit = design.config.position_unit
    rows = [('Vibration', f'train {number(v.natural_frequency_hz)} Hz, damping '
                          f'{number(v.damping_ratio)} of critical: {v.frequency_ratio:.3g} x the '
                          'cam frequency ('
                          + ('rigid model holds, VDI 2149: >= 10)' if v.rigid_ok else
                             'UNDER the 10 x VDI 2149 asks for a rigid model)'))]
    if v.compensated:
        rows.append(('', f'cam compensated for the train at {number(design.config.cam_speed)} '
                         'rad/s (polydyne): its output is the designed motion at this speed '
                         'only (at speed w\' it is off by the response to '
                         '2 zeta (w - w\') / wn s\' + (w^2 - w\'^2) / wn^2 s\'\')'))
    for s in v.segments:
        ramp = design.surface.segments[s.index].ramp
        of = (f'of the law\'s amplitude |h - v beta| {_position(design, s.law_amplitude)} (the '
              'stroke less the ramp\'s travel)' if ramp else 'of the stroke')
        rows.append(('', f'after segment {s.index}: residual '
                         f'{_position(design, s.residual_amplitude)} = {s.residual_ratio:.3g} '
                         f'{of} at r = T fn = {s.r:.4g} (undamped)'))
    rigid = (f'rigid {number(v.peak_rigid_acceleration)} {unit}/s^2' if not v.velocity_jumps else
             'rigid: unbounded, the velocity jumps at ' + ', '.join(
                 f'{cam_degrees(a, 1):.1f}' for a in v.velocity_jumps) + ' deg')
    if v.resonance is not None:
        rows.append(('', f'output at speed: NO steady state: harmonic {v.resonance} of the cam '
                         'motion drives the undamped train at fn, its vibration grows without '
                         f'bound (deviation, acceleration unbounded; {rigid})'))
    else:
        rows.append(('', f'output at speed: max |x - s| '
                         f'{_position(design, v.max_output_deviation)} at '
                         f'{cam_degrees(v.max_output_deviation_at, 1):.1f} deg; peak acceleration '
                         f'{number(v.peak_output_acceleration)} {unit}/s^2 at '
                         f'{cam_degrees(v.peak_output_acceleration_at, 1):.1f} deg ({rigid})'))
    if v.elastic_force_min is not None:
        force = 'N m' if design.config.oscillating else 'N'
        rows.append(('', 'least follower force with the output\'s acceleration: unbounded below: '
                         'LEAVES the cam' if v.elastic_force_min_at is None else
                         f'least follower force with the output\'s acceleration '
                         f'{number(v.elastic_force_min)} {force} at '
                         f'{cam_degrees(v.elastic_force_min_at, 1):.1f} deg: '
                         + ('LEAVES the cam' if v.leaves_cam else 'stays on the cam')))
    return rows


def _position(design: CamDesign, value: float) -> str:
    """Return a position or length (m or rad) with its unit, and in the config's unit beside."""
    unit, factor = design.config.file_position_unit
    si = design.config.position_unit
    return f'{number(value)} {si}' + ('' if unit == si else f' ({number(value * factor)} {unit})')


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


def _dynamics_rows(report: DesignReport) -> list[tuple[str, str]]:
    """Return the report's Dynamics lines (label, text); none without dynamics."""
    d, design = report.dynamics, report.design
    if d is None or design.dynamics is None:
        return []
    config, omega = design.dynamics.config, design.config.cam_speed
    oscillating = design.config.oscillating
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
                          f'{cam_degrees(d.contact_force_max_at, 1):.1f} deg'
                          + (' (negative: on the second side, see Closure)'
                             if design.closure is not None else '')),
        *([] if design.closure is not None else [
            ('', stays),
            ('Jump speed', speed),
            ('Spring preload', f'{number(d.spring_preload)} {force}; needed for safety factor '
                               f'{number(config.jump_safety_factor)}: '
                               f'{number(d.spring_preload_needed)} {force}')]),
        ('Camshaft torque', f'max |T| {number(d.camshaft_torque_max)} N m at '
                            f'{cam_degrees(d.camshaft_torque_max_at, 1):.1f} deg, rms '
                            f'{number(d.camshaft_torque_rms)} N m'),
        ('', f'peak power {number(d.power_max)} W; net work per revolution '
             f'{number(d.cycle_work)} J (damping and friction)'),
        *([] if design.closure is not None else [
            ('Contact stress', f'undefined (undercut) from '
                               f'{cam_degrees(d.contact_stress_max_at, 1):.1f} deg; {limit}'
                               if math.isnan(d.contact_stress_max) else
                               f'max {number(d.contact_stress_max / 1e6)} MPa at '
                               f'{cam_degrees(d.contact_stress_max_at, 1):.1f} deg, half-width '
                               f'{number(d.contact_half_width * 1e3)} mm; {limit}')]),
    ]


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


def format_report(report: DesignReport, config: str) -> str:
    """Return the readable report `cam_ros report` prints."""
    rows = _cam_rows(report) if report.design.follower is not None else _motion_only_rows(report)
    width = max(len(label) for label, _ in rows) + 2
    lines = [f'Cam design report: {config}', '']
    lines += [f'{label:<{width}}{text}' for label, text in rows]
    lines += ['', 'Segments (peaks at the cam speed)', _segment_table(report)]
    lines += ['', 'Discontinuities', _continuity_table(report)]
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
    return rows + closure_rows(design) + _dynamics_rows(report) + _vibration_rows(report)
