"""The command line page's synopsis names every cam_ros command and only options that exist."""
from __future__ import annotations

import argparse
import re

from docs_support import DOCS

from cam_ros.cli import build_parser


def subcommands() -> dict[str, argparse.ArgumentParser]:
    """Return cam_ros's commands by name."""
    (action,) = [action for action in build_parser()._actions
                 if isinstance(action, argparse._SubParsersAction)]
    return dict(action.choices)


def options(parser: argparse.ArgumentParser) -> set[str]:
    """Return every option string of a parser and of its subparsers (param get|set|list)."""
    found = {option for action in parser._actions for option in action.option_strings}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found |= options(sub)
    return found


def synopsis() -> dict[str, set[str]]:
    """Return each command of the page's synopsis with the options its lines name."""
    page = (DOCS / 'cli.md').read_text()
    block = page.split('```text\n', 1)[1].split('```', 1)[0]
    named: dict[str, set[str]] = {}
    command = None
    for line in block.splitlines():
        if line.startswith('cam_ros '):
            command = line.split()[1]
            named.setdefault(command, set())
        elif not line.lstrip().startswith('[') or command is None:
            continue
        left = line.strip().split('   ')[0]  # the usage column, not the description
        named[command] |= set(re.findall(r'(?<![\w-])(--?[a-z][\w-]*)', left))
    return named


def test_synopsis_lists_every_command_with_options_it_has() -> None:
    commands, named = subcommands(), synopsis()
    assert set(named) == set(commands), (set(commands) ^ set(named))
    for command, given in named.items():
        given = {option.replace('--[no-]', '--') for option in given}
        assert given <= options(commands[command]), (command, given - options(commands[command]))
