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
import os
import sys
from importlib.metadata import PackageNotFoundError, version
from typing import Callable, Sequence

from cam_ros.cli.arguments import (Parser, ANY_FAILED, EXIT_BROKEN_PIPE, EXIT_INTERRUPTED,
                                   exit_codes, UsageError)
from cam_ros.cli.ros import (lifecycle_command, node_commands, recording_commands,
                             ros_commands)
from cam_ros.core import CamError
from cam_ros.core.errors import one_line
from cam_ros.exit_codes import EXIT_INVALID


def build_parser(design: bool = True) -> Parser:
    """Return the parser of the whole `cam_ros` command line (design false: of the commands
    that talk to ROS alone, whose parsers import no design code: see main)."""
    try:
        release = version('cam_ros')
    except PackageNotFoundError:
        release = 'unknown'
    parser = Parser(prog='cam_ros', description='Design, inspect and serve disk cams.',
                    epilog=exit_codes(ANY_FAILED, '130 interrupted by Ctrl-C (echo, replay: '
                                                  'exit 0)'),
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--version', action='version', version=f'cam_ros {release}')
    sub = parser.add_subparsers(dest='command', metavar='COMMAND', required=True)
    if design:
        from cam_ros.cli.design import design_commands  # the cam tables' and writers' choices
        design_commands(sub)
    ros_commands(sub)
    node_commands(sub)
    lifecycle_command(sub)
    recording_commands(sub)
    parser.commands = tuple(sub.choices)
    return parser


def _handler(target: str) -> Callable[..., int]:
    module, _, function = target.partition(':')
    return getattr(importlib.import_module(module), function)


def main(argv: Sequence[str] | None = None) -> int:
    """Run `cam_ros` with argv (default sys.argv[1:]); return the exit code.

    A command that talks to a running node is parsed without the design commands: their
    choices import the core's cam tables and the writers, some 0.2 s of a 1 s round trip."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(design=False)
    if not argv or argv[0] not in parser.commands:
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
