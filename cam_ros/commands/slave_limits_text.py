"""The report's Slave limits: one line per limited axis, as text, and its JSON object (SI).

Peaks are printed rounded up and the largest master acceleration rounded down (core.rounding):
a figure never reads on the lenient side of its limit.
"""
from __future__ import annotations

import math
from typing import Any, Optional, Sequence

from cam_ros.commands.common import format_table, number
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.ecam.axis_limits import AxisLimits, SpeedPeaks
from cam_ros.core.ecam.slave_limits import SlaveLimits
from cam_ros.core.rounding import ceil_sig, floor_sig

DIRECTION_NAMES = {0: 'any', 1: 'positive', -1: 'negative'}
STATES = {True: 'ok', False: 'EXCEEDS'}
HEADERS = ('axis', 'unit', 'master rad/s', 'velocity /s', 'limit', 'acceleration /s^2', 'limit',
           'master accel allowed rad/s^2', 'direction')


def master_acceleration_note(check: AxisLimits) -> Optional[str]:
    """Say why the largest master acceleration is no figure (None when it is one)."""
    alpha = check.master_acceleration
    if alpha is None:
        return 'no slave.max_acceleration'
    if alpha == -math.inf:
        return 'none: the cam alone EXCEEDS slave.max_acceleration at cam_speed'
    if alpha == math.inf:
        return 'any: the axis never moves'
    return None


def _peaks_data(peaks: Optional[SpeedPeaks], limits: SlaveLimits) -> Optional[dict[str, Any]]:
    if peaks is None:
        return None
    return {'master_speed': peaks.master_speed, 'peak_velocity': peaks.velocity,
            'velocity_ok': peaks.velocity_ok(limits), 'peak_acceleration': peaks.acceleration,
            'acceleration_ok': peaks.acceleration_ok(limits)}


def slave_limits_data(check: Optional[AxisLimits], unit: str) -> Optional[dict[str, Any]]:
    """Return the report's 'slave_limits' object (SI, unit m or rad), None when not limited."""
    if check is None:
        return None
    limits = check.limits
    note = master_acceleration_note(check)
    return {
        'unit': unit,
        'max_velocity': limits.max_velocity or None,
        'max_acceleration': limits.max_acceleration or None,
        'direction': DIRECTION_NAMES[limits.direction],
        'at_cam_speed': _peaks_data(check.cam_speed, limits),
        'at_max_speed': _peaks_data(check.max_speed, limits),
        'max_master_acceleration': None if note else check.master_acceleration,
        'max_master_acceleration_at_deg': None if note else cam_degrees(
            check.master_acceleration_at),
        'max_master_acceleration_note': note,
        'backward_velocity': check.backward,
        'direction_ok': check.direction_ok,
        'ok': check.ok,
    }


def _figure(value: float, state: Optional[bool]) -> str:
    """Return a peak rounded up with its state ('' when there is no limit)."""
    return ceil_sig(value) + ('' if state is None else f' {STATES[state]}')


def _row(name: str, unit: str, check: AxisLimits) -> list[str]:
    """Return one axis's cells: at cam_speed, and below it at master.max_speed when given."""
    limits, speeds = check.limits, [check.cam_speed]
    if check.max_speed is not None:
        speeds.append(check.max_speed)
    note = master_acceleration_note(check)
    alpha = note or (f'{floor_sig(check.master_acceleration or 0.0)} at '
                     f'{cam_degrees(check.master_acceleration_at, 1):.1f} deg')
    way = DIRECTION_NAMES[limits.direction]
    if check.direction_ok is not None:
        way += ': ' + (STATES[True] if check.direction_ok else
                       f'EXCEEDS (back at {ceil_sig(check.backward)} {unit}/s)')
    return [name, unit,
            ' / '.join(number(peaks.master_speed) for peaks in speeds),
            ' / '.join(_figure(peaks.velocity, peaks.velocity_ok(limits)) for peaks in speeds),
            number(limits.max_velocity) if limits.max_velocity else '-',
            ' / '.join(_figure(peaks.acceleration, peaks.acceleration_ok(limits))
                       for peaks in speeds),
            number(limits.max_acceleration) if limits.max_acceleration else '-',
            alpha, way]


def slave_limits_lines(axes: Sequence[tuple[str, str, Optional[AxisLimits]]]) -> list[str]:
    """Return the Slave limits section for (axis name, unit, check) of every axis; [] when no
    axis is limited."""
    rows = [_row(name, unit, check) for name, unit, check in axes if check is not None]
    if not rows:
        return []
    table = format_table(HEADERS, rows)
    return ['', 'Slave limits (at cam_speed / at master.max_speed, constant master speed; peaks '
                'refined and rounded up, the master acceleration of either sign rounded down)',
            *('  ' + line for line in table.splitlines())]
