"""`cam_ros export --machining`: the cutter path or the nominal contour of a design."""
from __future__ import annotations

from pathlib import Path

from cam_ros.commands.common import load_design, positive_quantity, verdict, writing
from cam_ros.core import CamDesign, InvalidParameter
from cam_ros.core.geometry.arcs import fit_arcs, lines_only
from cam_ros.core.geometry.machining import Contour, cutter_contours, place_points
from cam_ros.core.program_from_config import in_file_units
from cam_ros.output.gcode import MACHINING_FORMATS, PathFile, resolution, UNITS, write_path
from cam_ros.core.rounding import ceil_sig


def _restated(err: InvalidParameter, option: str, text: str,
              design: CamDesign) -> InvalidParameter:
    """Return a core error about a length option, quoted as typed and in the file's units."""
    return InvalidParameter(option, text, in_file_units(err.rule, design.config))


def export_machining(config: str, output: str, cutter_radius: str | None,
                     tolerance: str | None, file_format: str,
                     compensation: str | None, arcs: bool = False,
                     axis: str | None = None) -> int:
    """Write the cutter path (gcode, dxf) or the nominal contour (csv, gcode with G41/G42)."""
    if file_format not in MACHINING_FORMATS:
        raise InvalidParameter('--format', file_format, 'a cutter path takes one of '
                               + ', '.join(MACHINING_FORMATS))
    for option, value in (('--compensation', compensation), ('--arcs', arcs or None)):
        if value is not None and file_format != 'gcode':
            raise InvalidParameter(option, value, 'applies to --format gcode')
    if tolerance is None:
        raise InvalidParameter('--tolerance', None, 'is required with --machining (the chordal '
                                                    'tolerance, in length_unit)')
    if cutter_radius is None and file_format != 'csv':
        raise InvalidParameter('--cutter-radius', None, f'is required with --format '
                                                        f'{file_format}')
    design = load_design(config, axis)
    closure = design.closure
    if design.check.undercut or (closure is not None and any(
            side.undercut for side in closure.sides.values())):
        raise InvalidParameter('--machining', True, 'the cam surface is undercut (see `cam_ros '
                                                    'report`): it has no cutter path')
    unit = 'in' if design.config.length_unit == 'in' else 'mm'
    limit = positive_quantity('--tolerance', tolerance, design)
    radius = (None if cutter_radius is None
              else positive_quantity('--cutter-radius', cutter_radius, design))
    nominal = file_format == 'csv' or compensation is not None
    contours, lead = _contours(design, radius, nominal, cutter_radius or '')
    try:
        placed = {name: place_points(contour, limit, resolution(unit))
                  for name, contour in contours.items()}
    except InvalidParameter as err:
        raise _restated(err, '--tolerance', tolerance, design) from err
    paths = {name: fit_arcs(contours[name], path, resolution(unit)) if arcs
             else lines_only(path) for name, path in placed.items()}
    about = PathFile(Path(config).name, unit, radius, nominal, compensation, lead)
    target = Path(output)
    with writing('export', f'writing {target}', target):
        write_path(target, file_format, paths, about)
    per_metre = UNITS[unit][0]
    what = ('nominal contour' if nominal else 'cutter path') + ('s' if len(paths) > 1 else '')
    count = ' + '.join(str(len(fitted.path.points)) for fitted in paths.values())
    worst = max(fitted.worst_deviation for fitted in paths.values())
    moves = (f', {sum(move.centre is not None for f in paths.values() for move in f.moves)} '
             f'arcs in {sum(len(f.moves) for f in paths.values())} moves' if arcs else '')
    print(f'wrote {target}: {what} of {count} points ({file_format}, {unit}{moves}), worst '
          f'deviation {ceil_sig(worst * per_metre)} {unit} within {ceil_sig(limit * per_metre)} '
          f'{unit}')
    return verdict('export', design)


def _contours(design: CamDesign, radius: float | None, nominal: bool,
              typed: str) -> tuple[dict[str, Contour], float]:
    """Return cutter_contours' contours and lead-in, errors naming --cutter-radius as typed."""
    half = None
    if design.config.follower.closure == 'groove':
        half = (getattr(design.follower, 'roller_radius')
                + 0.5 * design.config.follower.groove_clearance)
    try:
        return cutter_contours(design.contours(), radius, nominal, half, '--cutter-radius')
    except InvalidParameter as err:
        raise _restated(err, '--cutter-radius', typed, design) from err
