"""The argument parser: consistent help, one-line usage errors, exit codes."""
from __future__ import annotations

import inspect
import subprocess
import sys

import pytest
from cli_support import assert_one_error_line, DEFAULT_CONFIG, run_cli

from cam_ros.cli import _handler, build_parser, main
from cam_ros.core.errors import one_line

COMMANDS = ('report', 'sample', 'plot', 'export', 'call', 'echo', 'record', 'reload', 'param',
            'info', 'replay', 'recover')


def test_top_level_help_lists_every_command_and_the_exit_codes(capsys):
    run = run_cli(capsys, '--help')
    assert run.code == 0 and run.err == ''
    for command in COMMANDS:
        assert f'    {command}' in run.out
    assert 'exit codes:' in run.out and 'cam_ros <command>: <message>' in run.out


@pytest.mark.parametrize('command', COMMANDS)
def test_every_command_has_help_with_the_exit_codes(command, capsys):
    run = run_cli(capsys, command, '--help')
    assert run.code == 0 and run.err == ''
    assert run.out.startswith(f'usage: cam_ros {command} ')
    assert 'exit codes:' in run.out


#: Command -> a fragment of what exit code 1 means for it (None: it never returns 1), and
#: whether Ctrl-C ends it with 0 instead of 130.
FAILURES = {'report': ('violates one of its limits', False), 'sample': ('violates', False),
            'plot': ('violates', False), 'export': ('violates', False),
            'call': ('service was not available', False), 'echo': ('did not arrive', True),
            'record': ('node was not found', False), 'reload': ('node was not found', False),
            'param get': ('refused', False), 'param set': ('refused', False),
            'param list': ('refused', False), 'info': (None, False),
            'replay': ('rejected a recorded change', True),
            'recover': (None, False)}
HANDLERS = {'info': 'cam_ros.commands.recording:info',
            'replay': 'cam_ros.commands.recording:replay',
            'recover': 'cam_ros.commands.recording:recover'}


@pytest.mark.parametrize('command', list(FAILURES))
def test_help_lists_only_the_exit_codes_the_command_can_return(command, capsys):
    run = run_cli(capsys, *command.split(), '--help')
    epilog = run.out[run.out.index('exit codes:'):]
    codes = {line.split()[0]: line for line in epilog.splitlines()[1:] if line[2:3].isdigit()}
    failure, stops_cleanly = FAILURES[command]
    if failure is None:
        assert '1' not in codes
        # ... and the handler indeed has no failure exit: errors raise (exit 2).
        source = inspect.getsource(_handler(HANDLERS[command]))
        assert 'EXIT_FAILED' not in source and 'verdict(' not in source
    else:
        assert failure in ' '.join(epilog.split())
    assert {'0', '2'} <= set(codes)
    assert ('130' in epilog) is not stops_cleanly
    assert ('exit 0' in epilog) is stops_cleanly


def test_version(capsys):
    run = run_cli(capsys, '--version')
    assert run.code == 0 and run.out.startswith('cam_ros ')


@pytest.mark.parametrize('argv, command, fragment', [
    ([], '', 'the following arguments are required: COMMAND'),
    (['frobnicate'], '', "invalid choice: 'frobnicate'"),
    (['report'], ' report', 'the following arguments are required: CONFIG'),
    (['report', 'a.yaml', '--verbose'], '', 'unrecognized arguments: --verbose'),
])
def test_usage_errors_are_one_line_and_exit_2(argv, command, fragment, capsys):
    run = run_cli(capsys, *argv)
    assert run.code == 2 and run.out == ''
    assert run.err.splitlines() == [run.err.rstrip('\n')]
    assert run.err.startswith(f'cam_ros{command}: ') and fragment in run.err
    assert run.err.rstrip().endswith(f'(see cam_ros{command} --help)')


def test_main_reads_sys_argv_by_default(monkeypatch, capsys):
    monkeypatch.setattr('sys.argv', ['cam_ros', 'report', '--help'])
    assert main() == 0
    assert capsys.readouterr().out.startswith('usage: cam_ros report')


def test_parsed_options_are_exactly_the_command_functions_parameters():
    parser = build_parser()
    samples = {'report': ['c'], 'sample': ['c'], 'plot': ['c', '-o', 'x.png'],
               'export': ['c', '-o', 'x.csv'], 'call': ['1'], 'echo': ['/t'], 'record': ['on'],
               'reload': [], 'param get': ['n'], 'param set': ['n', '1'], 'param list': [],
               'info': ['f'], 'replay': ['f'], 'recover': ['f']}
    for command, rest in samples.items():
        options = vars(parser.parse_args([*command.split(), *rest]))
        function = _handler(options.pop('handler'))
        options.pop('command')
        options.pop('action', None)  # main() drops it too
        assert set(options) == set(inspect.signature(function).parameters), command


def test_multi_line_messages_become_one_line():
    assert one_line('bad YAML: here\n  x: [\n     ^\nend') == 'bad YAML: here x: [ end'


def test_invalid_config_error_names_the_command(tmp_path, capsys):
    missing = tmp_path / 'missing.yaml'
    assert_one_error_line(run_cli(capsys, 'sample', missing), 'sample', 'cannot be read')


@pytest.mark.parametrize('value', ['-1e-6', '-2.5E+3', '-.5e1'])
def test_a_negative_number_in_exponent_form_is_a_value_not_an_option(value, tmp_path, capsys):
    target = tmp_path / 'table.csv'
    run = run_cli(capsys, 'export', DEFAULT_CONFIG, '-o', target, '--cam-table',
                  '--tolerance', value)
    assert_one_error_line(run, 'export', f"--tolerance = '{value}'", '> 0')
    assert not target.exists()


def test_a_command_to_a_running_node_is_parsed_and_run_without_design_code():
    # The design commands' choices import the cam tables and the writers, and a design the
    # whole core: some 0.2 s of a command line's 1 s round trip (docs/cli.md).
    code = ('import sys\n'
            'from cam_ros.cli import build_parser, main\n'
            'main(["param", "get", "--help"])\n'
            'import cam_ros.commands.ros, cam_ros.commands.control, cam_ros.commands.lifecycle\n'
            'print(" ".join(sorted(name for name in sys.modules if name.startswith((\n'
            '    "cam_ros.cli.design", "cam_ros.output", "cam_ros.core.design",\n'
            '    "cam_ros.core.geometry.check", "cam_ros.core.machine")))))\n'
            'print(len(build_parser().commands), len(build_parser(design=False).commands))\n')
    done = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          timeout=60, check=True)
    loaded, counts = done.stdout.splitlines()[-2:]
    assert loaded == ''
    every, ros = (int(count) for count in counts.split())
    assert 0 < ros < every and set(COMMANDS) - {'report', 'sample', 'plot', 'export'} <= set(
        build_parser(design=False).commands)
