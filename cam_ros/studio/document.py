"""The design file as the studio edits it: its flat values and a YAML round trip for saving.

The values are the core's own reading of the file (read_parameters_file: the same safe reader
and the same flat parameter names as the CLI). The page edits them as the texts a user types
in a YAML file, typed by the core's YAML rules, so that a value is refused exactly as the same
text in the file would be. Saving writes the edited values into a round-trip YAML tree
(ruamel.yaml), so the file keeps its comments, key order and the spelling of every value not
edited, and is read back to check that it holds the values the page shows.
"""
from __future__ import annotations

import io
import math
import threading
from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap, CommentedSeq

from cam_ros.core import InvalidParameter, read_parameters_file
from cam_ros.core.config.params_file import NODE_NAMES, parse_yaml
from cam_ros.studio.axes import insert_section, plain_copy, remove_section

#: A value as the page shows it: the text of a scalar, or a list of them.
Text = Any
#: Scalar texts whose values are kept (a YAML scalar is immutable): a few large machines' worth.
TYPED_KEPT = 8192


def scalar_text(value: Any) -> str:
    """Return the YAML text of a scalar as a user would type it (4.0, .nan, true, cycloidal)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float):
        if math.isnan(value):
            return '.nan'
        if math.isinf(value):
            return '.inf' if value > 0 else '-.inf'
        return repr(value)
    return str(value)


def value_text(value: Any) -> Text:
    """Return a flat value as the page shows it (lists entry by entry)."""
    return [scalar_text(item) for item in value] if isinstance(value, list) else scalar_text(value)


def typed_value(key: str, text: Text) -> Any:
    """Return the value of a typed text under the core's YAML rules (a file's typing)."""
    if isinstance(text, list):
        return [typed_value(f'{key}[{index}]', item) for index, item in enumerate(text)]
    if not isinstance(text, str):
        raise InvalidParameter(key, text, 'must be typed as text')
    return _typed_scalar(key, text)


@lru_cache(maxsize=TYPED_KEPT)
def _typed_scalar(key: str, text: str) -> Any:
    """Return a scalar text's value, kept: the page sends every text with each edit."""
    value = parse_yaml(text, key, text) if text.strip() else ''
    if isinstance(value, (Mapping, list)) or value is None:
        raise InvalidParameter(key, text, 'must be one value (a number, a word, true or false)')
    return value


def typed_values(texts: Mapping[str, Text]) -> dict[str, Any]:
    """Return the flat values of the page's texts."""
    return {key: typed_value(key, text) for key, text in texts.items()}


def same(a: Any, b: Any) -> bool:
    """Say whether two flat values are equal, nan equal to nan and 4 not equal to 4.0."""
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return type(a) is type(b) and a == b


class DesignDocument:
    """One design file: its folder, its text's round-trip tree, and its flat values."""

    def __init__(self, path: str | Path, read_only: bool = False):
        self.label = str(path)  # as the user named it: `cam_ros report` prints it so
        self.path = Path(path).resolve()
        self.read_only = read_only
        self.lock = threading.RLock()  # one request at a time changes the tree
        self.yaml = YAML()  # the round-trip loader and dumper: comments and order survive
        self.yaml.width = 4096  # never fold a long flow list
        self.values = read_parameters_file(self.path)  # refuses what the CLI refuses
        self.tree = self.yaml.load(self.path.read_text(encoding='utf-8'))
        self.copies: dict[str, str] = {}  # an added axis: the axis it was made a copy of

    @property
    def folder(self) -> Path:
        """Return the folder of the design: the only place the studio reads or writes."""
        return self.path.parent

    def text(self, values: Mapping[str, Any]) -> str:
        """Return the file's text holding values: the tree with every changed value set."""
        with self.lock:
            return self._text(values)

    def _text(self, values: Mapping[str, Any]) -> str:
        self._axis_sections(values)
        for key in self.values.keys() - values.keys():
            self._remove(key)
        for key, value in values.items():
            if key not in self.values or not same(self.values[key], value):
                self._set(key, value)
        self.values = dict(values)
        stream = io.StringIO()
        self.yaml.dump(self.tree, stream)
        return stream.getvalue()

    def save(self, values: Mapping[str, Any]) -> None:
        """Write values into the file, then check that the file reads back as exactly them."""
        if self.read_only:
            raise InvalidParameter('FILE', str(self.path), 'is the shipped default design, '
                                   'shown read-only: start `cam_ros studio FILE` to save')
        with self.lock:
            self.path.write_text(self._text(values), encoding='utf-8')
            self.values = read_parameters_file(self.path)
        lost = [key for key in values.keys() | self.values.keys()
                if not same(values.get(key), self.values.get(key))]
        if lost:
            raise InvalidParameter(lost[0], values.get(lost[0]), f'was saved to {self.path} '
                                   f'but reads back as {self.values.get(lost[0])!r}')

    def _axis_sections(self, values: Mapping[str, Any]) -> None:
        """Remove the section of each axis values drop; add each new axis's as a copy of its
        source's (axes.py), its values then set as any other."""
        old, new = self.values.get('axes'), values.get('axes')
        if not isinstance(old, list) or not isinstance(new, list):
            return
        for name in old:
            found = self._find(name) if name not in new else None
            if found is not None and isinstance(found[0][found[1]], Mapping):
                remove_section(*found)
        for name in new:
            source = self._find(self.copies.get(name, '')) if name not in old else None
            if source is None or self._find(name) is not None:
                continue
            section, key = source
            placed = [axis for axis in old if axis in section and axis in new]
            insert_section(section, name, plain_copy(section[key]), placed[-1] if placed
                           else key)
            for flat in [f'{name}.{own[len(key) + 1:]}' for own in self.values
                         if own.startswith(f'{key}.')]:
                if flat not in values:  # a key of the source the new axis lacks
                    self._remove(flat)

    def _sections(self) -> list[CommentedMap]:
        """Return the parameter sections the core reads, in file order."""
        return [section['ros__parameters'] for key, section in self.tree.items()
                if key in NODE_NAMES and isinstance(section, Mapping)
                and isinstance(section.get('ros__parameters'), Mapping)]

    def _find(self, key: str) -> tuple[CommentedMap, str] | None:
        """Return the mapping and its key holding a flat parameter (the last section's wins)."""
        for section in reversed(self._sections()):
            found = _locate(section, key)
            if found is not None:
                return found
        return None

    def _set(self, key: str, value: Any) -> None:
        found = self._find(key)
        if found is None:
            mapping, parts = self._sections()[-1], key.split('.')
            for part in parts[:-1]:
                if not isinstance(mapping.get(part), Mapping):
                    mapping[part] = CommentedMap()
                mapping = mapping[part]
            mapping[parts[-1]] = _node(value)
            return
        mapping, name = found
        old = mapping[name]
        if isinstance(value, list) and isinstance(old, CommentedSeq):
            del old[len(value):]
            for index, item in enumerate(value):
                if index >= len(old):
                    old.append(item)
                elif not same(old[index], item):
                    old[index] = item
        else:
            mapping[name] = _node(value)

    def _remove(self, key: str) -> None:
        """Remove a flat parameter; a mapping it leaves empty goes too."""
        while (found := self._find(key)) is not None:
            mapping, name = found
            del mapping[name]
            outer = key[:-len(name) - 1]
            holder = self._find(outer) if not mapping and outer else None
            if holder is not None and holder[0][holder[1]] is mapping:
                self._remove(outer)


def _node(value: Any) -> Any:
    """Return a value for the tree: a list as a flow sequence, as parameters files write them."""
    if not isinstance(value, list):
        return value
    sequence = CommentedSeq(value)
    sequence.fa.set_flow_style()
    return sequence


def _locate(mapping: Mapping[str, Any], key: str) -> tuple[Any, str] | None:
    """Return (mapping, name) holding the dotted key under mapping, nested or dotted."""
    for name, value in mapping.items():
        if name == key:
            return mapping, name
        if key.startswith(f'{name}.') and isinstance(value, Mapping):
            found = _locate(value, key[len(name) + 1:])
            if found is not None:
                return found
    return None
