"""Commands on a machine file (axes on one master): report, sample, the timing diagram.

Each axis's figures are today's single-cam ones (report_text, SI); the interference pairs are
printed in the machine's length_unit with SI beside, a smallest gap or margin rounded down.
"""
from __future__ import annotations

import csv
import math
import sys
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from cam_ros.commands.common import (csv_column, dump_json, end_progress, format_table,
                                     number, output_path, progress, say, writing)
from cam_ros.commands.report_text import format_report, report_data
from cam_ros.commands.slave_limits_text import slave_limits_lines
from cam_ros.core import InvalidParameter, parse_parameters, read_parameters_file
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.machine import (build_machine, check_interference, is_machine, Machine,
                                  machine_report, PairCheck, parse_machine)
from cam_ros.core.machine.served import pair_line, pair_name
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

#: Machine-angle steps of `export --timing-diagram` without --points: one per degree.
TIMING_POINTS = 360
#: The setpoint arrays of `cam_ros sample MACHINE`, per axis: (name, unit; {p} = m or rad).
MACHINE_SAMPLE_FIELDS = (('position', '{p}'), ('velocity', '{p}/s'),
                         ('acceleration', '{p}/s^2'), ('jerk', '{p}/s^3'))


def is_machine_file(config: str | Path) -> bool:
    """Say whether a config file is a machine file (it has axes)."""
    return is_machine(read_parameters_file(config))


def load_machine_file(config: str | Path, option: str) -> Machine:
    """Read, check and build a machine file; a single-cam file is refused naming option."""
    values = read_parameters_file(config)
    if not is_machine(values):
        raise InvalidParameter(option, True, f'{config} is one cam, not a machine file (no '
                                             f'axes): leave out {option}')
    return build_machine(parse_machine(values))


def refuse_options(flag: str, options: dict[str, Any]) -> None:
    """Refuse every option given (not None) that cannot go with flag."""
    for option, value in options.items():
        if value is not None:
            raise InvalidParameter(option, value, f'cannot go with {flag} (it takes every axis '
                                                  'over the machine cycle)')


def switch_parameters(config: str | Path) -> Mapping[str, Any]:
    """Return the checked parameters holding a config's switch tracks (switches.*).

    A single cam's; a machine's machine-wide ones, whose tracks are on the machine angle: the
    master itself (master.offset_deg 0, master.scaling 1).
    """
    values = read_parameters_file(config)
    if not is_machine(values):
        return parse_parameters(values).parameters
    return {**parse_machine(values).parameters, 'master.offset_deg': 0.0, 'master.scaling': 1.0}


def cam_speed(machine: Machine) -> float:
    """Return the machine's cam_speed (rad/s of machine angle)."""
    return float(machine.config.parameters['cam_speed'])


# ------------------------------------------------------------------------------------ verdict

def machine_verdict(command: str, machine: Machine, checks: tuple[PairCheck, ...]) -> int:
    """Return 0 if every axis meets its limits and no pair collides, else say why and return 1.

    One stderr line per warning of a failing axis (named) and per colliding pair.
    """
    for axis in machine.axes:
        if not axis.design.ok:
            for warning in axis.design.warnings():
                say(command, f'warning: axis {axis.name}: {warning}')
    for check in checks:
        if not check.ok:
            say(command, f'warning: {pair_line(check, machine.config.length_unit)}')
    ok = all(axis.design.ok for axis in machine.axes) and all(check.ok for check in checks)
    return EXIT_OK if ok else EXIT_FAILED


# ------------------------------------------------------------------------------------ report

def report(config: str, json_output: bool = False) -> int:
    """Print each axis's report and each interference pair; 1 if any fails."""
    machine = load_machine_file(config, 'axes')
    progress('report', 'sizing each axis')
    text, ok = report_output(machine, config, json_output)
    end_progress()
    print(text)
    return EXIT_OK if ok else EXIT_FAILED


def report_output(machine: Machine, config: str, json_output: bool = False) -> tuple[str, bool]:
    """Return what `cam_ros report` prints for a machine (of config), and its ok."""
    result = machine_report(machine)
    if json_output:
        return dump_json({
            'axes': [{'name': axis.name, **report_data(axis_report, config)}
                     for axis, axis_report in zip(machine.axes, result.axes)],
            'interference': [_pair_data(check) for check in result.interference],
            'ok': result.ok}), result.ok
    return _report_text(machine, result.axes, result.interference, config), result.ok


def _pair_data(check: PairCheck) -> dict[str, Any]:
    """Return one pair's JSON object (a gap in m, a margin in deg; infinite: null)."""
    pair = check.pair
    value = (('min_clearance', check.value) if pair.type == 'clearance'
             else ('min_margin_deg', math.degrees(check.value)))
    return {'axis_a': pair.axis_a, 'axis_b': pair.axis_b, 'type': pair.type,
            value[0]: value[1], 'at_deg': cam_degrees(check.at), 'ok': check.ok}


def _report_text(machine: Machine, reports: tuple, checks: tuple[PairCheck, ...],
                 config: str) -> str:
    """Return the machine report as text: a header, each axis's report, the pairs, a verdict."""
    omega = cam_speed(machine)
    lines = [f'Machine report: {config}',
             f'{len(machine.axes)} axes on one master ({", ".join(machine.config.names)}) at '
             f'{number(omega)} rad/s of machine angle ({number(omega * 30.0 / math.pi)} cycles/'
             'min); each axis\'s figures over its own cam angle']
    for axis, axis_report in zip(machine.axes, reports):
        heading = f'Axis {axis.name}'
        lines += ['', heading, '=' * len(heading),
                  format_report(axis_report, f'{config}, axis {axis.name}', axis=None)]
    lines += slave_limits_lines([(axis.name, axis.design.config.position_unit,
                                  axis_report.slave_limits)
                                 for axis, axis_report in zip(machine.axes, reports)])
    lines += ['', f'Interference (lengths in {machine.config.length_unit}, machine angles)']
    unit = machine.config.length_unit
    lines += [f'  {pair_line(check, unit)}' for check in checks] or ['  no pairs checked']
    failing = [f'axis {axis.name} violates its limits'
               for axis, axis_report in zip(machine.axes, reports) if not axis_report.ok]
    failing += [f'{pair_name(check)} COLLIDES' for check in checks if not check.ok]
    lines += ['', 'Verdict: ' + ('; '.join(failing) if failing else
                                 'every axis meets its limits, no pair collides')]
    return '\n'.join(lines)


# ------------------------------------------------------------------------------------ sample

def sample(config: str, angles: np.ndarray, json_output: bool = False,
           csv_output: bool = False) -> int:
    """Print every axis's commanded setpoints at machine angles (rad) at cam_speed, SI."""
    machine = load_machine_file(config, 'axes')
    setpoints = machine.setpoints(angles, cam_speed(machine))
    units = [{name: template.format(p=axis.design.config.position_unit)
              for name, template in MACHINE_SAMPLE_FIELDS} for axis in machine.axes]
    values = [{name: np.asarray(getattr(points, name), dtype=float) for name in units[0]}
              for points in setpoints]
    if json_output:
        print(dump_json({'angle': angles, 'axes': dict(zip(machine.config.names, values))}))
    elif csv_output:
        writer = csv.writer(sys.stdout, lineterminator='\n')
        writer.writerow(['angle_rad'] + [csv_column(f'{axis.name}_{name}', unit)
                                         for axis, axis_units in zip(machine.axes, units)
                                         for name, unit in axis_units.items()])
        writer.writerows(np.column_stack(
            [angles] + [column for axis_values in values for column in axis_values.values()]
        ).tolist())
    else:
        blocks = []
        for axis, axis_units, axis_values in zip(machine.axes, units, values):
            headers = ['angle (rad)'] + [f'{name} ({unit})' for name, unit in axis_units.items()]
            rows = [[number(value) for value in row]
                    for row in np.column_stack([angles, *axis_values.values()]).tolist()]
            blocks.append(f'Axis {axis.name}: commanded at {number(cam_speed(machine))} rad/s '
                          f'of machine angle\n{format_table(headers, rows)}')
        print('\n\n'.join(blocks))
    return machine_verdict('sample', machine, check_interference(machine))


# ------------------------------------------------------------------------------------ plot

def plot_timing_diagram(config: str, output: str) -> int:
    """Draw every axis over one machine cycle, the switch tracks and every collision."""
    from cam_ros.output.plot import FORMATS
    from cam_ros.output.timing_diagram import plot_timing

    target = output_path('-o', output, FORMATS)
    machine = load_machine_file(config, '--timing-diagram')
    checks = check_interference(machine)
    with writing('plot', f'drawing {target}', target):
        plot_timing(machine, checks, target, title=Path(config).name)
    print(f'wrote {target}: timing diagram of {len(machine.axes)} axes')
    return machine_verdict('plot', machine, checks)


# ------------------------------------------------------------------------------------ export

def export_timing_diagram(config: str, output: str, file_format: str, points: int | None) -> int:
    """Write the timing diagram's curves: each axis's commanded position over a machine cycle."""
    from cam_ros.output.timing_diagram import timing_csv_text

    if file_format != 'csv':
        raise InvalidParameter('--format', file_format, 'the timing diagram takes csv')
    machine = load_machine_file(config, '--timing-diagram')
    count = TIMING_POINTS if points is None else points
    target = Path(output)
    with writing('export', f'writing {target}', target):
        target.write_text(timing_csv_text(machine, count), encoding='utf-8')
    print(f'wrote {target}: timing diagram of {len(machine.axes)} axes, {count + 1} machine '
          'angles over 0-360 deg (csv)')
    return machine_verdict('export', machine, check_interference(machine))
