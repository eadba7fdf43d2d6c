"""What a designer must know about a design, said once in words: each check's failures.

CamDesign.warnings puts these together for its follower, closure and follower train; each
function here says what one check found (nothing when it passed).
"""
from __future__ import annotations

import math
from typing import cast

import numpy as np

from .cam_angles import cam_degrees
from .config.schema import CamConfig
from .dynamics.flanks import SideLoads
from .dynamics.report import DynamicsReport
from .dynamics.vibration import RIGID_RATIO, VibrationReport
from .geometry.check import GeometryCheck
from .geometry.closure import ClosureCheck
from .motion.program import MotionProgram

#: Added to a velocity jump's warning: it fails the verdict unless the config allows it.
_VELOCITY_JUMP_NOTE = ('', ' (an infinite acceleration: set limits.allow_velocity_jumps: true '
                           'to accept it)')


def geometry_warnings(check: GeometryCheck, config: CamConfig) -> list[str]:
    """Say where the pressure angle or the radius of curvature breaks its limit, the undercut."""
    notes = []
    rise, ret = config.pressure_angle_limit, config.pressure_angle_return_limit
    sides = ((('', (check.max_pressure_angle, check.max_pressure_angle_at), rise),)
             if rise == ret else
             (('on the rise ', check.pressure_angle_rise, rise),
              ('on the return ', check.pressure_angle_return, ret)))
    for side, (peak, at), limit in sides:
        if peak > limit:
            notes.append(f'pressure angle {side}reaches {math.degrees(peak):.2f} deg at '
                         f'{math.degrees(at):.1f} deg, over the limit of '
                         f'{math.degrees(limit):.1f} deg')
    if check.radius_ok is False:
        notes.append(f'radius of curvature falls to {check.min_radius:.6g} m at '
                     f'{math.degrees(check.min_radius_at):.1f} deg, under the limit of '
                     f'{config.min_radius_of_curvature:.6g} m')
    if check.undercut:
        where = np.degrees(check.undercut_angles)
        notes.append(f'the cam surface is undercut between {where.min():.1f} and '
                     f'{where.max():.1f} deg')
    return notes


def motion_warnings(program: MotionProgram, config: CamConfig, slave_excess: str) -> list[str]:
    """Say where s or its derivatives jump, where a task overshoots, what exceeds slave.*
    (slave_excess: CamDesign.slave_excess)."""
    unit, notes = config.position_unit, list[str]()
    if slave_excess:
        notes.append(slave_excess)
    for jump in program.continuity_report():
        if jump.order <= 2:
            name = ('s', 'ds/dtheta', 'd2s/dtheta2')[jump.order]
            notes.append(f'{name} jumps by {jump.jump:.6g} {unit}/rad^{jump.order} at '
                         f'{math.degrees(jump.angle):.2f} deg'
                         + _VELOCITY_JUMP_NOTE[jump.order == 1
                                               and not config.allow_velocity_jumps])
    for segment in program.segment_summary():
        if segment.overshoot:
            notes.append(f'segment {segment.index} ({segment.task}, {segment.law}): '
                         f'ds/dtheta overshoots the velocity of its moving end by '
                         f'{segment.overshoot:.6g} {unit}/rad, as its boundary values force')
    return notes


def closure_warnings(closure: ClosureCheck, loads: SideLoads | None) -> list[str]:
    """Say which side of a form-closed cam is undercut, breaks a limit or is overloaded."""
    notes = []
    for name, side in closure.sides.items():
        if side.undercut:
            notes.append(f'the {name} {"flank" if closure.closure == "groove" else "cam"} is '
                         f'undercut (at {cam_degrees(side.at, 1):.1f} deg)')
    second = closure.second
    if second is not None and second.pressure_angle_ok is False:
        notes.append(f'the second cam\'s pressure angle reaches '
                     f'{math.degrees(second.max_pressure_angle):.2f} deg at '
                     f'{cam_degrees(second.max_pressure_angle_at, 1):.1f} deg, over its limit')
    if second is not None and second.radius_ok is False:
        notes.append(f'the second cam\'s radius of curvature falls to '
                     f'{second.min_radius:.6g} m, under the limit')
    limit = None if loads is None else loads.contact_stress_limit
    for name, load in zip(closure.sides, () if loads is None else loads.sides):
        if limit is not None and not load.contact_stress_max <= limit:
            notes.append(f'contact stress on the {name} side reaches '
                         f'{load.contact_stress_max / 1e6:.6g} MPa at '
                         f'{cam_degrees(load.contact_stress_max_at, 1):.1f} deg, over the '
                         f'allowable {limit / 1e6:.6g} MPa')
    return notes


def vibration_warnings(vibration: VibrationReport | None, config: CamConfig) -> list[str]:
    """Say when the rigid model does not hold (VDI 2149), the train resonates, it lifts off."""
    notes: list[str] = []
    if vibration is None:
        return notes
    if not vibration.rigid_ok:
        notes.append(f'the follower train\'s natural frequency '
                     f'{vibration.natural_frequency_hz:.6g} Hz is only '
                     f'{vibration.frequency_ratio:.3g} times the cam frequency: VDI 2149 '
                     f'asks for {RIGID_RATIO:g} or more for a rigid-body analysis (see the '
                     'vibration figures)')
    if vibration.resonance is not None:
        notes.append(vibration.resonance_note())
    elif vibration.leaves_cam:
        notes.append(f'with the elastic train the follower leaves the cam at '
                     f'{cam_degrees(cast(float, vibration.elastic_force_min_at), 1):.1f} deg '
                     f'({config.cam_speed:.6g} rad/s): the force falls to '
                     f'{vibration.elastic_force_min:.6g} '
                     + ('N m' if config.oscillating else 'N'))
    return notes


def dynamics_warnings(dynamics: DynamicsReport | None, config: CamConfig) -> list[str]:
    """Say where the rigid follower leaves the cam and where the contact stress is too high."""
    notes: list[str] = []
    if dynamics is None:
        return notes
    for start, end in dynamics.jump_angles:
        notes.append(f'the follower leaves the cam between {cam_degrees(start, 1):.1f} and '
                     f'{cam_degrees(end, 1, end=True):.1f} deg at {config.cam_speed:.6g} rad/s')
    if dynamics.contact_stress_ok is False:
        at = cam_degrees(dynamics.contact_stress_max_at, 1)
        allowable = cast(float, dynamics.contact_stress_limit) / 1e6
        notes.append(f'contact stress is undefined (undercut) from {at:.1f} deg, so not '
                     f'within the allowable {allowable:.6g} MPa'
                     if math.isnan(dynamics.contact_stress_max) else
                     f'contact stress reaches {dynamics.contact_stress_max / 1e6:.6g} MPa at '
                     f'{at:.1f} deg, over the allowable {allowable:.6g} MPa')
    return notes
