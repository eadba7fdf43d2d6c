"""`cam_ros export MACHINE --cam-table`: a machine file's tables, one per axis, into a folder.

Each axis takes the --tolerance of its kind of unit (cam_table_export); an axis whose kind has
none is refused before anything is written, saying which to add. A table format that cannot take
an axis (a slave that advances, for lenze, kollmorgen and rockwell) skips it: the others are
written, each skipped axis is said in one line, and the exit code is 1.
"""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

from cam_ros.commands.cam_table_export import (axis_tolerance, check_used, export_cam_table,
                                               tolerance_kinds)
from cam_ros.commands.common import positive_quantity, say, writing
from cam_ros.core import InvalidParameter, read_parameters_file
from cam_ros.core.machine import build_machine, parse_machine
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK
from cam_ros.output.cam_table_formats import check_target, FORMATS


def export_machine_tables(config: str, output: str, points: int | None,
                          tolerances: Sequence[str], table_format: str,
                          interpolation: str | None, end_point: bool | None,
                          derivatives: bool) -> int:
    """Write one cam table per axis of a machine file into the folder output, named by axis.

    Every axis the format can take; 1 when any was skipped (said on stderr) or fails.
    """
    folder = Path(output)
    if folder.exists() and not folder.is_dir():
        raise InvalidParameter('-o', output, 'must be a folder for a machine file\'s tables '
                               '(one per axis)')
    machine_config = parse_machine(read_parameters_file(config))
    kinds = tolerance_kinds(tolerances)
    check_used(kinds, machine_config.axes)
    machine = build_machine(machine_config)
    chosen: dict[str, str | None] = {}
    skipped: list[str] = []
    for axis in machine.axes:  # every axis is checked before any table is written
        try:
            check_target(table_format, axis.design)
        except InvalidParameter as err:
            skipped.append(f'skipped axis {axis.name}: {err}')
            continue
        tolerance = axis_tolerance(kinds, axis.design.config, f'axis {axis.name}')
        try:
            if tolerance is not None:
                positive_quantity('--tolerance', tolerance, axis.design,
                                  angular=axis.design.config.angular)
        except InvalidParameter as err:
            raise InvalidParameter(err.parameter, err.value,
                                   f'{err.rule} for axis {axis.name}') from err
        chosen[axis.name] = tolerance
    if chosen:
        with writing('export', f'making {folder}', folder):
            folder.mkdir(parents=True, exist_ok=True)
    suffix = FORMATS[table_format].suffix
    codes = [export_cam_table(config, str(folder / f'{name}{suffix}'), points,
                              [] if tolerance is None else [tolerance], table_format,
                              interpolation, end_point, derivatives, name)
             for name, tolerance in chosen.items()]
    for line in skipped:
        say('export', line)
    return max([*codes, EXIT_FAILED if skipped else EXIT_OK])
