"""Design commands on a config file: report, sample, plot, export (no ROS needed)."""
from __future__ import annotations

import csv
import math
import sys
from pathlib import Path
from typing import Sequence

import numpy as np

from cam_ros.commands.common import (csv_column, dump_json, DYNAMICS_FIELDS, end_progress,
                                     format_table, load_design, number, output_path,
                                     progress, verdict, writing)
from cam_ros.commands.report_text import format_report, report_data
from cam_ros.core import CamDesign, InvalidParameter, read_parameters_file
from cam_ros.core.machine import is_machine
from cam_ros.core.report import design_report
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK
from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS

#: The arrays of `cam_ros sample`, in output order: (name, CamState field, unit; {p} = m or rad).
SAMPLE_FIELDS = (
    ('angle', 'angle', 'rad'),
    ('position', 'position', '{p}'),
    ('velocity', 'velocity', '{p}/s'),
    ('acceleration', 'acceleration', '{p}/s^2'),
    ('jerk', 'jerk', '{p}/s^3'),
    ('dposition_dangle', 'ds', '{p}/rad'),
    ('d2position_dangle2', 'd2s', '{p}/rad^2'),
    ('d3position_dangle3', 'd3s', '{p}/rad^3'),
    ('pressure_angle', 'pressure_angle', 'rad'),
    ('radius_of_curvature', 'radius_of_curvature', 'm'),
)


# ------------------------------------------------------------------------------------ report

def report(config: str, json_output: bool = False, axis: str | None = None) -> int:
    """Print the design report of a config (or of a machine); 1 if it violates a limit."""
    from cam_ros.commands import machine

    if axis is None and machine.is_machine_file(config):
        return machine.report(config, json_output)
    design = load_design(config, axis)
    progress('report', 'sizing the base radius')
    text, ok = report_output(design, config, json_output, axis)
    end_progress()
    print(text)
    return EXIT_OK if ok else EXIT_FAILED


def report_output(design: CamDesign, config: str, json_output: bool = False,
                  axis: str | None = None) -> tuple[str, bool]:
    """Return what `cam_ros report` prints for a design (of config, or its axis), and its ok."""
    result = design_report(design)
    label = config if axis is None else f'{config}, axis {axis}'
    return (dump_json({**({} if axis is None else {'name': axis}), **report_data(result, config)})
            if json_output else format_report(result, label)), result.ok


# ------------------------------------------------------------------------------------ sample

def sample_angles(step_deg: float) -> np.ndarray:
    """Return cam angles (rad) from 0 in steps of step_deg degrees, below 360 deg."""
    if not (math.isfinite(step_deg) and 0.0 < step_deg <= 360.0):
        raise InvalidParameter('--step-deg', step_deg, 'must be in (0, 360] deg')
    return np.radians(np.arange(0.0, 360.0 - 1e-9 * step_deg, step_deg))


def sample_units(design: CamDesign) -> dict[str, str]:
    """Return the unit of each sampled array for this design's follower (and dynamics)."""
    unit = design.config.position_unit
    fields = SAMPLE_FIELDS + (DYNAMICS_FIELDS if design.dynamics else ())
    return {name: template.format(p=unit) for name, _, template in fields}


def sample(config: str, step_deg: float = 1.0, json_output: bool = False,
           csv_output: bool = False, axis: str | None = None) -> int:
    """Print the design (or a machine's axes) sampled every step_deg degrees."""
    from cam_ros.commands import machine

    if axis is None and machine.is_machine_file(config):
        return machine.sample(config, sample_angles(step_deg), json_output, csv_output)
    design = load_design(config, axis)
    state = design.evaluate(sample_angles(step_deg))
    units = sample_units(design)
    columns = {name: getattr(state, field) for name, field, _ in SAMPLE_FIELDS}
    if state.dynamics is not None:
        columns.update((name, getattr(state.dynamics, field))
                       for name, field, _ in DYNAMICS_FIELDS)
    if json_output:
        print(dump_json({'config': str(config), 'units': units, **columns}))
    elif csv_output:
        writer = csv.writer(sys.stdout, lineterminator='\n')
        writer.writerow(csv_column(name, unit) for name, unit in units.items())
        writer.writerows(np.column_stack(list(columns.values())).tolist())
    else:
        headers = [f'{name} ({units[name]})' for name in columns]
        rows = [[number(value) for value in row]
                for row in np.column_stack(list(columns.values())).tolist()]
        print(format_table(headers, rows))
    return verdict('sample', design)


# ------------------------------------------------------------------------------------ plot/export

def plot(config: str, output: str, angle_deg: float = 0.0, vibration: bool = False,
         axis: str | None = None, timing_diagram: bool = False) -> int:
    """Draw S-V-A-J diagrams and the cam at angle_deg (or the vibration figures) to a file.

    With timing_diagram: every axis of a machine file over one machine cycle.
    """
    from cam_ros.output.plot import FORMATS, plot_design
    from cam_ros.output.vibration_plot import plot_vibration

    if timing_diagram:
        from cam_ros.commands.machine import plot_timing_diagram, refuse_options

        refuse_options('--timing-diagram', {'--axis': axis, '--vibration': vibration or None,
                                            '--angle-deg': angle_deg or None})
        return plot_timing_diagram(config, output)
    target = output_path('-o', output, FORMATS)
    if not math.isfinite(angle_deg):
        raise InvalidParameter('--angle-deg', angle_deg, 'must be a finite angle (deg)')
    design = load_design(config, axis)
    title = Path(config).name + ('' if axis is None else f', axis {axis}')
    with writing('plot', f'drawing {target}', target):
        if vibration:
            plot_vibration(design, target, title=title)
        else:
            plot_design(design, target, math.radians(angle_deg), title=title)
    print(f'wrote {target}')
    return verdict('plot', design)


def export(config: str, output: str, samples: int | None = None, cam_table: bool = False,
           points: int | None = None, tolerance: str | Sequence[str] | None = None,
           file_format: str | None = None, interpolation: str | None = None,
           end_point: bool | None = None, derivatives: bool = False, machining: bool = False,
           cutter_radius: str | None = None, compensation: str | None = None,
           arcs: bool = False, switches: bool = False, axis: str | None = None,
           timing_diagram: bool = False) -> int:
    """Write the cam surface (mm), a cutter path, a cam table or the cam switch tracks.

    Or a machine's timing diagram (timing_diagram); axis takes one axis of a machine file.
    tolerance: one, or one per kind of unit (a length, an angle) for a cam table.
    """
    from cam_ros.output.drawing import EXPORT_SAMPLES, WRITERS, export_surface

    tolerances = [tolerance] if isinstance(tolerance, str) else list(tolerance or ())
    tolerance = ' '.join(tolerances) or None  # as refusals quote it

    if timing_diagram:
        from cam_ros.commands.machine import export_timing_diagram, refuse_options

        refuse_options('--timing-diagram', {
            '--axis': axis, '--switches': switches or None, '--cam-table': cam_table or None,
            '--machining': machining or None, '--samples': samples, '--tolerance': tolerance,
            '--interpolation': interpolation, '--end-point': end_point,
            '--derivatives': derivatives or None, '--cutter-radius': cutter_radius,
            '--compensation': compensation, '--arcs': arcs or None})
        return export_timing_diagram(config, output, file_format or 'csv', points)
    if switches:
        others = {'--cam-table': cam_table or None, '--machining': machining or None,
                  '--samples': samples, '--tolerance': tolerance, '--points': points,
                  '--interpolation': interpolation, '--end-point': end_point,
                  '--derivatives': derivatives or None, '--cutter-radius': cutter_radius,
                  '--compensation': compensation, '--arcs': arcs or None}
        others['--axis'] = axis  # the switch tracks are the machine's, on the machine angle
        for option, value in others.items():
            if value is not None:
                raise InvalidParameter(option, value, 'cannot go with --switches')
        return export_switches(config, output, file_format or 'csv')

    table_options = {'--points': points, '--interpolation': interpolation,
                     '--end-point': end_point, '--derivatives': derivatives or None}
    machining_options = {'--cutter-radius': cutter_radius, '--compensation': compensation,
                         '--arcs': arcs or None}
    if cam_table and machining:
        raise InvalidParameter('--machining', True, 'cannot go with --cam-table: one or the '
                                                    'other')
    if cam_table or machining:
        if samples is not None:
            raise InvalidParameter('--samples', samples, 'counts surface points; a cam table '
                                   'takes --points or --tolerance, a cutter path --tolerance')
        unused = machining_options if cam_table else table_options
        for option, value in unused.items():
            if value is not None:
                raise InvalidParameter(option, value, 'applies to '
                                       + ('--machining' if cam_table else 'cam tables') + ' only')
    if machining:
        from cam_ros.commands.machining import export_machining

        if len(tolerances) > 1:
            raise InvalidParameter('--tolerance', tolerances[1], 'a cutter path takes one '
                                   '--tolerance (in length_unit or with its unit)')
        return export_machining(config, output, cutter_radius, tolerance,
                                file_format or 'gcode', compensation, arcs, axis)
    if cam_table:
        table_format = file_format or 'csv'
        if table_format not in TABLE_FORMATS:
            raise InvalidParameter('--format', table_format, 'a cam table takes one of '
                                   + ', '.join(TABLE_FORMATS))
        from cam_ros.commands.cam_table_export import export_cam_table
        from cam_ros.commands.machine_export import export_machine_tables

        if axis is None and is_machine(read_parameters_file(config)):
            return export_machine_tables(config, output, points, tolerances, table_format,
                                         interpolation, end_point, derivatives)
        return export_cam_table(config, output, points, tolerances, table_format,
                                interpolation, end_point, derivatives, axis)
    surface_only = {**table_options, **machining_options, '--tolerance': tolerance,
                    '--format': file_format}
    for option, value in surface_only.items():
        if value is not None:
            hint = ('cutter paths only: add --machining' if option in machining_options
                    else 'cam tables or cutter paths only: add --cam-table or --machining'
                    if option in ('--tolerance', '--format')
                    else 'cam tables only: add --cam-table')
            raise InvalidParameter(option, value, f'applies to {hint}')
    target = output_path('-o', output, tuple(WRITERS))
    design = load_design(config, axis)
    with writing('export', f'writing {target}', target):
        count = export_surface(design, target, EXPORT_SAMPLES if samples is None else samples)
    print(f'wrote {target}: closed cam surface of {count} points (mm)')
    return verdict('export', design)


def export_switches(config: str, output: str, table_format: str) -> int:
    """Write the cam switch tracks (switches.*) of a config for a PLC's cam controller."""
    from cam_ros.commands.machine import switch_parameters
    from cam_ros.output.switch_table import SWITCH_FORMATS, switch_table_text

    if table_format not in SWITCH_FORMATS:
        raise InvalidParameter('--format', table_format, 'the switch tracks take one of '
                               + ', '.join(SWITCH_FORMATS))
    target = Path(output)
    parameters = switch_parameters(config)
    text = switch_table_text(parameters, table_format, Path(config).name)
    with writing('export', f'writing {target}', target):
        target.write_text(text, encoding='utf-8')
    print(f'wrote {target}: {len(parameters["switches.names"])} cam switch tracks '
          f'({table_format})')
    return EXIT_OK
