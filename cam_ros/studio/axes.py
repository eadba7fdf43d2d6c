"""Adding and removing a machine's axis: in its flat values, and in its file's round-trip tree.

A new axis is a copy of an existing one, appended to `axes`; removing an axis drops it from
`axes`, its keys and every interference pair naming it (an index of every parallel
interference array; no pair left: no interference key). The machine's core (parse_machine,
through machine_from_values) judges the result as it judges any edit: an axis name is checked
there, never here.

In the file, a new axis's section is a copy of its source's section without the source's
comments (they describe the source), written after the machine's last axis section; a removed
axis's section goes with the comment lines above it (its heading), and the comment lines after
it stay where they were (they head the next key).
"""
from __future__ import annotations

from typing import Any, Mapping

from ruamel.yaml.comments import CommentedMap, CommentedSeq

from cam_ros.core import InvalidParameter
from cam_ros.core.machine import is_machine
from cam_ros.core.machine.config import axis_index
from cam_ros.core.machine.parameters import INTERFERENCE


def _axes(values: Mapping[str, Any]) -> list[str]:
    """Return the machine's axes; a single cam has none to add to or remove."""
    if not is_machine(values):
        raise InvalidParameter('axes', None, 'a single cam has no axes to add or remove: '
                               'a machine file names them in axes')
    return list(values['axes'])


def with_axis(values: Mapping[str, Any], name: str, source: str) -> dict[str, Any]:
    """Return values with axis name appended to axes, its keys those of axis source."""
    axes = _axes(values)
    axis_index(tuple(axes), source)
    added = {} if name in axes else {  # a name given twice: the core says so, nothing copied
        f'{name}.{key[len(source) + 1:]}': list(value) if isinstance(value, list) else value
        for key, value in values.items() if key.startswith(f'{source}.')}
    return {**values, 'axes': [*axes, name], **added}


def without_axis(values: Mapping[str, Any], name: str) -> dict[str, Any]:
    """Return values without axis name: not in axes, no key of its own, no pair naming it."""
    axes = _axes(values)
    axis_index(tuple(axes), name)
    pairs = zip(values.get('interference.axis_a', []), values.get('interference.axis_b', []))
    kept = [index for index, pair in enumerate(pairs) if name not in pair]
    result: dict[str, Any] = {}
    for key, value in values.items():
        if key == 'axes':
            result[key] = [axis for axis in axes if axis != name]
        elif key in INTERFERENCE and isinstance(value, list):
            if kept:
                result[key] = [value[index] for index in kept if index < len(value)]
        elif not key.startswith(f'{name}.'):
            result[key] = value
    return result


def plain_copy(node: Any) -> Any:
    """Return a copy of a YAML node without its comments (a flow list stays a flow list)."""
    if isinstance(node, CommentedMap):
        copied = CommentedMap()
        for key, value in node.items():
            copied[key] = plain_copy(value)
        return copied
    if isinstance(node, CommentedSeq):
        sequence = CommentedSeq(plain_copy(item) for item in node)
        if node.fa.flow_style():
            sequence.fa.set_flow_style()
        return sequence
    return node  # a scalar: immutable, its spelling kept


def _last_leaf(node: Any) -> tuple[CommentedMap, Any] | None:
    """Return (mapping, key) of the last key written in a block mapping, nested or not."""
    if not isinstance(node, CommentedMap) or not node:
        return None
    key = list(node)[-1]
    return _last_leaf(node[key]) or (node, key)


def _tail(node: Any) -> Any:
    """Return and detach the comment lines written after a node (ruamel keeps them on the
    node's last key when the next key's heading follows a flow list or a scalar)."""
    leaf = _last_leaf(node)
    if leaf is None or leaf[1] not in leaf[0].ca.items:
        return None
    slots = leaf[0].ca.items[leaf[1]]
    tail, slots[2] = slots[2], None
    return tail


def _own_line(token: Any) -> Any:
    """Return a tail's comment on its node's own line (None: none), without the lines after."""
    if token is None or token.value.startswith('\n'):
        return None
    token.value = token.value.split('\n', 1)[0] + '\n'
    return token


def _set_tail(node: Any, tail: Any) -> None:
    leaf = _last_leaf(node)
    if leaf is not None and tail is not None:
        leaf[0].ca.items.setdefault(leaf[1], [None, None, None, None])[2] = tail


def remove_section(section: CommentedMap, name: str) -> None:
    """Remove an axis's section: with its heading, keeping the lines that head the next key."""
    keys = list(section)
    index = keys.index(name)
    tail = _tail(section[name])
    if index:
        before = section[keys[index - 1]]
        heading = _tail(before)  # this axis's heading, when ruamel put it there
        own = _own_line(heading)
        if own is not None and tail is not None:
            own.value += tail.value.lstrip('\n')
        _set_tail(before, own or tail)
    del section[name]
    section.ca.items.pop(name, None)


def insert_section(section: CommentedMap, name: str, node: CommentedMap,
                   after: str) -> None:
    """Insert an axis's section after the section after (which keeps its comments)."""
    tail = _tail(section[after])
    section.insert(list(section).index(after) + 1, name, node)
    _set_tail(node, tail)
