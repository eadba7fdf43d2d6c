"""`cam_ros plan`: the moves an engagement or a recovery makes onto the cams, before making them.

A machine file's axes, or a single cam as a machine of one axis (its axis `follower`): every axis
given a position moves onto its cam (core.ecam.moves), the others stay on theirs, all with the
master at --master-position turning at --master-speed; the moves are checked against every
interference pair and ordered when moving together would collide (core.machine.move_check).
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Union

from cam_ros.commands.common import dump_json
from cam_ros.core import InvalidParameter, read_parameters_file
from cam_ros.core.cam_angles import cam_degrees
from cam_ros.core.config.quantity import typed_quantity
from cam_ros.core.ecam.moves import AxisState, MasterMotion, Move
from cam_ros.core.ecam.slave_limits import BACKWARD_TOLERANCE, SlaveLimits
from cam_ros.core.machine import Machine
from cam_ros.core.machine.move_check import (axis_limits, check_moves, MoveCheck, plan_moves,
                                             Sequence, sequence_moves)
from cam_ros.core.machine.served import machine_from_values, pair_name
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

#: The peaks `plan` sets against each limit: (name, SlaveLimits field, per time).
PEAKS = (('velocity', 'max_velocity', '/s'), ('acceleration', 'max_acceleration', '/s^2'),
         ('jerk', 'max_jerk', '/s^3'))
DIRECTION_NAMES = {1: 'positive', -1: 'negative'}


def plan(config: str, position: list[str], master_speed: float = 0.0,
         master_position: str = '0', json_output: bool = False) -> int:
    """Print the moves onto the cams from the positions given; exit 1 when refused."""
    machine = machine_from_values(read_parameters_file(config))
    starts = start_positions(machine, position)
    theta = typed_quantity('--master-position', master_position, 'deg', angular=True)
    master = MasterMotion(theta, master_speed)
    moves = plan_moves(machine, starts, master)
    if isinstance(moves, str):
        found: Union[Sequence, str] = moves
        planned: Mapping[str, Move] = {}
        checks: tuple[MoveCheck, ...] = ()
    else:
        found = sequence_moves(machine, moves, master)
        planned, checks = ((found.moves, found.checks) if isinstance(found, Sequence)
                           else (moves, check_moves(machine, moves, master)))
    refused = found if isinstance(found, str) else None
    data = plan_data(machine, config, master, starts, planned, found, checks)
    print(dump_json(data) if json_output else plan_text(machine, data))
    return EXIT_FAILED if refused else EXIT_OK


def start_positions(machine: Machine, texts: list[str]) -> dict[str, AxisState]:
    """Return each axis's start (at rest) from the --position texts AXIS=VALUE (SI)."""
    names = machine.config.names
    starts: dict[str, AxisState] = {}
    for text in texts:
        name, given, value = text.rpartition('=')
        if not given and len(names) == 1:
            name = names[0]
        if name not in names:
            raise InvalidParameter('--position', text, f'must be AXIS=VALUE, AXIS one of '
                                                       f'{", ".join(names)}')
        if name in starts:
            raise InvalidParameter('--position', text, f'gives {name} twice')
        axis = machine.axis(name).design.config
        starts[name] = AxisState(typed_quantity('--position', value, axis.length_unit,
                                                angular=axis.angular))
    return starts


def plan_data(machine: Machine, config: str, master: MasterMotion,
              starts: Mapping[str, AxisState], moves: Mapping[str, Move],
              found: Union[Sequence, str], checks: tuple[MoveCheck, ...]) -> dict[str, Any]:
    """Return what `plan` says, as JSON-ready data (SI, angles in deg)."""
    axes = {}
    for name, start in starts.items():
        axis = machine.axis(name)
        limits, unit, _ = axis_limits(axis)
        entry: dict[str, Any] = {'unit': unit.si, 'file_unit': unit.name,
                                 'per_si': unit.per_si, 'start': start.position}
        move = moves.get(name)
        if move is not None:
            entry.update(moved(move, limits))
        axes[name] = entry
    length_unit = machine.config.length_unit
    return {
        'config': config,
        'master': {'position_deg': math.degrees(master.theta), 'speed': master.omega},
        'axes': axes,
        'order': list(found.order) if isinstance(found, Sequence) else None,
        'pairs': [{'pair': pair_name(check.check), 'value': check.check.value,
                   'unit': 'm' if check.check.pair.type == 'clearance' else 'rad',
                   'at_deg': cam_degrees(check.check.at, 2), 'time_s': check.time,
                   'ok': check.ok, 'line': check.line(length_unit)} for check in checks],
        'ok': isinstance(found, Sequence),
        'refused': found if isinstance(found, str) else None,
    }


def moved(move: Move, limits: SlaveLimits) -> dict[str, Any]:
    """Return one move's figures: where it ends, its timing, its peaks against the limits."""
    target = float(move.commands([move.duration])[0][0])
    peaks = {name: {'value': getattr(move.peaks, name), 'limit': getattr(limits, field) or None,
                    'ok': not getattr(limits, field)
                    or getattr(move.peaks, name) <= getattr(limits, field)}
             for name, field, _ in PEAKS if name != 'jerk' or limits.max_jerk}
    if limits.direction:
        peaks['direction'] = {'value': move.peaks.backward,
                              'limit': DIRECTION_NAMES[limits.direction],
                              'ok': move.peaks.backward <= BACKWARD_TOLERANCE}
    return {'target': target, 'turns': move.turns, 'delay_s': move.delay,
            'duration_s': move.duration, 'peaks': peaks}


def plan_text(machine: Machine, data: Mapping[str, Any]) -> str:
    """Return `plan`'s report: the moves, the order, the pairs, the verdict."""
    master = data['master']
    speed = master['speed']
    lines = [f'Moves onto the cams: {data["config"]}, master at '
             f'{master["position_deg"]:.6g} deg, '
             + (f'turning at {speed:.6g} rad/s' if speed else 'at rest')]
    for name, entry in data['axes'].items():
        lines += axis_lines(machine, name, entry)
    if data['order']:
        lines.append(f'Order: {", then ".join(data["order"])}, each waiting at its start until '
                     'the one before is on its cam (together they would collide)')
    elif data['ok']:
        lines.append('Order: together')
    if data['pairs']:
        lines.append(f'Interference during the moves (lengths in {machine.config.length_unit}, '
                     'machine angles)')
        lines += [f'  {pair["line"]}' for pair in data['pairs']]
    verdict = ('the moves keep every limit and no pair collides' if data['ok']
               else f'REFUSED: {data["refused"]}')
    return '\n'.join([*lines, '', f'Verdict: {verdict}'])


def axis_lines(machine: Machine, name: str, entry: Mapping[str, Any]) -> list[str]:
    """Return one axis's lines: its move and its peaks against its limits."""
    limits, unit, _ = axis_limits(machine.axis(name))
    if 'duration_s' not in entry:
        return [f'Axis {name}: from {unit.say(entry["start"])}: not planned']
    if not entry['duration_s']:
        return [f'Axis {name}: at {unit.say(entry["start"])}, on its cam: no move']
    turns, delay = entry['turns'], entry['delay_s']
    joined = f', {turns:+d} turn{"s" if abs(turns) != 1 else ""}' if turns else ''
    timing = (f'waits {delay:.6g} s, moves {entry["duration_s"] - delay:.6g} s (on its cam '
              f'{entry["duration_s"]:.6g} s after the start)' if delay
              else f'moves {entry["duration_s"]:.6g} s')
    lines = [f'Axis {name}: from {unit.say(entry["start"])} onto its cam at '
             f'{unit.say(entry["target"])}{joined}: {timing}']
    for peak, field, per in PEAKS:
        if peak not in entry['peaks']:
            continue
        figures = entry['peaks'][peak]
        limit = getattr(limits, field)
        against = (f'limit {unit.say(limit, per)}: {"ok" if figures["ok"] else "EXCEEDS"}'
                   if limit else 'no limit (off its cam within the cam\'s own peaks at cam_speed)')
        lines.append(f'  {peak:<12}  peak {unit.say(figures["value"], per)}, {against}')
    if 'direction' in entry['peaks']:
        figures = entry['peaks']['direction']
        lines.append(f'  {"direction":<12}  {figures["limit"]} only: '
                     + ('never against it: ok' if figures['ok'] else
                        f'moves against it at {unit.say(figures["value"], "/s")}: EXCEEDS'))
    return lines
