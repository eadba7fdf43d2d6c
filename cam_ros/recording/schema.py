"""Message types as rosbag2 stores them: names, full .msg definitions and type hashes."""

import importlib
import json
from pathlib import Path
import re
import sys

from ament_index_python.packages import get_package_share_directory

from cam_ros.core.errors import RecordingError

#: Line that separates the definitions of a ros2msg schema (80 '=' characters).
SEPARATOR = '=' * 80

# The same field-type pattern and primitive set rosbag2's LocalMessageDefinitionSource uses, so
# that the dependency list (and thus the schema text) is the one `ros2 bag record` writes.
# 'wstring' is added: rosbag2 would look for a 'pkg/wstring' message and fall back to IDL.
_FIELD_TYPE = re.compile(r'(?:^|\n)\s*([a-zA-Z0-9_/]+)(?:\[[^\]]*\])?\s+')
_PRIMITIVES = frozenset({
    'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16',
    'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring'})


def type_name(msg_type: type) -> str:
    """Return the ROS name 'pkg/msg/Type' of a generated message class."""
    package, interface = msg_type.__module__.split('.')[:2]
    return f'{package}/{interface}/{msg_type.__name__}'


def import_type(name: str) -> type:
    """Return the generated message class named 'pkg/msg/Type'."""
    try:
        package, interface, short = name.split('/')
        return getattr(importlib.import_module(f'{package}.{interface}'), short)
    except (ValueError, ImportError, AttributeError) as exc:
        raise RecordingError(f'message type {name!r} is not installed: {exc}') from exc


def share_directory(package: str) -> Path:
    """Return the share directory of an installed package (ament index, else sys.prefix/share)."""
    try:
        return Path(get_package_share_directory(package))
    except (LookupError, OSError, ValueError):
        fallback = Path(sys.prefix, 'share', package)
    if not fallback.is_dir():
        raise RecordingError(f'package {package!r} has no share directory (ament index or '
                             f'{fallback.parent})')
    return fallback


def _interface_file(name: str, suffix: str) -> Path:
    """Return the installed definition file ('.msg' or '.json') of 'pkg/msg/Type' or 'pkg/Type'."""
    parts = name.split('/')
    package, interface, short = (parts[0], 'msg', parts[1]) if len(parts) == 2 else parts
    return share_directory(package) / interface / f'{short}{suffix}'


def _read_text(path: Path) -> str:
    """Return a file's text, as a RecordingError when it cannot be read."""
    try:
        return path.read_text(encoding='utf-8')
    except OSError as exc:
        raise RecordingError(f'cannot read message definition {path}: {exc.strerror}') from exc


def _dependencies(text: str, package: str) -> list[str]:
    """Return the sorted non-primitive field types of a .msg text, as 'pkg/Type'."""
    found = set()
    for field_type in _FIELD_TYPE.findall(text):
        if field_type not in _PRIMITIVES:
            found.add(field_type if '/' in field_type else f'{package}/{field_type}')
    return sorted(found)


def message_definition(name: str) -> str:
    """
    Return the ros2msg schema text of 'pkg/msg/Type', as rosbag2 writes it.

    The type's .msg text verbatim, then every dependency once, depth-first in sorted order, each
    preceded by an empty line, a line of 80 '=' and a line 'MSG: pkg/Type'.
    """
    seen: set[str] = set()

    def expand(type_id: str) -> str:
        text = _read_text(_interface_file(type_id, '.msg'))
        result = text
        for dependency in _dependencies(text, type_id.split('/')[0]):
            if dependency not in seen:
                seen.add(dependency)
                result += f'\n{SEPARATOR}\nMSG: {dependency}\n' + expand(dependency)
        return result

    return expand(name)


def type_hash(name: str) -> str:
    """Return the 'RIHS01_<hex>' type hash of 'pkg/msg/Type' from its installed .json file."""
    path = _interface_file(name, '.json')
    try:
        hashes = json.loads(_read_text(path))['type_hashes']
        return next(entry['hash_string'] for entry in hashes if entry['type_name'] == name)
    except (ValueError, KeyError, TypeError, StopIteration) as exc:
        raise RecordingError(f'{path} holds no type hash for {name}') from exc
