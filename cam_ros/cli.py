"""The `cam_ros` command line: all argument parsing, then one command function per subcommand.

Commands live in cam_ros.commands and are imported only when run, so `cam_ros report` never
loads rclpy or matplotlib. Every command returns its exit code:

  0  ok
  1  the design violates one of its limits (output is still written), or a ROS command failed
  2  invalid input: config, arguments or file; one line 'cam_ros <command>: <message>' on stderr
"""
from __future__ import annotations

import argparse
import importlib
import math
import os
import re
import sys
import textwrap
from importlib.metadata import PackageNotFoundError, version
from typing import Callable, NoReturn, Sequence

from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS
from cam_ros.output.gcode import MACHINING_FORMATS
from cam_ros.exit_codes import EXIT_INVALID
from cam_ros.core import CamError
from cam_ros.core.errors import one_line
from cam_ros.core.ecam.cam_table import INTERPOLATIONS

#: What exit code 1 means for each kind of command (commands without a failure never return 1).
LIMITS_FAILED = ('the design violates one of its limits (pressure angle, radius of curvature, '
                 'undercut, a velocity jump, or contact stress with dynamics), or a machine\'s '
                 'axis does or an interference pair collides; the output is still written')
CALL_FAILED = 'the service was not available, refused the request or did not answer in time'
ECHO_FAILED = 'the messages asked for (any, without --count/--once) did not arrive in --timeout'
NODE_FAILED = 'the node was not found, did not answer in time or refused the request'
ANY_FAILED = ('report, sample, plot, export: the design violates a limit; call, echo, record, '
              'reload, param, lifecycle: the ROS request failed or was refused')
#: The transitions `cam_ros lifecycle set` takes (`ros2 lifecycle set`'s labels).
TRANSITIONS = ('configure', 'activate', 'deactivate', 'cleanup', 'shutdown')
LIFECYCLE_FAILED = ('the node was not found or did not answer in time, the transition is not '
                    'available from its state, or the node refused it (its reason is printed)')
STOPS_CLEANLY = 'Ctrl-C stops cleanly (exit 0)'


def exit_codes(failed: str | None, interrupt: str = '130 interrupted by Ctrl-C') -> str:
    """Return the 'exit codes:' epilog of a command: only the codes it can return."""
    lines = ['exit codes:', '  0  ok']
    if failed:
        lines += textwrap.wrap(failed, HELP_WIDTH, initial_indent='  1  ',
                               subsequent_indent='     ')
    lines += ['  2  invalid input (config, arguments, file): one line on stderr,',
              '     "cam_ros <command>: <message>"', f'  {interrupt}; 141 output pipe closed']
    return '\n'.join(lines) + '\n'


HELP_WIDTH = 79
EXIT_INTERRUPTED = 130
EXIT_BROKEN_PIPE = 141


class UsageError(Exception):
    """An argument error, reported as one line by main()."""

    def __init__(self, prog: str, message: str):
        super().__init__(message)
        self.prog = prog
        self.message = message


class _Parser(argparse.ArgumentParser):
    """ArgumentParser that raises UsageError instead of printing usage and exiting.

    A negative number in exponent form (--tolerance -1e-6) is a value, not an option.
    """

    def __init__(self, *args: object, **kwargs: object):
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self._negative_number_matcher = re.compile(r'^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$')

    def error(self, message: str) -> NoReturn:
        """Raise the error so that main() prints it as one line."""
        raise UsageError(self.prog, message)


def _number(kind: Callable[[str], float], rule: str,
            ok: Callable[[float], bool]) -> Callable[[str], float]:
    """Return an argparse type converting with kind and checking ok, naming the rule."""
    def convert(text: str) -> float:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'{text!r}: must be {rule}') from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f'{text!r}: must be {rule}')
        return value
    return convert


FINITE = _number(float, 'a finite number', math.isfinite)
POSITIVE = _number(float, 'a finite number > 0', lambda x: math.isfinite(x) and x > 0.0)
NON_NEGATIVE = _number(float, 'a finite number >= 0', lambda x: math.isfinite(x) and x >= 0.0)
STEP_DEG = _number(float, 'a number in (0, 360]', lambda x: 0.0 < x <= 360.0)
COUNT = _number(int, 'an integer >= 1', lambda x: x >= 1)
SAMPLES = _number(int, 'an integer >= 3', lambda x: x >= 3)
POINTS = _number(int, 'an integer >= 2', lambda x: x >= 2)


def _command(sub: argparse._SubParsersAction, name: str, target: str, summary: str,
             description: str, epilog: str) -> argparse.ArgumentParser:
    """Add a subcommand whose handler is the function target ('module:function')."""
    parser = sub.add_parser(name, help=summary, epilog=epilog,
                            description=textwrap.fill(f'{summary}. {description}', HELP_WIDTH),
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.set_defaults(handler=target)
    return parser


def _axis_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--axis', default=None, metavar='NAME',
                        help='a machine file (with axes): take this axis alone, as a single '
                             'cam over its own cam angle')


def _design_commands(sub: argparse._SubParsersAction) -> None:
    config_help = ('cam config: a ROS 2 parameters file (e.g. config/default.yaml), or a '
                   'machine file (with axes, e.g. config/machine.yaml)')
    parser = _command(sub, 'report', 'cam_ros.commands.design:report', 'Report on a cam design',
                      'Pressure angle, radius of curvature, undercut, smallest base radius, '
                      'face width, per-segment Cv/Ca/Cj and peaks at the cam speed, '
                      'discontinuities. SI units, angles in degrees. A machine file: each '
                      'axis\'s report and each interference pair (smallest gap or margin, '
                      'rounded down).', exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object instead of text')
    _axis_option(parser)

    parser = _command(sub, 'sample', 'cam_ros.commands.design:sample', 'Sample a cam design',
                      'Arrays over one revolution from 0: angle (rad), position, velocity, '
                      'acceleration, jerk (SI), their derivatives per rad of cam angle, '
                      'pressure angle (rad) and radius of curvature (m). A machine file: '
                      'each axis\'s position, velocity, acceleration, jerk as commanded at '
                      'cam_speed over the machine angle.',
                      exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('--step-deg', type=STEP_DEG, default=1.0, metavar='D',
                        help='cam angle step in degrees (default 1)')
    form = parser.add_mutually_exclusive_group()
    form.add_argument('--json', dest='json_output', action='store_true',
                      help='print one JSON object of arrays (with units)')
    form.add_argument('--csv', dest='csv_output', action='store_true',
                      help='print CSV with units in the header')
    _axis_option(parser)

    parser = _command(sub, 'plot', 'cam_ros.commands.design:plot', 'Plot a cam design',
                      'S-V-A-J diagrams over cam angle and a drawing of the cam (surface, '
                      'pitch curve, base circle) with the follower at the chosen angle.',
                      exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('-o', '--output', required=True, metavar='FILE',
                        help='image to write: .png or .svg')
    parser.add_argument('--angle-deg', type=FINITE, default=0.0, metavar='A',
                        help='cam angle at which the follower is drawn, deg (default 0)')
    parser.add_argument('--vibration', action='store_true',
                        help='draw the follower train instead: residual-vibration spectrum of '
                             'each moving segment\'s law over r = 0.5..10 with this design\'s '
                             'operating points, and the periodic output against s')
    _axis_option(parser)
    parser.add_argument('--timing-diagram', action='store_true',
                        help='a machine file: every axis over one machine cycle (each in its '
                             'own unit), the switch tracks, every collision or too small a '
                             'margin shaded')

    parser = _command(sub, 'export', 'cam_ros.commands.design:export',
                      'Export the cam surface for manufacturing, a cutter path, or a cam table '
                      'for a PLC',
                      'The surface: one closed curve in mm in the cam frame (cam centre at the '
                      'origin): CSV (x_mm,y_mm), DXF (closed LWPOLYLINE, $INSUNITS = mm) or SVG '
                      '(closed path); a groove cam: both flanks, a conjugate pair: both cams, '
                      'each its own curve. With --machining: the cutter-location path (the '
                      'surface offset by the cutter radius) or the nominal contour, points placed '
                      'by a '
                      'chordal tolerance, in mm (inch for length_unit in). With --cam-table: '
                      'master position (deg) -> slave position (length_unit, deg for '
                      'oscillating followers), optionally velocity and acceleration per deg and '
                      'deg^2 of master.', exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('-o', '--output', required=True, metavar='FILE',
                        help='file to write: .csv, .dxf or .svg (a cam table or a cutter path: '
                             'any name)')
    parser.add_argument('--samples', type=SAMPLES, default=None, metavar='N',
                        help='points on the surface, equally spaced in cam angle '
                             '(default 3600)')
    parser.add_argument('--format', dest='file_format', default=None,
                        choices=tuple(TABLE_FORMATS) + tuple(f for f in MACHINING_FORMATS
                                                             if f not in TABLE_FORMATS),
                        help='a cam table: csv (default), sew (MOVI-C point list), xyva '
                             '(CODESYS SMC_CAMXYVA columns), st (IEC 61131-3 ARRAY OF LREAL), '
                             'lenze (Global Drive Cam Loader text), kollmorgen (KAS cam CSV), '
                             'rockwell (L5X tag of CAM[N] for MCCP), twincat-functions (ST '
                             'ARRAY OF MC_MotionFunctionPoint: polynomial laws exact, others '
                             'quintic pieces within --tolerance); '
                             'a cutter path: gcode (default), csv (the nominal contour with '
                             'its unit normals, for a CMM), dxf')
    spacing = parser.add_mutually_exclusive_group()
    spacing.add_argument('--tolerance', default=None, metavar='T',
                         help='a cam table: place points so that the interpolation stays '
                              'within T of the exact law, T in the table\'s unit (the config\'s '
                              'length_unit, deg for oscillating followers); a cutter path: the '
                              'chordal tolerance in length_unit (required); or with a unit: '
                              '0.01mm, 10um, 1e-5m, 0.1deg')
    machining = parser.add_argument_group('cutter path')
    machining.add_argument('--machining', action='store_true',
                           help='write a cutter path (G-code) or the nominal contour instead of '
                                'the surface')
    machining.add_argument('--cutter-radius', default=None, metavar='R',
                           help='cutter radius in length_unit or with a unit (required but for '
                                '--format csv); a cutter larger than the smallest concave '
                                'radius of the cam is refused')
    machining.add_argument('--compensation', default=None, choices=('left', 'right'),
                           help='gcode: write the nominal contour with G41 (left) or G42 '
                                '(right) and the cutter radius in register D1, instead of the '
                                'offset path')
    machining.add_argument('--arcs', action='store_true',
                           help='gcode: join runs of points into arcs (G2/G3) where an arc stays '
                                'within --tolerance of the exact curve')
    table = parser.add_argument_group('cam table')
    table.add_argument('--cam-table', action='store_true',
                       help='write a cam table instead of the surface')
    spacing.add_argument('--points', type=POINTS, default=None, metavar='N',
                         help='a cam table: N equidistant master steps over one revolution '
                              '(default 360): N + 1 rows with the end point 360 deg, N without')
    table.add_argument('--interpolation', default=None, choices=INTERPOLATIONS,
                       help='what the target does between points (default linear; xyva: '
                            'quintic, its only one); cubic: Hermite with the velocity column as '
                            'slopes (csv); quintic: fifth-degree pieces through position, '
                            'velocity and acceleration (csv, xyva)')
    table.add_argument('--end-point', action=argparse.BooleanOptionalAction, default=None,
                       help='write the periodic end point 360 deg (default: yes)')
    table.add_argument('--derivatives', action='store_true',
                       help='csv: add velocity and acceleration columns')
    parser.add_argument('--switches', action='store_true',
                        help='write the cam switch tracks (switches.*) for a PLC\'s cam '
                             'controller instead: --format csv (default) or st (PLCopen '
                             'MC_CAMSWITCH_TR / MC_TRACK_TR field names)')
    _axis_option(parser)
    parser.add_argument('--timing-diagram', action='store_true',
                        help='a machine file: each axis\'s commanded position over one machine '
                             'cycle, --format csv: machine angle (deg) and a column per axis in '
                             'its file unit, --points N steps (default 360: N + 1 rows)')


def _ros_commands(sub: argparse._SubParsersAction) -> None:
    parser = _command(sub, 'call', 'cam_ros.commands.ros:call', 'Call a cam node',
                      'Evaluate the served cam at cam angles through its EvaluateCam service '
                      'and print position, velocity, acceleration, jerk, pressure angle and '
                      'radius of curvature (SI; the table shows angles in degrees too).',
                      exit_codes(CALL_FAILED))
    parser.add_argument('angles', nargs='+', type=FINITE, metavar='ANGLE',
                        help='cam angles, rad (deg with --deg); any real value')
    parser.add_argument('--deg', dest='degrees', action='store_true',
                        help='the angles are in degrees')
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object of arrays (SI, with units)')
    parser.add_argument('--service', default='/cam/evaluate', metavar='NAME',
                        help='EvaluateCam service (default /cam/evaluate)')
    parser.add_argument('--timeout', type=POSITIVE, default=5.0, metavar='S',
                        help='seconds to wait for the service and its answer (default 5)')

    parser = _command(sub, 'echo', 'cam_ros.commands.ros:echo', 'Print a topic',
                      'Subscribe to any topic once it has a publisher (type and QoS from the '
                      'graph; latched topics are received) and print each message YAML-like, '
                      'or as CSV of its numeric fields.', exit_codes(ECHO_FAILED, STOPS_CLEANLY))
    parser.add_argument('topic', metavar='TOPIC', help='topic name, e.g. /cam/joint_states')
    amount = parser.add_mutually_exclusive_group()
    amount.add_argument('--once', action='store_true', help='print one message and exit')
    amount.add_argument('--count', type=COUNT, default=None, metavar='N',
                        help='print N messages and exit')
    parser.add_argument('--csv', dest='csv_output', action='store_true',
                        help='print numeric fields as CSV (header from the first message)')
    parser.add_argument('--timeout', type=POSITIVE, default=None, metavar='S',
                        help='give up after S seconds (exit 1 if the messages asked for, or '
                             'any message, did not arrive); default: wait for ever')


def _node_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--node', default='/cam', metavar='NAME',
                        help='the cam node (default /cam)')
    parser.add_argument('--timeout', type=POSITIVE, default=5.0, metavar='S',
                        help='seconds to wait for the node and its answer (default 5)')


def _actions(parser: argparse.ArgumentParser, failed: str,
             actions: Sequence[tuple[str, str, str]]) -> dict[str, argparse.ArgumentParser]:
    """Add ACTION subcommands (name, handler 'module:function', summary) to a node command."""
    sub = parser.add_subparsers(dest='action', metavar='ACTION', required=True)
    made = {}
    for action, target, summary in actions:
        made[action] = sub.add_parser(
            action, help=summary, description=f'{summary[0].upper()}{summary[1:]}.',
            epilog=exit_codes(failed), formatter_class=argparse.RawDescriptionHelpFormatter)
        made[action].set_defaults(handler=target)
        _node_options(made[action])
    return made


def _node_commands(sub: argparse._SubParsersAction) -> None:
    parser = _command(sub, 'record', 'cam_ros.commands.control:record',
                      'Start or stop recording', 'Through the node\'s ~/record service; prints '
                      'the file recorded to, or the messages written.', exit_codes(NODE_FAILED))
    parser.add_argument('state', choices=('on', 'off'), metavar='on|off',
                        help='on: record to a new file; off: stop, write the summary')
    _node_options(parser)

    parser = _command(sub, 'reload', 'cam_ros.commands.control:reload',
                      'Reload the params file', 'The node re-reads the params file it was '
                      'started with (~/reload); a file the node refuses changes nothing.',
                      exit_codes(NODE_FAILED))
    _node_options(parser)

    parser = _command(sub, 'param', '', 'Get, set or list node parameters',
                      'Through the node\'s parameter services. `set` is atomic: all the '
                      'values are taken, or none and the node\'s reason is printed.',
                      exit_codes(NODE_FAILED))
    made = _actions(parser, NODE_FAILED, [
        (action, f'cam_ros.commands.control:param_{action}', summary)
        for action, summary in (('get', 'print parameter values'),
                                ('set', 'set parameters atomically'),
                                ('list', 'print every parameter and its value'))])
    made['get'].add_argument('names', nargs='+', metavar='NAME', help='parameter names')
    made['set'].add_argument('assignments', nargs='+', metavar='NAME VALUE',
                             help='names and values; values as YAML, as `ros2 param set` reads '
                                  'them (4.0 is a double, 4 an integer, [1.0, 2.0] an array)')


def _lifecycle_command(sub: argparse._SubParsersAction) -> None:
    parser = _command(sub, 'lifecycle', '', 'Get or change a managed node\'s state',
                      'As `ros2 lifecycle get|set` does, through the node\'s lifecycle '
                      'services (~/get_state, ~/get_available_transitions, ~/change_state).',
                      exit_codes(LIFECYCLE_FAILED))
    made = _actions(parser, LIFECYCLE_FAILED, (
        ('get', 'cam_ros.commands.lifecycle:get',
         'print the state as `ros2 lifecycle get` does: active [3]'),
        ('set', 'cam_ros.commands.lifecycle:set_state',
         'take a transition; print "from -> to"')))
    made['set'].add_argument('transition', metavar='TRANSITION', choices=TRANSITIONS,
                             help=', '.join(TRANSITIONS[:-1]) + f' or {TRANSITIONS[-1]}')


def _recording_commands(sub: argparse._SubParsersAction) -> None:
    parser = _command(sub, 'info', 'cam_ros.commands.recording:info', 'Describe a recording',
                      'Topics, types, counts, QoS, duration and attachments of an MCAP '
                      'recording, laid out like `ros2 bag info`.', exit_codes(None))
    parser.add_argument('path', metavar='FILE', help='MCAP recording')
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object')

    parser = _command(sub, 'replay', 'cam_ros.commands.recording:replay', 'Replay a recording',
                      'Publish the recorded messages with their recorded QoS and timing: '
                      'by default the recording node\'s inputs (its master, slave state and '
                      '~/engage calls, made again at their master messages), not its own '
                      'outputs; stderr says what is left out.',
                      exit_codes('--apply-parameters: a node did not answer or rejected a '
                                 'recorded change; a recorded ~/engage call was not answered '
                                 'as recorded', STOPS_CLEANLY))
    parser.add_argument('path', metavar='FILE', help='MCAP recording')
    parser.add_argument('--rate', type=POSITIVE, default=1.0, metavar='R',
                        help='speed factor (default 1: recorded timing)')
    parser.add_argument('--topics', nargs='+', default=None, metavar='TOPIC',
                        help='replay exactly these topics (an ~/engage_requests topic: its '
                             'calls)')
    parser.add_argument('--outputs', action='store_true',
                        help='publish the recording node\'s own outputs too (commands, joint '
                             'states, diagnostics...), where a controller may be listening')
    parser.add_argument('--apply-parameters', action='store_true',
                        help='set the recorded parameter changes (/parameter_events) on their '
                             'nodes, one atomic set per event, before the first message logged '
                             'at or after it (not recording.*; not with --loop)')
    parser.add_argument('--loop', action='store_true', help='repeat until Ctrl-C')
    parser.add_argument('--wait', type=NON_NEGATIVE, default=3.0, metavar='S',
                        help='seconds to wait for every topic to have a subscriber before '
                             'the first message (default 3; 0: start at once)')

    parser = _command(sub, 'recover', 'cam_ros.commands.recording:recover',
                      'Recover a killed recording',
                      'Copy what a recording cut short holds (every complete record) into a '
                      'finished file with summary, footer and rosbag2 metadata, which every '
                      'reader opens; the input is left alone unless --in-place.', exit_codes(None))
    parser.add_argument('path', metavar='FILE', help='MCAP recording')
    target = parser.add_mutually_exclusive_group()
    target.add_argument('-o', '--output', default=None, metavar='OUT',
                        help='new file to write (default FILE with suffix .recovered.mcap)')
    target.add_argument('--in-place', action='store_true',
                        help='replace FILE, once the recovered file is complete')


def build_parser() -> argparse.ArgumentParser:
    """Return the parser of the whole `cam_ros` command line."""
    try:
        release = version('cam_ros')
    except PackageNotFoundError:
        release = 'unknown'
    parser = _Parser(prog='cam_ros', description='Design, inspect and serve disk cams.',
                     epilog=exit_codes(ANY_FAILED, '130 interrupted by Ctrl-C (echo, replay: '
                                                   'exit 0)'),
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--version', action='version', version=f'cam_ros {release}')
    sub = parser.add_subparsers(dest='command', metavar='COMMAND', required=True)
    _design_commands(sub)
    _ros_commands(sub)
    _node_commands(sub)
    _lifecycle_command(sub)
    _recording_commands(sub)
    return parser


def _handler(target: str) -> Callable[..., int]:
    module, _, function = target.partition(':')
    return getattr(importlib.import_module(module), function)


def main(argv: Sequence[str] | None = None) -> int:
    """Run `cam_ros` with argv (default sys.argv[1:]); return the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except UsageError as err:
        print(f'{err.prog}: {err.message} (see {err.prog} --help)', file=sys.stderr)
        return EXIT_INVALID
    except SystemExit as done:  # --help, --version
        return int(done.code or 0)
    options = vars(args)
    command, target = options.pop('command'), options.pop('handler')
    options.pop('action', None)  # the handler of `param`/`lifecycle ACTION` is the action's
    try:
        return _handler(target)(**options)
    except CamError as err:
        print(f'cam_ros {command}: {one_line(str(err))}', file=sys.stderr)
        return EXIT_INVALID
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # the reader went away (e.g. `| head`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE


if __name__ == '__main__':
    sys.exit(main())
