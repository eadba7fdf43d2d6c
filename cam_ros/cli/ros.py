"""The ROS commands of `cam_ros`: call, echo, info, param, lifecycle, record and replay."""
from __future__ import annotations

import argparse
from typing import Sequence

from cam_ros.cli.arguments import (add_command, CALL_FAILED, COUNT, ECHO_FAILED, exit_codes,
                                   FINITE, LIFECYCLE_FAILED, NODE_FAILED, NON_NEGATIVE, POSITIVE,
                                   STOPS_CLEANLY, TRANSITIONS)


def ros_commands(sub: argparse._SubParsersAction) -> None:
    parser = add_command(sub, 'call', 'cam_ros.commands.ros:call', 'Call a cam node',
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

    parser = add_command(sub, 'echo', 'cam_ros.commands.ros:echo', 'Print a topic',
                         'Subscribe to any topic once it has a publisher (type and QoS from the '
                         'graph; latched topics are received) and print each message YAML-like, '
                         'or as CSV of its numeric fields.',
                         exit_codes(ECHO_FAILED, STOPS_CLEANLY))
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


def node_commands(sub: argparse._SubParsersAction) -> None:
    parser = add_command(sub, 'record', 'cam_ros.commands.control:record',
                         'Start or stop recording', 'Through the node\'s ~/record service; prints '
                         'the file recorded to, or the messages written.', exit_codes(NODE_FAILED))
    parser.add_argument('state', choices=('on', 'off'), metavar='on|off',
                        help='on: record to a new file; off: stop, write the summary')
    _node_options(parser)

    parser = add_command(sub, 'reload', 'cam_ros.commands.control:reload',
                         'Reload the params file', 'The node re-reads the params file it was '
                         'started with (~/reload); a file the node refuses changes nothing.',
                         exit_codes(NODE_FAILED))
    _node_options(parser)

    parser = add_command(sub, 'param', '', 'Get, set or list node parameters',
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


def lifecycle_command(sub: argparse._SubParsersAction) -> None:
    parser = add_command(sub, 'lifecycle', '', 'Get or change a managed node\'s state',
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


def recording_commands(sub: argparse._SubParsersAction) -> None:
    parser = add_command(sub, 'info', 'cam_ros.commands.recording:info', 'Describe a recording',
                         'Topics, types, counts, QoS, duration and attachments of an MCAP '
                         'recording, laid out like `ros2 bag info`.', exit_codes(None))
    parser.add_argument('path', metavar='FILE', help='MCAP recording')
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object')

    parser = add_command(sub, 'replay', 'cam_ros.commands.recording:replay', 'Replay a recording',
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

    parser = add_command(sub, 'recover', 'cam_ros.commands.recording:recover',
                         'Recover a killed recording',
                         'Copy what a recording cut short holds (every complete record) into a '
                         'finished file with summary, footer and rosbag2 metadata, which every '
                         'reader opens; the input is left alone unless --in-place.',
                         exit_codes(None))
    parser.add_argument('path', metavar='FILE', help='MCAP recording')
    target = parser.add_mutually_exclusive_group()
    target.add_argument('-o', '--output', default=None, metavar='OUT',
                        help='new file to write (default FILE with suffix .recovered.mcap)')
    target.add_argument('--in-place', action='store_true',
                        help='replace FILE, once the recovered file is complete')
