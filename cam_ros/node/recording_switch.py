"""cam_node's recording: one switch (~/record and recording.enabled) over a Recorder.

Either side of the switch starts or stops the recording and the other follows, so
``recording.enabled`` says whether the node records. Every start and stop is logged with its
cause; a recording carries the parameters in force, the params file and the designs' summary.
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Mapping, NamedTuple, Sequence

from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher

from cam_ros.core import CamConfig, CamError
from cam_ros.node.master_follower import MasterFollower
from cam_ros.node.parameters import RECORDING_SWITCH
from cam_ros.recording import (CONFIG_ATTACHMENT, PARAMETER_EVENTS, PARAMETERS_ATTACHMENT,
                               params_file, Recorder, TopicSpec)
from cam_ros.recording.parameters import NODE_KEY


class Served(NamedTuple):
    """What a recording carries of what the node serves.

    config gives the recording.* settings; parameters are those in force; summary describes
    the designs.
    """

    config: CamConfig
    parameters: Mapping[str, Any]
    summary: str


class NodeRecording:
    """Record the node's topics to MCAP while the switch is on."""

    def __init__(self, node: Node, params_file: Path | None, publishers: Sequence[Publisher],
                 ecam: MasterFollower | None):
        """Record the publishers' topics, /parameter_events and the electronic cam's."""
        self._node, self._params_file = node, params_file
        self._topics = [TopicSpec(pub.topic_name, pub.msg_type, pub.qos_profile)
                        for pub in publishers] + [PARAMETER_EVENTS] + (
                            ecam.topics() if ecam else [])
        self.recorder: Recorder | None = None

    def start_up(self, served: Served) -> None:
        """Start recording if recording.enabled is true (once the node is built)."""
        if served.config.recording_enabled:
            self.switch(True, f'{RECORDING_SWITCH} true at start-up', served)

    @property
    def running(self) -> bool:
        """Return whether a recording runs (one stopped by a write error does not)."""
        return self.recorder is not None and not self.recorder.failed

    def switch(self, enabled: bool, why: str, served: Served) -> tuple[bool, str]:
        """Start or stop recording, logging why; then make recording.enabled say the outcome.

        The parameter and ~/record are one switch: `param get` tells whether the node records.
        """
        answer = self._start(why, served) if enabled else self.stop(why)
        if self._node.get_parameter(RECORDING_SWITCH).value != self.running:
            # after ~/record or a failed start; follow() then finds nothing to switch
            self._node.set_parameters([Parameter(RECORDING_SWITCH, Parameter.Type.BOOL,
                                                 self.running)])
        return answer

    def follow(self, updates: Sequence[Parameter], served: Served) -> None:
        """Start or stop recording as an accepted update sets recording.enabled."""
        for param in updates:
            if param.name == RECORDING_SWITCH and param.value != self.running:
                self.switch(param.value, f'{RECORDING_SWITCH} set to '
                                         f'{str(param.value).lower()}', served)

    def stop(self, why: str) -> tuple[bool, str]:
        """Close the recording (writing its summary); log why unless a write error ended it."""
        recorder, self.recorder = self.recorder, None
        if recorder is None:
            return True, 'not recording'
        failed = recorder.failed  # then the recorder has logged its own end
        recorder.close()
        stopped = f'{recorder.message_count} messages in {recorder.path}'
        if not failed:
            self._node.get_logger().info(f'recording stopped ({why}): {stopped}')
        return True, f'stopped; {stopped}'

    def _start(self, why: str, served: Served) -> tuple[bool, str]:
        """Start recording the node's topics to a new MCAP file; say what happened."""
        if self.running:
            return True, f'already recording to {self.recorder.path}'
        self.stop(why)  # release one that a write error stopped
        config, node = served.config, self._node
        stamp = time.strftime('%Y%m%d-%H%M%S')
        path = Path(config.recording_directory) / f'{node.get_name()}_{stamp}.mcap'
        name = node.get_fully_qualified_name()
        in_force = {**served.parameters, RECORDING_SWITCH: True}  # on while it records
        attachments = {PARAMETERS_ATTACHMENT: params_file(
            in_force, f'Parameters of {name} in force when recording {path.name} began')}
        if self._params_file and self._params_file.exists():
            attachments[CONFIG_ATTACHMENT] = self._params_file.read_text()
        description = {'params_file': str(self._params_file or ''), NODE_KEY: name,
                       'design': served.summary}
        try:
            self.recorder = Recorder(node, path, self._topics,
                                     compression=config.recording_compression,
                                     attachments=attachments, description=description)
        except CamError as err:
            node.get_logger().error(f'recording not started: {err}')
            return False, str(err)
        node.get_logger().info(f'recording to {path} ({why})')
        return True, f'recording to {path}'
