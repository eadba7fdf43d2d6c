"""Print any ROS message readably (YAML-like) or as flat numeric CSV columns.

A tiny replacement for rosidl_runtime_py (not available from PyPI): it walks a message through
get_fields_and_field_types(), so it works for every generated message class.
"""
from __future__ import annotations

import array
import json
import math
import re
from typing import Any, Iterator

import numpy as np

SEQUENCES = (list, tuple, array.array, np.ndarray)
#: Strings printed without quotes (others as JSON strings, which YAML reads as well).
PLAIN_STRING = re.compile(r'[A-Za-z_/][\w./,()-]*(?: [\w./,()-]+)*')
YAML_WORDS = frozenset({'true', 'false', 'yes', 'no', 'on', 'off', 'null', 'y', 'n'})


def _is_message(value: Any) -> bool:
    return hasattr(type(value), 'get_fields_and_field_types')


def _is_sequence(value: Any) -> bool:
    """Return True for an array or sequence field (a single octet's bytes is a scalar)."""
    if isinstance(value, bytes):
        return len(value) != 1
    return isinstance(value, SEQUENCES)


def _scalar(value: Any) -> Any:
    """Return a field value as a plain Python scalar (bytes of an octet become an int)."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, bytes) and len(value) == 1:
        return value[0]
    return value


def _scalar_text(value: Any) -> str:
    """Return a scalar as YAML text: strings plain when YAML reads them back unchanged."""
    value = _scalar(value)
    if isinstance(value, str):
        plain = PLAIN_STRING.fullmatch(value) and value.lower() not in YAML_WORDS
        return value if plain else json.dumps(value)
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float):
        return _float_text(value)
    return repr(value)


def _float_text(value: float) -> str:
    """Return the shortest exact text of a float that YAML 1.1 readers also take as a float."""
    if math.isnan(value):
        return '.nan'
    if math.isinf(value):
        return '.inf' if value > 0 else '-.inf'
    text = repr(value)
    mantissa, e, exponent = text.partition('e')
    return f'{mantissa}.0e{exponent}' if e and '.' not in mantissa else text


def _items(value: Any) -> list[Any]:
    """Return the elements of a sequence field (bytes as ints)."""
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    return value.tolist() if isinstance(value, (array.array, np.ndarray)) else list(value)


def message_lines(message: Any, indent: str = '') -> list[str]:
    """Return a message as YAML-like lines, nested fields indented by two spaces."""
    lines = []
    for name in type(message).get_fields_and_field_types():
        value = getattr(message, name)
        if _is_message(value):
            lines.append(f'{indent}{name}:')
            lines += message_lines(value, indent + '  ')
        elif _is_sequence(value):
            items = _items(value)
            if not items:
                lines.append(f'{indent}{name}: []')
                continue
            lines.append(f'{indent}{name}:')
            for item in items:
                if _is_message(item):
                    nested = message_lines(item, '')
                    lines.append(f'{indent}- {nested[0]}' if nested else f'{indent}- {{}}')
                    lines += [f'{indent}  {line}' for line in nested[1:]]
                else:
                    lines.append(f'{indent}- {_scalar_text(item)}')
        else:
            lines.append(f'{indent}{name}: {_scalar_text(value)}')
    return lines


def message_text(message: Any) -> str:
    """Return a message as YAML-like text (no trailing newline)."""
    return '\n'.join(message_lines(message))


def numeric_fields(message: Any, prefix: str = '') -> Iterator[tuple[str, float | int]]:
    """Yield (dotted name, number) for every numeric or boolean field, arrays as name[i]."""
    for name in type(message).get_fields_and_field_types():
        yield from _numeric(getattr(message, name), f'{prefix}{name}')


def _numeric(value: Any, name: str) -> Iterator[tuple[str, float | int]]:
    if _is_message(value):
        yield from numeric_fields(value, f'{name}.')
    elif _is_sequence(value):
        for index, item in enumerate(_items(value)):
            yield from _numeric(item, f'{name}[{index}]')
    else:
        value = _scalar(value)
        if isinstance(value, bool):
            yield name, int(value)
        elif isinstance(value, (int, float)):
            yield name, value
