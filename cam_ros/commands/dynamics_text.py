"""The report's follower-train figures: dynamics and vibration, as text and as JSON (SI).

Angles in degrees; forces in N (N m for an oscillating arm), stresses in Pa (MPa in the text).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

from cam_ros.commands.closure_text import LIMIT_STATES
from cam_ros.commands.common import number
from cam_ros.core import CamDesign
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.dynamics.report import DynamicsReport
from cam_ros.core.dynamics.vibration import VibrationReport
from cam_ros.core.report import DesignReport


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


def vibration_rows(report: DesignReport) -> list[tuple[str, str]]:
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
        amplitude = position_text(design, s.law_amplitude)
        of = (f'of the law\'s amplitude |h - v beta| {amplitude} (the stroke less the ramp\'s '
              'travel)' if ramp else 'of the stroke')
        rows.append(('', f'after segment {s.index}: residual '
                         f'{position_text(design, s.residual_amplitude)} = {s.residual_ratio:.3g} '
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
                         f'{position_text(design, v.max_output_deviation)} at '
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


def position_text(design: CamDesign, value: float) -> str:
    """Return a position or length (m or rad) with its unit, and in the config's unit beside."""
    unit, factor = design.config.file_position_unit
    si = design.config.position_unit
    return f'{number(value)} {si}' + ('' if unit == si else f' ({number(value * factor)} {unit})')


def dynamics_rows(report: DesignReport) -> list[tuple[str, str]]:
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
        f'limit {number(d.contact_stress_limit / 1e6)} MPa: {LIMIT_STATES[d.contact_stress_ok]}')
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
