"""`cam_ros export --cam-table` by axis: each axis's --tolerance by the kind of its unit, and a
machine file's tables, one per axis, into a folder.

`--tolerance` may be given once per kind of unit: a length (`10um`) for the axes in a length
unit, an angle (`0.001deg`) for the rotary ones (deg) and the oscillating arms; a bare number is
in each axis's own unit and then the only one. A machine axis whose kind has no tolerance is
refused before anything is written, saying which to add. A table format that cannot take an
axis (a slave that advances, for lenze, kollmorgen and rockwell) skips it: the others are
written, each skipped axis is said in one line, and the exit code is 1.
"""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

from cam_ros.commands.common import say
from cam_ros.core import CamConfig, InvalidParameter, read_parameters_file
from cam_ros.core.config.quantity import split_quantity, TYPED_ANGLES
from cam_ros.core.machine import parse_machine
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

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


def export_machine_tables(config: str, output: str, points: int | None,
                          tolerances: Sequence[str], table_format: str,
                          interpolation: str | None, end_point: bool | None,
                          derivatives: bool) -> int:
    """Write one cam table per axis of a machine file into the folder output, named by axis.

    Every axis the format can take; 1 when any was skipped (said on stderr) or fails.
    """
    from cam_ros.commands.common import positive_quantity, writing
    from cam_ros.commands.design import export_cam_table
    from cam_ros.core.machine import build_machine
    from cam_ros.output.cam_table_formats import check_target, FORMATS

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
