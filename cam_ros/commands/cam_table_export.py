"""`cam_ros export --cam-table` of one cam (or one axis): a table for a PLC or drive, or
Beckhoff motion functions; which --tolerance it takes.

`--tolerance` may be given once per kind of unit: a length (`10um`) for the axes in a length
unit, an angle (`0.001deg`) for the rotary ones (deg) and the oscillating arms; a bare number is
in each axis's own unit and then the only one.
"""
from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence

from cam_ros.commands.common import load_design, positive_quantity, verdict, writing
from cam_ros.core import CamConfig, CamDesign, InvalidParameter
from cam_ros.core.config.quantity import split_quantity, TYPED_ANGLES
from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS

#: The table format written as motion functions (points with a function type each).
MOTION_FUNCTIONS = 'twincat-functions'
#: Points of `export --cam-table` without --points or --tolerance: one per degree.
DEFAULT_TABLE_POINTS = 360

#: A tolerance of each kind, as a user would type it.
EXAMPLES = {'length': '10um', 'angle': '0.001deg'}


def tolerance_kinds(tolerances: Sequence[str]) -> dict[str, str]:
    """Return each --tolerance by its kind: 'length', 'angle', or 'bare' (each axis's unit).

    One per kind; a bare number only alone (it would fit every axis).
    """
    kinds: dict[str, str] = {}
    for text in tolerances:
        _, unit = split_quantity('--tolerance', text)
        kind = 'angle' if unit in TYPED_ANGLES else 'length' if unit else 'bare'
        if kind in kinds:
            raise InvalidParameter('--tolerance', text, f'is a second {kind} tolerance (after '
                                   f'{kinds[kind]!r}): give one per kind of unit, a length and '
                                   'an angle')
        kinds[kind] = text
    if 'bare' in kinds and len(kinds) > 1:
        raise InvalidParameter('--tolerance', kinds['bare'], 'needs its unit (e.g. 10um or '
                               '0.001deg) when --tolerance is given more than once')
    return kinds


def kind_of(config: CamConfig) -> str:
    """Return the kind of unit a design's table is in: 'angle' or 'length'."""
    return 'angle' if config.angular else 'length'


def axis_tolerance(kinds: dict[str, str], config: CamConfig, name: str) -> str | None:
    """Return the --tolerance a design (called name in errors) takes; None if none is given.

    Raises naming the kind to add when tolerances are given but none of its kind.
    """
    if not kinds or 'bare' in kinds:
        return kinds.get('bare')
    kind = kind_of(config)
    if kind in kinds:
        return kinds[kind]
    (given,) = kinds.values()
    unit = config.file_position_unit[0]
    raise InvalidParameter('--tolerance', given, f'gives no {kind} tolerance for {name} (in '
                           f'{unit}): add --tolerance {EXAMPLES[kind]} or the like (one per '
                           'kind of unit)')


def check_used(kinds: dict[str, str], configs: Sequence[CamConfig]) -> None:
    """Refuse a --tolerance of a kind none of the designs (a machine's axes, or one cam) takes."""
    used = {kind_of(config) for config in configs}
    for kind, text in kinds.items():
        if kind != 'bare' and kind not in used:
            where = (f'this cam is in {configs[0].file_position_unit[0]}' if len(configs) == 1
                     else f'no axis of this machine is in {"an" if kind == "angle" else "a"} '
                          f'{kind} unit')
            raise InvalidParameter('--tolerance', text, f'is {"an" if kind == "angle" else "a"} '
                                   f'{kind} tolerance, but {where}')


def cam_tolerance(tolerances: Sequence[str], config: CamConfig) -> str | None:
    """Return the --tolerance a single cam takes: the one given, or the one of its kind."""
    if len(tolerances) <= 1:
        return tolerances[0] if tolerances else None  # its unit checked with the design
    kinds = tolerance_kinds(tolerances)
    check_used(kinds, [config])
    return axis_tolerance(kinds, config, 'this cam')


def export_cam_table(config: str, output: str, points: int | None,
                     tolerances: Sequence[str], table_format: str, interpolation: str | None,
                     end_point: bool | None, derivatives: bool, axis: str | None = None) -> int:
    """Write a cam table (master deg -> slave) of a config for a PLC or drive to import.

    tolerances: none, one, or one per kind of unit (the one of the table's unit is taken).
    """
    from cam_ros.output.cam_table_formats import (cam_table_text, check_options, size_note,
                                                  table_rounding)
    from cam_ros.core.rounding import ceil_sig
    from cam_ros.core.config.quantity import split_quantity
    from cam_ros.core.ecam.cam_table import CamTable, equidistant_table, tolerance_table

    target = Path(output)
    interpolation, with_derivatives = check_options(table_format, interpolation, derivatives)
    if table_format == MOTION_FUNCTIONS:
        _motion_function_options(points, end_point)
    for text in tolerances:
        split_quantity('--tolerance', text)  # a typo is refused before the config is read
    design = load_design(config, axis)
    tolerance = cam_tolerance(tolerances, design.config)
    unit, factor = design.config.file_position_unit
    limit = None if tolerance is None else positive_quantity(  # in the table's unit
        '--tolerance', tolerance, design, angular=design.config.angular)
    if table_format == MOTION_FUNCTIONS:
        return _export_motion_function(design, config, target, tolerance, limit)

    def place(allowed: float | None) -> CamTable:
        return (tolerance_table(design.program, allowed, interpolation, unit=(unit, factor))
                if allowed is not None else
                equidistant_table(design.program, DEFAULT_TABLE_POINTS if points is None
                                  else points, interpolation))

    with _option_names(tolerance):
        table = place(limit)
        extra = table_rounding(table, design, table_format) / factor
        if limit is not None and table.max_error + extra > limit:  # leave room for rounding
            table = place(limit - 2.0 * extra)  # the new points round differently
            extra = table_rounding(table, design, table_format) / factor
            if table.max_error + extra > limit:
                raise InvalidParameter('tolerance', limit, 'is too small for REAL (single '
                                                           'precision) Master and Slave')
    text = cam_table_text(table, design, table_format, Path(config).name,
                          True if end_point is None else end_point, with_derivatives)
    with writing('export', f'writing {target}', target):
        target.write_text(text, encoding='utf-8')
    within = '' if limit is None else \
        f' within a tolerance of {ceil_sig(limit * factor)} {unit}'
    worst = f'{ceil_sig((table.max_error + extra) * factor)} {unit}'
    if interpolation in TABLE_FORMATS[table_format].unstated:
        worst = (f'not stated by the {table_format} manual (under the {interpolation} '
                 f'interpolation assumed: {worst})')
    print(f'wrote {target}: cam table of {len(table.master_deg) - (end_point is False)} '
          f'points ({table_format}, {interpolation} interpolation){within}, worst deviation '
          f'{worst}')
    note = size_note(table_format, len(table.master_deg) - (end_point is False))
    if note:
        print(f'note: {note}')
    if not TABLE_FORMATS[table_format].comments:
        print(f'note: the {table_format} file has no comment syntax: its characteristic values '
              f'are those of `cam_ros export --format csv`')
    return verdict('export', design)


@contextmanager
def _option_names(tolerance: str | None) -> Iterator[None]:
    """Re-raise the core's InvalidParameter naming the option and its value as typed."""
    try:
        yield
    except InvalidParameter as err:
        value = tolerance if err.parameter == 'tolerance' else err.value
        raise InvalidParameter(f'--{err.parameter}', value, err.rule) from err


def _motion_function_options(points: int | None, end_point: bool | None) -> None:
    """Refuse the options a motion function cannot take."""
    if points is not None:
        raise InvalidParameter('--points', points, f'--format {MOTION_FUNCTIONS} writes the '
                                                   'segments\' own functions: give --tolerance '
                                                   'for laws it lacks')
    if end_point is False:
        raise InvalidParameter('--end-point', False, f'--format {MOTION_FUNCTIONS} needs its '
                                                     'end point: it ends the last segment')


def _export_motion_function(design: CamDesign, config: str, target: Path,
                            tolerance: str | None, limit: float | None) -> int:
    """Write the design as Tc2_MC2_Camming motion-function points (IEC 61131-3 ST)."""
    from cam_ros.core.ecam.motion_functions import motion_function
    from cam_ros.output.cam_table_formats import check_target, periodic_note
    from cam_ros.output.characteristics_text import characteristic_notes
    from cam_ros.output.motion_function_text import (motion_function_text, segment_notes,
                                                     UNUSED)
    from cam_ros.core.rounding import ceil_sig

    unit, factor = design.config.file_position_unit
    check_target(MOTION_FUNCTIONS, design)
    with _option_names(tolerance):
        function = motion_function(design.program, limit, unit=(unit, factor))
    count = len(function.angle)
    notes = [f'motion function of {Path(config).name} from cam_ros: {count} points over master '
             f'0-360 deg, {periodic_note(design, True)}',
             'Tc2_MC2_Camming MC_MotionFunctionPoint: FunctionType is the function from this '
             'point to the next; POLYNOM1 the line through the two positions, POLYNOM5 the '
             'rest-to-rest quintic, POLYNOM5_MM the quintic through SlavePos, SlaveVelo and '
             'SlaveAcc at both points (Beckhoff states no formula: this reading is the only '
             'polynomial those values determine)',
             'MasterPos in deg, SlavePos in ' + unit + ', SlaveVelo, SlaveAcc, SlaveJerk per '
             'deg, deg^2, deg^3 of master (master velocity 1); RelIndexNextPoint 1 throughout',
             'not used (no formula or parameters in Beckhoff\'s pages): ' + ', '.join(UNUSED),
             *segment_notes(function, design), *characteristic_notes(design)]
    text = motion_function_text(function, design, notes)
    with writing('export', f'writing {target}', target):
        target.write_text(text, encoding='utf-8')
    pieced = f'{len(function.pieced)} of {len(design.program.segments)} segments as quintic ' \
             f'pieces, worst deviation {ceil_sig(function.max_error * factor)} {unit}'
    print(f'wrote {target}: motion function of {count} points ({MOTION_FUNCTIONS}), {pieced}')
    return verdict('export', design)
