"""cam_node's process: its command line, rclpy, the executor, and exit codes.

`cam_node` (and `python -m cam_ros.node`) runs CamNode until Ctrl-C, SIGTERM or its shutdown
transition; invalid input exits 2 with one line 'cam_node: <message>'.
"""
from __future__ import annotations

import gc
import signal
import sys
from typing import Sequence

import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor

from cam_ros.core import CamError
from cam_ros.core.errors import one_line
from cam_ros.exit_codes import EXIT_INVALID
from cam_ros.node.middleware import serve_over_udp
from cam_ros.node.node import CamNode
from cam_ros.node.parameters import parse_command_line, start_rclpy, USAGE
from cam_ros.paths import default_config_path


def _invalid(message: str) -> int:
    """Print one line 'cam_node: message' on stderr and return the exit code of bad input."""
    print(f'cam_node: {one_line(message)}', file=sys.stderr)
    return EXIT_INVALID


STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
SIGNAL_LATENCY_S = 0.1  # the executor's longest wait: how soon a stop signal is acted on


def note_stop_signals() -> list[int]:
    """Return a list that Ctrl-C and SIGTERM append to from now on (also where a shell's '&'
    ignored them), and nothing else.

    rclpy's own handlers shut the context down at once, from a thread of theirs, while the
    node's threads (~/evaluate, the master intake, the recorder's, the line shaft's clock) are
    inside it: the node then logged to a closed /rosout and once crashed (SIGSEGV). Noted here,
    a signal ends the spin; the node is taken down with its context valid, then rclpy.
    """
    heard: list[int] = []
    for sig in STOP_SIGNALS:
        signal.signal(sig, lambda signum, _frame: heard.append(signum))
    return heard


def main(args: Sequence[str] | None = None) -> int:
    """Run cam_node until Ctrl-C, SIGTERM or its shutdown transition; exit 2 with one line on
    invalid input (with autostart: a design configure refuses)."""
    heard = note_stop_signals()
    argv = list(sys.argv if args is None else args)
    try:
        command = parse_command_line(argv, default_config_path())
    except CamError as err:
        return _invalid(str(err))
    if {'-h', '--help'} & set(command.user_args):
        print(USAGE, end='')
        return 0
    if command.user_args:
        return _invalid(f'unrecognized arguments: {" ".join(command.user_args)} '
                        '(see cam_node --help)')
    try:
        serve_over_udp()
    except CamError as err:
        return _invalid(str(err))
    problem = start_rclpy(command.ros_args)
    if problem:  # a bad remapping or logging argument
        return _invalid(f'invalid ROS arguments: {problem}')
    executor = SingleThreadedExecutor()
    node = None
    code = 0
    try:
        node = CamNode(command.sources)
        # The node's own objects, built now, are never collected: moved out of the collector's
        # generations, they cost no collection pauses on the master thread (p99, machines).
        gc.collect()
        gc.freeze()
        executor.add_node(node)
        while not (heard or node.finished.done()):  # a signal or the shutdown transition
            executor.spin_once(timeout_sec=SIGNAL_LATENCY_S)
    except CamError as err:
        code = _invalid(str(err))
    except ExternalShutdownException:
        pass
    finally:
        executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code
