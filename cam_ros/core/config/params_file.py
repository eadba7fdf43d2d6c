"""Read ROS 2 parameters files safely: plain nested mappings, lists and scalars, nothing more.

A parameters file needs nothing of YAML beyond mappings, lists and scalars, so whatever makes a
careless or hostile file silently wrong or expensive is refused while it is read, before a
single value is built:

- anchors and aliases (``&a``, ``*a``): refused at the first anchor, so an alias bomb is never
  expanded;
- a key given twice in one mapping (YAML would keep the last one and hide the first): the error
  names the key and both lines;
- more than MAX_FILE_BYTES bytes, a list of more than MAX_ARRAY_LENGTH entries, a value of more
  than MAX_STRING_LENGTH characters, nesting deeper than MAX_DEPTH, more than MAX_VALUES values.

Scalars are typed as ROS's parameter parser types them (YAML 1.1, and ``1e3`` is a float).
libyaml's parser is used when PyYAML has it; the document is composed here, node by node, so
that every check runs as soon as its node is read. Every error is one InvalidParameter naming the
parameter (or ``config`` and the file) and the rule.
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Iterable, Mapping

import yaml
from yaml.composer import Composer
from yaml.constructor import SafeConstructor
from yaml.events import AliasEvent
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.reader import ReaderError
from yaml.resolver import Resolver

from ..errors import InvalidParameter

#: Node names whose section of a parameters file the cam node reads, merged in file order.
NODE_NAMES = ('cam', '/cam', '/**')
#: Largest parameters file read (bytes); a real one holds a few kB.
MAX_FILE_BYTES = 1 << 20
#: Most entries of one array parameter, in a file or in a parameter update.
MAX_ARRAY_LENGTH = 1000
#: Most characters of one value, in a file or in a parameter update.
MAX_STRING_LENGTH = 4096
#: Deepest nesting of mappings and lists (a parameters file needs 5 or 6 levels).
MAX_DEPTH = 16
#: Most values (keys, entries, scalars) in one file.
MAX_VALUES = 20000
ROS_FLOAT = re.compile(r'^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$')

try:  # libyaml's event parser when PyYAML was built with it (15x faster), else PyYAML's own
    from yaml import CParser as _EventParser
except ImportError:  # pragma: no cover - PyYAML without libyaml
    from yaml.parser import Parser
    from yaml.reader import Reader
    from yaml.scanner import Scanner

    class _EventParser(Reader, Scanner, Parser):  # type: ignore[no-redef]
        """PyYAML's pure-Python event parser."""

        def __init__(self, stream: str):
            Reader.__init__(self, stream)
            Scanner.__init__(self)
            Parser.__init__(self)


class _Loader(Composer, _EventParser, SafeConstructor, Resolver):
    """Compose a document from parser events, refusing what a parameters file must not hold."""

    def __init__(self, text: str, parameter: str, value: object):
        _EventParser.__init__(self, text)
        SafeConstructor.__init__(self)
        Resolver.__init__(self)
        Composer.__init__(self)
        self.what = (parameter, value)  # names the whole input in errors not about one key
        self.keys: list[str] = []  # keys from the document root to the node being composed
        self.lines: dict[int, dict[tuple[str, str], int]] = {}  # mapping -> key -> line
        self.depth = 0
        self.values = 0

    def refuse(self, rule: str) -> InvalidParameter:
        """Return an error about the whole input."""
        return InvalidParameter(*self.what, rule)

    def dotted_name(self) -> str:
        """Return the dotted parameter name of the node being composed."""
        keys = self.keys[2:] if self.keys[1:2] == ['ros__parameters'] else self.keys
        return '.'.join(keys) or self.what[0]

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        """Compose one node after checking anchors, depth and sizes; check keys and length."""
        event = self.peek_event()
        line = event.start_mark.line + 1
        if isinstance(event, AliasEvent) or getattr(event, 'anchor', None) is not None:
            sign = '*' if isinstance(event, AliasEvent) else '&'
            raise self.refuse(f'uses the YAML anchor or alias {sign}{event.anchor} at line '
                              f'{line}: parameters files may not use anchors or aliases')
        self.values += 1
        if self.values > MAX_VALUES:
            raise self.refuse(f'holds more than {MAX_VALUES} values (line {line})')
        if self.depth >= MAX_DEPTH:
            raise self.refuse(f'nests deeper than {MAX_DEPTH} levels at line {line}')
        if isinstance(parent, SequenceNode) and index >= MAX_ARRAY_LENGTH:
            raise InvalidParameter(self.dotted_name(),
                                   _Unread(self.construct_all(parent.value[:3])),
                                   f'must have at most {MAX_ARRAY_LENGTH} entries')
        key = index if isinstance(parent, MappingNode) and isinstance(index, ScalarNode) else None
        if key is not None:
            self.keys.append(key.value)
        self.depth += 1
        node = self._checked(super().compose_node(parent, index))
        self.depth -= 1
        if key is not None:
            lines, line = self.lines.setdefault(id(parent), {}), key.start_mark.line + 1
            if (key.tag, key.value) in lines:
                raise InvalidParameter(
                    self.dotted_name(), self.construct_all([node])[0],
                    f'is given twice, at lines {lines[key.tag, key.value]} and {line}: give '
                    'each key once')
            lines[key.tag, key.value] = line
            self.keys.pop()
        return node

    def _checked(self, node: Node) -> Node:
        """Return node unless it is a scalar longer than MAX_STRING_LENGTH."""
        if isinstance(node, ScalarNode) and len(node.value) > MAX_STRING_LENGTH:
            raise InvalidParameter(self.dotted_name(), node.value,
                                   f'must have at most {MAX_STRING_LENGTH} characters')
        return node

    def construct_all(self, nodes: Iterable[Node]) -> list[Any]:
        """Build the values of composed nodes (to quote them in an error)."""
        return [self.construct_object(node, deep=True) for node in nodes]


_Loader.add_implicit_resolver('tag:yaml.org,2002:float', ROS_FLOAT, list('-+0123456789.'))


class _Unread:
    """The first entries of a list too long to read in full; quoted with a trailing '...'."""

    def __init__(self, first: list[Any]):
        self.first = first

    def __repr__(self) -> str:
        return '[' + ', '.join(map(repr, self.first)) + ', ...]'


def parse_yaml(text: str, parameter: str = 'config', value: object = '<text>') -> Any:
    """Parse one YAML document under the rules above; errors name parameter and value."""
    loader = None
    try:
        loader = _Loader(text, parameter, value)  # the reader refuses control characters here
        return loader.get_single_data()
    except ReaderError as err:
        line = text.count('\n', 0, err.position) + 1
        column = err.position - (text.rfind('\n', 0, err.position) + 1) + 1
        raise InvalidParameter(parameter, value, f'is not text (a binary file?): the control '
                               f'character U+{err.character:04X} at line {line}, column '
                               f'{column} may not be in YAML') from err
    except yaml.YAMLError as err:
        mark = getattr(err, 'problem_mark', None)
        where = f' at line {mark.line + 1}, column {mark.column + 1}' if mark else ''
        problem = '; '.join(filter(None, (getattr(err, 'context', None),
                                          getattr(err, 'problem', None)))) or 'syntax error'
        raise InvalidParameter(parameter, value, f'is not valid YAML{where}: {problem}') from err
    finally:
        if loader is not None:
            loader.dispose()


def read_yaml(path: str | Path) -> Any:
    """Read and parse a YAML file of at most MAX_FILE_BYTES bytes of UTF-8."""
    try:
        with open(path, 'rb') as stream:
            data = stream.read(MAX_FILE_BYTES + 1)
    except OSError as err:
        raise InvalidParameter('config', str(path), f'cannot be read ({err.strerror})') from err
    if len(data) > MAX_FILE_BYTES:
        raise InvalidParameter('config', str(path), f'is larger than {MAX_FILE_BYTES} bytes, '
                               'the most a parameters file may hold')
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as err:
        raise InvalidParameter('config', str(path),
                               f'is not UTF-8 text (byte {err.start})') from err
    return parse_yaml(text, 'config', str(path))


def flatten(tree: Mapping[str, Any], prefix: str = '') -> dict[str, Any]:
    """Flatten nested YAML mappings into dotted ROS parameter names."""
    flat: dict[str, Any] = {}
    for key, value in tree.items():
        name = f'{prefix}{key}'
        if isinstance(value, Mapping):
            flat.update(flatten(value, f'{name}.'))
        else:
            flat[name] = value
    return flat


def read_parameters_file(path: str | Path,
                         node_names: tuple[str, ...] = NODE_NAMES) -> dict[str, Any]:
    """Read a ROS 2 parameters file and return its cam node's flat parameters.

    Every section named in node_names with a ``ros__parameters`` mapping counts, in file order
    (later values win), as rcl merges ``/**`` and the node's own section.
    """
    document = read_yaml(path)
    if not isinstance(document, Mapping):
        raise InvalidParameter('config', str(path),
                               'must be a mapping with a node name at the top')
    sections = [section['ros__parameters'] for key, section in document.items()
                if key in node_names and isinstance(section, Mapping)
                and isinstance(section.get('ros__parameters'), Mapping)]
    if not sections:
        raise InvalidParameter('config', str(path), f'needs one of {", ".join(node_names)} '
                               'with ros__parameters under it')
    flat: dict[str, Any] = {}
    for section in sections:
        flat.update(flatten(section))
    return flat
