"""Find the documentation's examples (Sybil, MyST code blocks) and check each against the code.

Fenced blocks by language:
- ``sh``: command lines. `cam_ros` lines are parsed by the real argparse parser, and the cheap
  design commands (report, sample, export, plot, plan) run for real and must exit 0; `make`
  names a Makefile target and existing files; `cam_node`, `ros2 run` and `export` lines are
  checked as described in `check_command`. Anything else fails: a new kind of command needs a
  rule here.
- ``console``: `$ command` lines (run as above) followed by an excerpt of their output: every
  shown line must appear in the real output, in order (`...` stands for lines left out). A
  command may exit 1 (the design breaks its limits) only where its excerpt shows it: a line
  that `FAILING` matches (the report's failing verdict, or a command's warning).
- ``yaml``: a whole parameters file is read and checked by the project's own reader and schema
  (`read_parameters_file`, `parse_parameters`); a fragment's every key must be a cam parameter
  whose value passes its rule (`check_parameter`).
- ``python``: run, or only compiled when the line before the block is
  `<!-- docs: compile only (needs a running node) -->`.
- ``text``: not code (trees, formulae, usage synopses); the synopsis of the command line is
  checked in test_docs_cli_synopsis.py.
"""
from __future__ import annotations

import argparse
import os
import re
import shlex
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any, Callable

from sybil import Document, Example
from sybil.parsers.myst import CodeBlockParser

from cam_ros.cli import build_parser
from cam_ros.core.config.parameters import check_parameter
from cam_ros.core.config.params_file import flatten, parse_yaml, read_parameters_file
from cam_ros.core.config.schema import parse_parameters

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / 'docs'
PAGES = [REPO / 'README.md', *sorted(DOCS.glob('*.md'))]
LANGUAGES = ('sh', 'console', 'yaml', 'python', 'text')
COMPILE_ONLY = '<!-- docs: compile only (needs a running node) -->'
#: cam_ros commands cheap enough to run for real on the shipped configs (a second or two each).
RUN = {'report', 'sample', 'export', 'plot', 'plan'}
TIMEOUT_S = 120
#: An output line saying the design breaks its limits: the only excuse for an example's exit 1.
FAILING = re.compile(r'Verdict: (VIOLATES its limits|.*(violates its limits|COLLIDES))'
                     r'|cam_ros \w+: warning: ')


def document(path: Path) -> Document:
    """Parse one page into its examples, one parser per language."""
    parsers = [CodeBlockParser(language=language, evaluator=EVALUATORS[language])
               for language in LANGUAGES]
    return Document.parse(str(path), *parsers)


def documents() -> list[Document]:
    """Parse every page into its examples."""
    return [document(path) for path in PAGES]


def examples() -> list[Example]:
    """Return every example of every page."""
    return [example for document in documents() for example in document]


def example_id(example: Example) -> str:
    """Name an example by page and line, e.g. docs/cli.md:12."""
    return f'{Path(example.path).relative_to(REPO)}:{example.line}'


def command_lines(source: str) -> list[str]:
    """Join backslash continuations, drop comments and blank lines."""
    joined = re.sub(r'\\\n\s*', ' ', source)
    lines = []
    for line in joined.splitlines():
        words = shlex.split(line, comments=True)
        if words:
            lines.append(line.strip())
    return lines


def workspace(tmp: Path) -> Path:
    """Return a folder where commands run as at the repository root, writing only into tmp."""
    for name in ('config',):
        link = tmp / name
        if not link.exists():
            link.symlink_to(REPO / name)
    (tmp / 'docs').mkdir(exist_ok=True)
    return tmp


def run(words: list[str], cwd: Path) -> tuple[int, str]:
    """Run a cam_ros command from the venv; return its exit code and its output."""
    command = [str(Path(sys.executable).parent / 'cam_ros'), *words[1:]]
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT_S,
                          env={**os.environ, 'MPLBACKEND': 'Agg', 'PYTHONPATH': str(REPO)})
    return done.returncode, done.stdout + done.stderr


def strict(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Refuse abbreviated options in the parser and its subparsers: the docs spell them out."""
    parser.allow_abbrev = False
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                strict(sub)
    return parser


def check_cam_ros(words: list[str], cwd: Path, may_fail: bool) -> str | None:
    """
    Parse a cam_ros command with the real parser, run it when cheap; return its output.

    It must exit 0, or 1 when may_fail (the page shows that the design breaks its limits).
    """
    try:
        args = strict(build_parser()).parse_args(words[1:])
    except SystemExit as err:  # argparse's error (our parser raises UsageError instead)
        raise AssertionError(f'{shlex.join(words)}: argparse refused it ({err})') from err
    except Exception as err:  # noqa: B902 - UsageError and friends
        raise AssertionError(f'{shlex.join(words)}: the parser refused it: {err}') from err
    if args.command not in RUN:
        return None
    code, output = run(words, cwd)
    assert code == 0 or (code == 1 and may_fail), (
        f'{shlex.join(words)}: exit {code} (1, the design breaks its limits, only in a console '
        f'block whose excerpt shows the failing verdict or warning)\n{output}')
    assert 'Traceback' not in output, output
    return output


def check_files(words: list[str]) -> None:
    """Check that every repository file a command names exists."""
    for word in words:
        for path in re.findall(r'(?:config|docs|benchmarks|tools)/[\w./-]+', word):
            assert (REPO / path).exists(), f'{path} named in {shlex.join(words)} does not exist'


def makefile_targets() -> set[str]:
    """Return the targets the Makefile declares."""
    text = (REPO / 'Makefile').read_text()
    return set(re.findall(r'^([\w.-]+):', text, flags=re.M))


def check_cam_node(words: list[str]) -> None:
    """Check cam_node's params files exist and its -p overrides pass the parameters' rules."""
    check_files(words)
    assert words[1] == '--ros-args', words
    for flag, value in zip(words, words[1:]):
        if flag == '-p':
            name, _, text = value.partition(':=')
            if not name.startswith('slave.state_topic'):
                check_parameter(name, parse_yaml(text))
            else:
                check_parameter(name, text)
        if flag == '-r':
            assert re.fullmatch(r'[\w/~]+:=[\w/~]+', value), f'bad remap rule {value}'


def check_command(line: str, cwd: Path, may_fail: bool = False) -> str | None:
    """Check one command line as the module docstring says; return the output of a run."""
    words = shlex.split(line, comments=True)
    if words[0].startswith('.venv/bin/'):
        words[0] = words[0].removeprefix('.venv/bin/')
    if words[0] == 'cam_ros':
        return check_cam_ros(words, cwd, may_fail)
    if words[0] == 'make':
        assert words[1] in makefile_targets(), f'make {words[1]}: no such target'
        makefile = (REPO / 'Makefile').read_text()
        for word in words[2:]:
            name, _, value = word.partition('=')
            assert re.search(rf'^{name} \?=', makefile, flags=re.M), f'{word}: no such variable'
            for path in (part for part in value.split() if '/' in part):
                assert (REPO / path).exists(), f'{word}: {path} does not exist'
        return None
    if words[0] == 'cam_node':
        check_cam_node(words)
        return None
    if words[0] == 'ros2':
        assert words[1] == 'run', words
        check_files(words)
        return None
    if words[0] == 'head':  # a file an earlier command of the block wrote
        return ''.join((cwd / words[-1]).read_text().splitlines(keepends=True)[:int(words[1][1:])])
    if words[0] == 'colcon':
        assert (REPO / 'colcon_defaults.yaml').exists()
        return None
    if words[0] == 'export':
        name, _, _ = words[1].partition('=')
        done = subprocess.run(['bash', '-ec', f'cd {shlex.quote(str(REPO))}; {line}; '
                               f'test -f "${name}"'], capture_output=True, text=True,
                              timeout=TIMEOUT_S)
        assert done.returncode == 0, f'{line}: {done.stderr}'
        return None
    raise AssertionError(f'no rule checks the command {line!r}: add one in {__file__}')


def check_sh(example: Example) -> None:
    """Check every command of an sh block."""
    cwd = workspace(example.namespace['tmp_path'])
    for line in command_lines(example.parsed):
        check_command(line, cwd)


def check_console(example: Example) -> None:
    """Run each `$ command` and check the excerpt of its output shown under it."""
    cwd = workspace(example.namespace['tmp_path'])
    blocks = re.split(r'^\$ ', example.parsed, flags=re.M)
    assert not blocks[0].strip(), 'a console block starts with a `$ ` command'
    for block in blocks[1:]:
        command, *shown = re.sub(r'\\\n\s*', ' ', block).splitlines()
        output = check_command(command, cwd, may_fail=any(FAILING.match(line) for line in shown))
        if output is None:
            assert not [line for line in shown if line.strip()], f'{command}: output not checked'
            continue
        check_excerpt(command, shown, output.splitlines())


def check_excerpt(command: str, shown: list[str], actual: list[str]) -> None:
    """Check that the shown lines appear in the actual output, in order."""
    position = 0
    for line in shown:
        if line.strip() in ('', '...'):
            continue
        try:
            position = actual.index(line.rstrip(), position) + 1
        except ValueError:
            raise AssertionError(f'{command}: the documented line\n  {line}\nis not in its '
                                 'output (in that order):\n' + '\n'.join(actual)) from None


def check_yaml(example: Example) -> None:
    """Read a whole parameters file with the project's reader; check a fragment's keys."""
    text = textwrap.dedent(example.parsed)
    if 'ros__parameters' in text:
        path = example.namespace['tmp_path'] / 'snippet.yaml'
        path.write_text(text)
        parse_parameters(read_parameters_file(path))
        return
    for name, value in flatten(parse_yaml(text, 'snippet')).items():
        check_parameter(name, value)


def check_python(example: Example) -> None:
    """Run a Python block from the repository root, or compile it when it needs a node."""
    code = compile(example.parsed, example_id(example), 'exec')
    before = example.document.text[:example.start].rstrip().splitlines()
    if before and before[-1].strip() == COMPILE_ONLY:
        return
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        exec(code, {'__name__': '__docs__'})
    finally:
        os.chdir(cwd)


def check_text(example: Example) -> None:
    """Plain text: nothing to run."""


EVALUATORS: dict[str, Callable[[Example], Any]] = {
    'sh': check_sh, 'console': check_console, 'yaml': check_yaml, 'python': check_python,
    'text': check_text,
}
