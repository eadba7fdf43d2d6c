"""Write cam tables as the files PLCs and drives import: CSV, SEW, XYVA, ST, Lenze, KAS, L5X.

Columns: master position in degrees (ascending), slave position in the config's length_unit (deg
for an oscillating follower), then, where the format has them, slave velocity and acceleration
per degree and per degree^2 of master (master velocity 1, as cam tables store them; not per
second).  Numbers are positional (no exponent), with '.' as the decimal separator and the
shortest digits that read back as the same double, so a file holds the core's values exactly.
Conventions and their sources: docs/cam-tables.md, "Cam tables for PLCs and drives".
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from cam_ros.core import CamDesign, InvalidParameter
from cam_ros.core.ecam.cam_table import CamTable, INTERPOLATIONS
from cam_ros.output.characteristics_text import characteristic_notes
from cam_ros.core.rounding import ceil_sig
from cam_ros.output.vendor_formats import (KOLLMORGEN_MIN_POINTS, number, real_rounding,
                                           write_kollmorgen, write_lenze, write_rockwell)

DEGREE = math.pi / 180.0
#: Most points a SEW MOVI-C ST_PointsList takes (library parameter gc_uMaxNumberOfInterpPoints).
SEW_MAX_POINTS = 16383
#: Points a SEW MOVI-C point list holds by default (its list size parameter; up to SEW_MAX_POINTS).
SEW_DEFAULT_POINTS = 1024
#: Why a format refuses a rotary slave (one that advances per cycle).
NO_ADVANCE = ('its manual ({}) states no slave advance per cycle: a rotary slave that ends a '
              'cycle above its start is refused')
#: Name of the array in the structured-text file.
ST_NAME = 'CamTable'
ST_INDENT = '    '


@dataclass(frozen=True)
class TableFormat:
    """What a target format carries and how it is written."""

    derivatives: str  # 'never', 'optional' or 'always' (velocity and acceleration columns)
    write: Callable[[Sequence[str], np.ndarray, Sequence[str], str], str]
    max_points: int = 0  # 0: no limit of its own
    default_points: int = 0  # what the target holds unless configured for more (0: no such size)
    #: What the target may do between points; the first is assumed unless told.
    interpolations: tuple[str, ...] = ('linear',)
    min_points: int = 2
    #: Why the format cannot hold a rotary slave's advance per cycle ('' when it can).
    no_advance: str = ''
    #: Interpolations whose deviation the target's manual does not let us state.
    unstated: tuple[str, ...] = ()
    #: Whether the file can carry the notes (a comment syntax its manual shows).
    comments: bool = True
    single_precision: bool = False
    #: Where the point limits come from, for the refusal.
    source: str = ''
    #: File name ending of a table written per axis of a machine (export -o DIR).
    suffix: str = '.txt'
    #: Who interpolates the rows so, where a manual says it (said beside the method).
    interpolated_by: str = ''

    def method(self, interpolation: str) -> str:
        """Say how the rows are interpolated, and by whom where the manual says it."""
        by = f', as {self.interpolated_by}' if self.interpolated_by else ''
        return METHODS[interpolation] + by


def _rows(values: np.ndarray, separator: str) -> list[str]:
    return [separator.join(number(value) for value in row) for row in values.tolist()]


def _write_csv(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
               interpolation: str) -> str:
    header = [f'# {note}' for note in notes] + ['# ' + ','.join(names)]
    return '\n'.join(header + _rows(values, ',')) + '\n'


def _write_sew(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
               interpolation: str) -> str:
    return '\n'.join([str(len(values))] + _rows(values, ';')) + '\n'


def _write_st(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
              interpolation: str) -> str:
    rows, columns = values.shape
    lines = [f'(* {note} *)' for note in notes]
    lines += [f'(* {ST_NAME}[i, {column}]: {name} *)' for column, name in enumerate(names)]
    lines += ['VAR_GLOBAL',
              f'{ST_INDENT}{ST_NAME} : ARRAY[0..{rows - 1}, 0..{columns - 1}] OF LREAL := [']
    body = _rows(values, ', ')
    lines += [f'{ST_INDENT * 2}{row},' for row in body[:-1]] + [f'{ST_INDENT * 2}{body[-1]}];']
    return '\n'.join(lines + ['END_VAR']) + '\n'


FORMATS: dict[str, TableFormat] = {
    'csv': TableFormat('optional', _write_csv, interpolations=INTERPOLATIONS, suffix='.csv'),
    'sew': TableFormat('never', _write_sew, SEW_MAX_POINTS, SEW_DEFAULT_POINTS,
                       comments=False, source='MOVI-C library parameter '
                                              'gc_uMaxNumberOfInterpPoints', suffix='.csv'),
    # CODESYS SoftMotion interpolates an XYVA cam by fifth-degree polynomials through X, Y, V, A.
    'xyva': TableFormat('always', _write_csv, interpolations=('quintic',), suffix='.csv',
                        interpolated_by='CODESYS SoftMotion interpolates XYVA cams'),
    'st': TableFormat('never', _write_st, suffix='.st'),
    'lenze': TableFormat('never', write_lenze, no_advance=NO_ADVANCE.format('Cam Loader'),
                         unstated=('linear',)),
    'kollmorgen': TableFormat('never', write_kollmorgen, min_points=KOLLMORGEN_MIN_POINTS,
                              no_advance=NO_ADVANCE.format('KAS cam CSV import'),
                              unstated=('linear',), comments=False,
                              source='KAS IDE, Import Cam Profile: at least 4 spline segments',
                              suffix='.csv'),
    'rockwell': TableFormat('never', write_rockwell, interpolations=('linear', 'cubic'),
                            no_advance=NO_ADVANCE.format('Logix CAM data type'),
                            unstated=('cubic',), single_precision=True, suffix='.L5X'),
    # Written by motion_function_text; listed here for the option's choices.
    'twincat-functions': TableFormat('always', _write_st, interpolations=('quintic',),
                                     suffix='.st'),
}
#: How the header names each interpolation.
METHODS = {
    'linear': 'linear',
    'cubic': 'cubic Hermite, slopes from the velocity column',
    'quintic': 'quintic Hermite (on each interval the fifth-degree polynomial through the '
               'position, velocity and acceleration at both ends)',
}


def size_note(name: str, rows: int) -> str | None:
    """Return a note when a table of rows points exceeds the target's default list size."""
    default = FORMATS[name].default_points
    if not default or rows <= default:
        return None
    return (f'{rows} points exceed the {name} target\'s default list size of {default}: '
            f'configure the list for {rows} points (at most {FORMATS[name].max_points})')


def check_options(name: str, interpolation: str | None,
                  derivatives: bool) -> tuple[str, bool]:
    """Return the interpolation (None: the target's default) and whether the file gets
    derivative columns; raise for what the format cannot carry."""
    target = FORMATS[name]
    chosen = target.interpolations[0] if interpolation is None else interpolation
    if chosen not in target.interpolations:
        if target.derivatives == 'never':
            needs = 'the slopes' + (' and accelerations' if chosen == 'quintic' else '')
            rule = f'needs {needs}, which --format {name} does not carry: use csv' + (
                ' or xyva' if chosen == 'quintic' else '')
        else:
            rule = (f'--format {name} is interpolated by its target by '
                    f'{target.method(target.interpolations[0])}: give '
                    f'{" or ".join(target.interpolations)} or leave --interpolation out')
        raise InvalidParameter('--interpolation', interpolation, rule)
    if target.derivatives == 'never' and derivatives:
        raise InvalidParameter('--derivatives', True, f'--format {name} carries master and '
                                                      'slave positions only')
    return chosen, target.derivatives == 'always' or derivatives or chosen != 'linear'


def table_columns(table: CamTable, design: CamDesign,
                  derivatives: bool) -> tuple[list[str], np.ndarray]:
    """Return the column names (with units) and values of a table, in the file's units."""
    unit, factor = design.config.file_position_unit
    names = ['master_deg', f'slave_{unit}']
    columns = [table.master_deg, table.position * factor]
    if derivatives:
        names += [f'velocity_{unit}_per_deg', f'acceleration_{unit}_per_deg2']
        columns += [table.slope * (factor * DEGREE), table.curvature * (factor * DEGREE ** 2)]
    return names, np.column_stack(columns)


def periodic_note(design: CamDesign, end_point: bool) -> str:
    """Return how the table closes its cycle: the end point and a rotary slave's advance."""
    unit, factor = design.config.file_position_unit
    advance = design.program.advance * factor
    if advance:  # a rotary slave: each cycle starts where the last ended
        return (f'the slave advancing {advance:.12g} {unit} per cycle: the end point 360 deg '
                f'(the start plus the advance) ' + ('included' if end_point else 'left out'))
    return ('the periodic end point 360 deg included' if end_point else
            'periodic: the end point 360 deg repeats 0 deg and is left out')


def _notes(table: CamTable, design: CamDesign, name: str, source: str, rows: int,
           end_point: bool, derivatives: bool, rounding: float) -> list[str]:
    """Return the header lines: what the table is, what it assumes, how exact it is.

    rounding (file unit) is what single-precision values add to the worst deviation.
    """
    unit, factor = design.config.file_position_unit
    steps = len(table.master_deg) - 1
    spacing = (f'placed for {table.interpolation} interpolation within a tolerance of '
               f'{ceil_sig(table.tolerance * factor)} {unit} (greedy; segment boundaries are '
               f'points)'
               if table.tolerance is not None else f'equidistant, every {360.0 / steps:.12g} deg')
    method = FORMATS[name].method(table.interpolation)
    worst = table.max_error * factor + rounding
    if table.interpolation in FORMATS[name].unstated:
        exactness = (f'interpolation assumed: {method}, but the {name} manual does not define '
                     f'the target\'s interpolation: its deviation is not stated (under the '
                     f'{table.interpolation} interpolation assumed it is {ceil_sig(worst)} '
                     f'{unit})')
    else:
        exactness = (f'interpolation assumed: {method}; worst deviation from the exact law '
                     f'{ceil_sig(worst)} {unit} (dense check of every interval, rounded up)')
    notes = [
        f'cam table of {source} from cam_ros: {rows} points over master 0-360 deg, '
        f'{periodic_note(design, end_point)}',
        f'points: {spacing}',
        exactness,
    ]
    if FORMATS[name].single_precision:
        notes.append(f'Master and Slave are REAL (single precision): their rounding adds at '
                     f'most {ceil_sig(rounding)} {unit} to the linear interpolant (included '
                     'above)')
    if derivatives:
        notes.append('velocity and acceleration are per deg and per deg^2 of master (master '
                     'velocity 1), not per second')
    return notes + characteristic_notes(design)


def check_target(name: str, design: CamDesign) -> None:
    """Raise when the format cannot hold the design: a rotary slave's advance per cycle."""
    rule = FORMATS[name].no_advance
    if rule and design.program.advance:
        unit, factor = design.config.file_position_unit
        raise InvalidParameter('--format', name, f'{rule} (this slave advances '
                                                 f'{design.program.advance * factor:.12g} '
                                                 f'{unit} per cycle)')


def table_rounding(table: CamTable, design: CamDesign, name: str) -> float:
    """Return what single-precision rounding adds to the deviation (file unit; 0 if none)."""
    if not FORMATS[name].single_precision:
        return 0.0
    _, values = table_columns(table, design, False)
    try:
        return real_rounding(values[:, 0], values[:, 1])
    except ValueError as err:
        raise InvalidParameter('--format', name, f'{err}: points closer than single '
                                                 'precision resolves (a larger --tolerance '
                                                 'or fewer --points)') from err


def cam_table_text(table: CamTable, design: CamDesign, name: str, source: str,
                   end_point: bool, derivatives: bool) -> str:
    """Return the file text of a table in format name (derivatives from check_options)."""
    target = FORMATS[name]
    check_target(name, design)
    names, values = table_columns(table, design, derivatives)
    if not end_point:
        values = values[:-1]
    unit, factor = design.config.file_position_unit
    option, value = (('--points', len(values) - end_point) if table.tolerance is None
                     else ('--tolerance', f'{number(table.tolerance * factor)} {unit}'))
    if target.max_points and len(values) > target.max_points:
        raise InvalidParameter(option, value, f'gives {len(values)} points; --format {name} '
                                              f'takes at most {target.max_points} '
                                              f'({target.source})')
    if len(values) < target.min_points:
        raise InvalidParameter(option, value, f'gives {len(values)} points; --format {name} '
                                              f'takes at least {target.min_points} '
                                              f'({target.source})')
    notes = _notes(table, design, name, source, len(values), end_point, derivatives,
                   table_rounding(table, design, name))
    return target.write(notes if target.comments else [], values, names, table.interpolation)
