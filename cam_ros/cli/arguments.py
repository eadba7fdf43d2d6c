"""The `cam_ros` command line's building blocks: exit-code texts, the parser, argument types."""
from __future__ import annotations

import argparse
import math
import re
import textwrap
from typing import Callable, NoReturn

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


class Parser(argparse.ArgumentParser):
    """ArgumentParser that raises UsageError instead of printing usage and exiting.

    A negative number in exponent form (--tolerance -1e-6) is a value, not an option.
    """

    def __init__(self, *args: object, **kwargs: object):
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.commands: tuple[str, ...] = ()  # the subcommands' names (build_parser)
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


def add_command(sub: argparse._SubParsersAction, name: str, target: str, summary: str,
                description: str, epilog: str) -> argparse.ArgumentParser:
    """Add a subcommand whose handler is the function target ('module:function')."""
    parser = sub.add_parser(name, help=summary, epilog=epilog,
                            description=textwrap.fill(f'{summary}. {description}', HELP_WIDTH),
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.set_defaults(handler=target)
    return parser


def axis_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--axis', default=None, metavar='NAME',
                        help='a machine file (with axes): take this axis alone, as a single '
                             'cam over its own cam angle')
