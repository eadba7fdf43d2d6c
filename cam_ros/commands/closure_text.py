"""The report's lines and JSON keys on a form-closed cam: a groove's flanks, a conjugate pair.

Lengths in m, forces in N, stresses in Pa (MPa in text), angles in degrees.
"""
from __future__ import annotations

import math
from typing import Any

from cam_ros.commands.common import degrees, number
from cam_ros.core import CamDesign
from cam_ros.core.cam_angles import cam_degrees

#: How a limit check reads: met, broken, or no limit given.
LIMIT_STATES = {True: 'ok', False: 'VIOLATED', None: 'no limit'}


def closure_data(design: CamDesign) -> dict[str, Any]:
    """Return the report's closure keys: 'closure', and a form-closed cam's two sides (SI)."""
    closure = design.closure
    data: dict[str, Any] = {'closure': design.config.follower.closure}
    if closure is None:
        return data
    loads = design.side_loads
    sides = {}
    for index, (name, side) in enumerate(closure.sides.items()):
        entry: dict[str, Any] = {
            'radius_of_curvature_min': side.radius_of_curvature_min,
            'radius_of_curvature_min_at_deg': cam_degrees(side.at) if math.isfinite(
                side.radius_of_curvature_min) else None, 'undercut': side.undercut}
        if loads is not None:
            load = loads.sides[index]
            entry.update({
                'carries_load_deg': [[cam_degrees(a), cam_degrees(b, end=True)]
                                     for a, b in load.spans],
                'contact_force_max': load.contact_force_max,
                'contact_force_max_deg': cam_degrees(load.contact_force_max_at),
                'contact_stress_max': load.contact_stress_max,
                'contact_stress_max_deg': cam_degrees(load.contact_stress_max_at)})
        sides[name] = entry
    data['flanks' if closure.closure == 'groove' else 'cams'] = sides
    if loads is not None:
        data['crossovers_deg'] = [cam_degrees(angle) for angle in loads.crossovers]
    second = closure.second
    if second is not None:
        sides['second'].update({
            'pressure_angle_max_deg': degrees(second.max_pressure_angle),
            'pressure_angle_max_at_deg': cam_degrees(second.max_pressure_angle_at),
            'pressure_angle_ok': second.pressure_angle_ok})
    if closure.breadth is not None:
        data['constant_breadth'] = {'holds': closure.breadth.holds,
                                    'spread': closure.breadth.spread}
    return data


def closure_rows(design: CamDesign) -> list[tuple[str, str]]:
    """Return the report's lines on a form-closed cam's two sides; none for force closure."""
    closure, loads = design.closure, design.side_loads
    if closure is None:
        return []
    kind = 'flank' if closure.closure == 'groove' else 'cam'
    rows = [('Closure', f'{closure.closure}: no spring, no jump; the '
                        + ' and '.join(f'{name} {kind}' for name in closure.sides)
                        + ' guide the roller' + ('' if closure.second is None else 's'))]
    for index, (name, side) in enumerate(closure.sides.items()):
        text = (f'{name} {kind}: smallest convex radius {number(side.radius_of_curvature_min)} m'
                f' at {cam_degrees(side.at, 1):.1f} deg' if math.isfinite(
                    side.radius_of_curvature_min) else f'{name} {kind}: no convex part')
        text += ', UNDERCUT' if side.undercut else ''
        if loads is not None:
            load = loads.sides[index]
            spans = ', '.join(f'{cam_degrees(a, 1):.1f}-{cam_degrees(b, 1, end=True):.1f}'
                              for a, b in load.spans) or 'never'
            text += (f'; carries the load {spans} deg, max {number(load.contact_force_max)} N, '
                     f'{number(load.contact_stress_max / 1e6)} MPa')
        rows.append(('', text))
    if closure.second is not None:
        rows.append(('', f'second cam: max |pressure angle| '
                         f'{math.degrees(closure.second.max_pressure_angle):.2f} deg at '
                         f'{cam_degrees(closure.second.max_pressure_angle_at, 1):.1f} deg: '
                         f'{LIMIT_STATES[closure.second.pressure_angle_ok]}'))
    if loads is not None:
        rows.append(('', 'load crosses over at ' + (', '.join(
            f'{cam_degrees(a, 1):.1f}' for a in loads.crossovers) or 'no angle') + ' deg'))
    if closure.breadth is not None:
        rows.append(('', 'constant breadth: ' + (
            'yes, one cam with opposed rollers would do' if closure.breadth.holds else
            f'no, s(theta) + s(theta + 180 deg) spreads by {number(closure.breadth.spread)} m')))
    return rows
