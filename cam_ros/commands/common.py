"""What the commands share: loading a design, verdict lines, JSON, tables, progress."""
from __future__ import annotations

import json
import math
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Sequence, TYPE_CHECKING

import numpy as np

from cam_ros.core.errors import InvalidParameter
from cam_ros.exit_codes import EXIT_FAILED, EXIT_OK

if TYPE_CHECKING:  # the ROS commands use these helpers without loading any design code
    from cam_ros.core import CamDesign

#: The dynamics arrays `sample` and `call` add for a design with dynamics: (name, field, unit).
DYNAMICS_FIELDS = (
    ('contact_force', 'contact_force', 'N'),
    ('camshaft_torque', 'camshaft_torque', 'Nm'),
    ('contact_stress', 'contact_stress', 'Pa'),
)


def positive_quantity(option: str, text: str, design: CamDesign, angular: bool = False) -> float:
    """Return a typed length option in m (an angle in rad when angular), > 0.

    A bare number is in the config's length_unit (deg when angular).
    """
    from cam_ros.core.config.quantity import typed_quantity

    value = typed_quantity(option, text, design.config.length_unit, angular=angular)
    if value <= 0.0:
        raise InvalidParameter(option, text, 'must be > 0')
    return value


def load_design(config: str | Path, axis: str | None = None) -> CamDesign:
    """Read, check and build the design of a config file, or of axis of a machine file.

    A machine file without axis is refused (the command takes one cam), as is an axis of a
    single-cam file; raises InvalidParameter.
    """
    from cam_ros.core import build_design, parse_parameters, read_parameters_file
    from cam_ros.core.machine import build_machine, is_machine, parse_machine

    values = read_parameters_file(config)
    if not is_machine(values):
        if axis is not None:
            raise InvalidParameter('--axis', axis, f'applies to machine files (with axes): '
                                                   f'{config} is one cam')
        return build_design(parse_parameters(values))
    if axis is None:
        raise InvalidParameter('axes', values['axes'], f'{config} is a machine file: this takes '
                               'one cam: give --axis NAME (or --timing-diagram for the whole '
                               'machine)')
    return build_machine(parse_machine(values)).axis(axis).design


def say(command: str, message: str) -> None:
    """Write one line 'cam_ros <command>: <message>' on stderr."""
    print(f'cam_ros {command}: {message}', file=sys.stderr, flush=True)


def verdict(command: str, design: CamDesign) -> int:
    """Return 0 if the design meets its limits, else print its warnings on stderr and return 1.

    The limits are the report's: geometry, and the follower's jump and contact stress.
    """
    if design.ok:
        return EXIT_OK
    for warning in design.warnings():
        say(command, f'warning: {warning}')
    return EXIT_FAILED


def progress(command: str, message: str) -> None:
    """Show what a long run is doing, on stderr, when stderr is a terminal."""
    if sys.stderr.isatty():
        sys.stderr.write(f'\rcam_ros {command}: {message}\x1b[K')
        sys.stderr.flush()


def end_progress() -> None:
    """Clear the progress line, if one was shown."""
    if sys.stderr.isatty():
        sys.stderr.write('\r\x1b[K')
        sys.stderr.flush()


def plain(value: Any) -> Any:
    """Return value as JSON-ready Python data: arrays as lists, non-finite floats as None."""
    if isinstance(value, np.ndarray):
        return [plain(item) for item in value.tolist()]
    if isinstance(value, dict):
        return {str(key): plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(item) for item in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


def dump_json(data: Any) -> str:
    """Return data as strict JSON (non-finite numbers become null), indented."""
    return json.dumps(plain(data), indent=2, allow_nan=False)


def _numeric(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def format_table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """Return rows of strings as columns: numbers right-aligned, text left-aligned."""
    columns = list(zip(headers, *rows))
    widths = [max(len(cell) for cell in column) for column in columns]
    right = [bool(rows) and all(_numeric(cell) for cell in column[1:]) for column in columns]

    def line(cells: Sequence[str]) -> str:
        return '  '.join(f'{cell:>{width}}' if align else f'{cell:<{width}}'
                         for cell, width, align in zip(cells, widths, right)).rstrip()

    return '\n'.join([line(headers), *(line(row) for row in rows)])


def csv_column(name: str, unit: str) -> str:
    """Return a CSV column name with its unit: velocity, m/s -> velocity_m_per_s."""
    return f'{name}_{unit}'.replace('/', '_per_').replace('^', '')


def degrees(angle: float) -> float:
    """Return an angle (rad) in degrees, rounded to 1e-9 deg so that 240 prints as 240.0."""
    return round(math.degrees(angle), 9)


def number(value: float, digits: int = 6) -> str:
    """Format a number with digits significant digits ('inf', '-inf', 'nan' as such)."""
    return f'{value:.{digits}g}'


def output_path(option: str, path: str | Path, suffixes: Sequence[str]) -> Path:
    """Return the output path if its suffix is one of suffixes, else raise InvalidParameter."""
    result = Path(path)
    if result.suffix.lower() not in suffixes:
        raise InvalidParameter(option, str(path), 'must end in ' + ', '.join(suffixes))
    return result


@contextmanager
def writing(command: str, message: str, target: Path) -> Iterator[None]:
    """Show progress while the -o target is written; an OSError names -o and the file."""
    progress(command, message)
    try:
        yield
    except OSError as err:
        raise InvalidParameter('-o', str(target),
                               f'cannot be written ({err.strerror or err})') from err
    finally:
        end_progress()
