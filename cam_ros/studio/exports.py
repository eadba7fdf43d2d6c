"""The report and the downloads of the edited design, made by the CLI's own commands.

The report is `cam_ros report`'s output for the design built from the page's values
(commands.design.report_output, commands.machine.report_output). Every other download runs
the `cam_ros plot` or `cam_ros export` command itself on the edited file written, under the
design's own name, into a temporary folder inside the design's folder (removed at once), so
each download holds the bytes the CLI writes for the saved file.
"""
from __future__ import annotations

import contextlib
import io
import re
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from cam_ros.commands import design as design_commands
from cam_ros.commands import machine as machine_commands
from cam_ros.core import InvalidParameter
from cam_ros.core.machine import is_machine
from cam_ros.core.machine.served import machine_from_values
from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS
from cam_ros.studio.document import DesignDocument

#: The CLI's commands print their result line; one command at a time holds stdout.
_OUTPUT_LOCK = threading.Lock()
#: Options a download may pass on to the command (the CLI's own names, without the --).
OPTIONS = ('file_format', 'points', 'tolerance', 'cutter_radius', 'compensation', 'arcs',
           'interpolation', 'derivatives', 'end_point', 'samples', 'angle_deg')


#: Each download's command and the flag that selects it.
KINDS: dict[str, tuple[Callable[..., int], str | None]] = {
    'plot': (design_commands.plot, None),
    'timing-plot': (design_commands.plot, 'timing_diagram'),
    'surface': (design_commands.export, None),
    'cam-table': (design_commands.export, 'cam_table'),
    'machining': (design_commands.export, 'machining'),
    'switches': (design_commands.export, 'switches'),
    'timing': (design_commands.export, 'timing_diagram'),
}
#: The file ending of a download without a format.
DEFAULT_FORMATS = {'plot': 'png', 'timing-plot': 'png', 'surface': 'dxf', 'machining': 'gcode'}


@dataclass(frozen=True)
class Download:
    """A file the CLI wrote: its name, its bytes and the line the command printed."""

    name: str
    data: bytes
    message: str


def report(document: DesignDocument, values: Mapping[str, Any], json_output: bool) -> str:
    """Return `cam_ros report`'s output (text or JSON) for the page's values."""
    if is_machine(values):
        return machine_commands.report_output(machine_from_values(values), document.label,
                                              json_output)[0]
    design = machine_from_values(values).axes[0].design
    return design_commands.report_output(design, document.label, json_output)[0]


def _suffix(kind: str, file_format: str | None) -> str:
    """Return the file ending the CLI writes for a download (it checks the format itself)."""
    if file_format is not None and not re.fullmatch(r'[a-z0-9-]+', file_format):
        raise InvalidParameter('--format', file_format, 'must be a format\'s name')
    if kind == 'cam-table':
        table = TABLE_FORMATS.get(file_format or 'csv')
        return '.txt' if table is None else table.suffix
    return '.' + (file_format or DEFAULT_FORMATS.get(kind, 'csv'))


def _command(kind: str, options: dict[str, Any]) -> Callable[..., int]:
    """Return the CLI command of a download, with its flag set in options."""
    if kind not in KINDS:
        raise InvalidParameter('kind', kind, 'must be one of ' + ', '.join(KINDS))
    command, flag = KINDS[kind]
    if flag:
        options[flag] = True
    if kind in ('plot', 'timing-plot', 'surface'):
        options.pop('file_format', None)  # their format is the file's ending
    return command


def download(document: DesignDocument, values: Mapping[str, Any], kind: str,
             options: Mapping[str, Any], axis: str | None = None) -> Download:
    """Run the CLI command of a download on the edited design and return what it wrote."""
    unknown = set(options) - set(OPTIONS)
    if unknown:
        raise InvalidParameter('options', sorted(unknown), 'are not options of a download')
    given = {key: value for key, value in options.items() if value is not None}
    suffix = _suffix(kind, given.get('file_format'))
    command = _command(kind, given)
    if axis is not None:
        if not re.fullmatch(r'\w+', axis):
            raise InvalidParameter('--axis', axis, 'must be an axis name')
        given['axis'] = axis
    name = document.path.stem + ('' if axis is None else f'-{axis}') + suffix
    with tempfile.TemporaryDirectory(prefix='.cam_ros_studio-', dir=document.folder) as folder:
        config = Path(folder) / document.path.name
        config.write_text(document.text(values), encoding='utf-8')
        target = Path(folder) / name
        printed = io.StringIO()
        try:
            with _OUTPUT_LOCK, contextlib.redirect_stdout(printed), \
                    contextlib.redirect_stderr(io.StringIO()):
                command(str(config), str(target), **given)
        except InvalidParameter as err:  # named as the user knows it, not the scratch copy
            raise InvalidParameter(err.parameter, _named(err.value, folder, document),
                                   _named(err.rule, folder, document)) from err
        if target.is_dir():  # a machine's cam tables: the CLI wrote one per axis
            raise InvalidParameter('--axis', None, 'is needed: a machine\'s cam tables are '
                                                   'one per axis')
        data = target.read_bytes()
    message = printed.getvalue().strip().replace(str(target), name)
    return Download(name, data, message)


def _named(value: Any, folder: str, document: DesignDocument) -> Any:
    """Return an error's value or rule with the scratch folder's paths as the design's."""
    return value.replace(f'{folder}/', f'{document.folder}/') if isinstance(value, str) \
        else value
