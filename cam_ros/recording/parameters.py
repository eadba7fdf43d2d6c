"""What a recording says about its node's parameters: those in force at its start, and changes.

The recorder attaches the parameters in force as a ROS 2 params file (PARAMETERS_ATTACHMENT) next
to the file the node was started with (CONFIG_ATTACHMENT); every later change is a message on
/parameter_events, which parameter_changes() turns into (time, node, name, old, new) rows.
"""

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from rclpy.parameter import parameter_value_to_python
import yaml

from cam_ros.core.config.parameters import SPECS
from cam_ros.core.config.params_file import flatten
from cam_ros.recording.reader import Recording

#: The params file the node was started with, verbatim.
CONFIG_ATTACHMENT = 'cam_config.yaml'
#: The parameters in force when the recording started, as a params file that reproduces them.
PARAMETERS_ATTACHMENT = 'cam_parameters.yaml'
#: Description key (metadata record 'cam_ros') naming the node whose parameters are attached.
NODE_KEY = 'node'
PARAMETER_EVENTS_TOPIC = '/parameter_events'


class _ParamsDumper(yaml.SafeDumper):
    """Safe YAML dumper writing mappings as blocks and lists in flow style ([1.0, 2.0])."""


_ParamsDumper.add_representer(list, lambda dumper, value: dumper.represent_sequence(
    'tag:yaml.org,2002:seq', value, flow_style=True))


def params_file(values: Mapping[str, Any], comment: str = '') -> str:
    """
    Return flat parameter values as a ROS 2 params file (`/**: ros__parameters:`, nested keys).

    Empty lists are left out: a params file cannot declare their type, and empty is the default.
    Floats keep their shortest exact text, so the file reproduces the values bit for bit.
    """
    tree: dict[str, Any] = {}
    for name, value in values.items():
        if isinstance(value, (list, tuple)):
            if not value:
                continue
            value = list(value)
        *parents, leaf = name.split('.')
        branch = tree
        for parent in parents:
            branch = branch.setdefault(parent, {})
        branch[leaf] = value
    text = yaml.dump({'/**': {'ros__parameters': tree}}, Dumper=_ParamsDumper, sort_keys=False,
                     width=99)
    header = ''.join(f'# {line}\n' for line in comment.splitlines())
    return header + text


@dataclass(frozen=True)
class ParameterChange:
    """One parameter of an event: kind 'changed', 'new' or 'deleted'; old None if unknown."""

    time_ns: int
    node: str
    name: str
    kind: str
    old: Any
    new: Any

    def text(self) -> str:
        """Return the change as 'name: old -> new', 'name = new (new)' or 'name (deleted)'."""
        if self.kind == 'deleted':
            return f'{self.name} (deleted)'
        if self.kind == 'new':
            return f'{self.name} = {self.new!r} (new)'
        old = '?' if self.old is None else repr(self.old)
        return f'{self.name}: {old} -> {self.new!r}'


def initial_parameters(recording: Recording) -> dict[str, dict[str, Any]]:
    """Return {node: flat values} of the parameters attached as in force at the start."""
    node = recording.metadata.get('cam_ros', {}).get(NODE_KEY)
    text = recording.attachments.get(PARAMETERS_ATTACHMENT)
    if not node or text is None:
        return {}
    try:
        document = yaml.safe_load(text)
        tree = document['/**']['ros__parameters']
    except (yaml.YAMLError, KeyError, TypeError):
        return {}
    return {node: flatten(tree)} if isinstance(tree, Mapping) else {}


def parameter_changes(recording: Recording) -> list[ParameterChange]:
    """
    Return every parameter event recorded, one row per parameter, in recording order.

    Old values come from the attached parameters in force and from earlier events; a change
    whose old value equals the new one (e.g. the unchanged rest of a reload) is left out. A cam
    node's recording lists cam nodes only: the recorded node and any that sets cam parameters,
    not the helper nodes of the CLI (whose only parameters are ROS's own, such as use_sim_time).
    """
    if PARAMETER_EVENTS_TOPIC not in recording.topics:
        return []
    known = initial_parameters(recording)
    changes = []
    for recorded in recording.messages([PARAMETER_EVENTS_TOPIC]):
        event = recorded.message
        values = known.setdefault(event.node, {})
        for kind, parameters in (('new', event.new_parameters),
                                 ('changed', event.changed_parameters),
                                 ('deleted', event.deleted_parameters)):
            for parameter in parameters:
                new = None if kind == 'deleted' else parameter_value_to_python(parameter.value)
                old = values.get(parameter.name)
                if kind == 'changed' and parameter.name in values and old == new:
                    continue
                values[parameter.name] = new
                changes.append(ParameterChange(recorded.log_time_ns, event.node, parameter.name,
                                               kind, old, new))
    recorded_node = recording.metadata.get('cam_ros', {}).get(NODE_KEY)
    if not recorded_node:
        return changes
    cam_nodes = {recorded_node} | {change.node for change in changes if change.name in SPECS}
    return [change for change in changes if change.node in cam_nodes]
