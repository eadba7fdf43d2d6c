"""
Electronic cam on ROS 2: follow a master axis topic and command a ros2_control axis.

The CamNode creates a MasterFollower when master.source is topic, for the axes it serves (a
machine's, or the single cam's joint follower: one path for both). For every accepted master
message (sensor_msgs/JointState) it publishes ~/commands for a forward_command_controller
(position or velocity of every axis joint, in the axes' order), ~/joint_states with the master's
stamp (the master joint and every axis joint) and, with a trajectory horizon, ~/joint_trajectory
for a joint_trajectory_controller (command_topics.py sends those); /diagnostics about once a
second. One master subscription, one speed estimate for all axes; every number comes from
cam_ros.core.ecam.
"""
from __future__ import annotations

import threading
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.node import Node
from rclpy.publisher import Publisher
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt32
from std_srvs.srv import SetBool

from cam_ros.core import CamDesign
from cam_ros.core.ecam.axes import by_axis, SlaveAxes
from cam_ros.core.ecam.follow import EngageConfig, Follower, STOPPING
from cam_ros.core.ecam.following_error import CommandHistory
from cam_ros.core.ecam.master import CamMapping, ElectronicCam, MasterConfig
from cam_ros.core.ecam.master_tracker import (BadMaster, JUMP_FACTOR, LOST, MasterState,
                                              MasterTracker, OK, read_master)
from cam_ros.core.ecam.slave_limits import AxisUnit, SlaveLimits
from cam_ros.core.ecam.switches import switch_table, SwitchTracks
from cam_ros.recording import Recorder, TopicSpec
from cam_ros.recording.parameter_replay import (CHANGED_AFTER_KEY, DESIGN_CHANGES_KEY,
                                                MASTER_TOPIC_KEY)
from cam_ros.node.ecam_diagnostics import (design_statuses, engagement_status, jump_speed,
                                           master_status, recording_status)
from cam_ros.node.ecam_log import EcamLog
from cam_ros.node.slave_feedback import SLAVE_QOS, SlaveFeedback, watches
from cam_ros.node.master_intake import master_intake, MASTER_QOS, refuse_rewiring, stamp_ns
from cam_ros.node.command_topics import COMMAND_QOS, CommandTopics
from cam_ros.node.qos_events import LATCHED, publisher

DIAGNOSTICS_PERIOD_S = 1.0


class MasterFollower:
    """Turn master messages into every axis's commands; hand design changes over smoothly.

    axes: (joint name, design) per axis; their machine-wide parameters (master.*, switches.*,
    command.trajectory_*) are the first axis's. switches: the switches.* values, on the machine
    angle (the master position) when machine, else on the single cam's angle.
    """

    @classmethod
    def attach(cls, node: Node, axes: Sequence[tuple[str, CamDesign]],
               switches: Mapping[str, Any], machine: bool, joint_pub: Publisher,
               recorder: Callable[[], Recorder | None],
               active: bool = True) -> MasterFollower | None:
        """Return the component if master.source is topic, else None."""
        refuse_rewiring(node)
        if MasterConfig.from_config(axes[0][1].config).source != 'topic':
            return None
        return cls(node, axes, switches, machine, joint_pub, recorder, active)

    def __init__(self, node: Node, axes: Sequence[tuple[str, CamDesign]],
                 switches: Mapping[str, Any], machine: bool, joint_pub: Publisher,
                 recorder: Callable[[], Recorder | None], active: bool = True):
        """Follow the master; inactive (a managed node's state) until activate() unless active."""
        self._node, self._recorder = node, recorder
        self._machine = machine
        first = axes[0][1].config
        values = first.parameters
        self._config = MasterConfig.from_config(first)
        self._units = [AxisUnit.of(design.config) for _, design in axes]
        self._axes = SlaveAxes(
            [name for name, _ in axes],
            [Follower(design.electronic_cam,
                      EngageConfig.from_parameters(design.config.parameters),
                      values['master.engage_on_start'], SlaveLimits.from_config(design.config),
                      unit) for (_, design), unit in zip(axes, self._units)],
            _interfaces(axes))
        self._design_statuses = design_statuses(node, axes)
        self._tracks = SwitchTracks(switch_table(switches))
        self._speed_limit = _speed_limit(axes)
        self._tracker = MasterTracker(int(self._config.timeout * 1e9), self._speed_limit[0],
                                      int(values['master.velocity_window'] * 1e9),
                                      self._config.max_speed, _nominal_speed(axes))
        self._last_handover = 'none'
        # Design changes taken, and the stamp of the last master message before the latest one:
        # in ~/state, so a replay can make each recorded change at the same master message.
        self._changes = 0
        self._changed_after: int | None = None
        self._said: tuple[str, int | None, int] = ('', None, 0)  # status, switches, changes
        self._overspeed_said = False
        self._active = active  # a managed node's inactive state sends nothing
        self._topics = CommandTopics(node, self._axes, joint_pub, self._config)
        self._diagnostics_pub = publisher(node, DiagnosticArray, '/diagnostics', COMMAND_QOS)
        self._switches_pub = publisher(node, UInt32, '~/switches', LATCHED)
        self._state_pub = publisher(node, DiagnosticStatus, '~/state', LATCHED)
        self._lock = threading.Lock()  # master thread vs executor (timers, updates)
        self._slave_topics = sorted({design.config.parameters['slave.state_topic']
                                     for _, design in axes} - {''})
        self._log = EcamLog(node, LATCHED, self._slave_topics, SLAVE_QOS)
        self._history = CommandHistory()
        self._feedback = SlaveFeedback(node, self._axes, self._slave_topics, self._history,
                                       watches(axes), self._lock, self._fault)
        node.create_service(SetBool, '~/engage', self._engage)
        self._intake = master_intake(node, self._config.topic, self._on_master)
        self._master_sub = self._intake.entity
        self._watch_timer = node.create_timer(self._config.timeout / 4.0, self._watch)
        node.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        self._publish_state()
        interfaces = ', '.join(f'{name} {interface}' for name, interface in
                               zip(self._axes.names, self._axes.interfaces))
        node.get_logger().info(
            f'electronic cam: following {self._master_sub.topic_name} (joint '
            f'{self._config.joint}), commands on {self._topics.commands.topic_name} '
            f'({interfaces})')

    def topics(self) -> list[TopicSpec]:
        """Return the master input and the command topics, for the recorder."""
        return [TopicSpec(self._master_sub.topic_name, JointState, MASTER_QOS)] + [
            TopicSpec(pub.topic_name, pub.msg_type, pub.qos_profile)
            for pub in (self._topics.commands, self._topics.trajectory, self._diagnostics_pub,
                        self._switches_pub, self._state_pub, self._feedback.publisher)
        ] + self._log.topics()

    def change(self, axes: Sequence[tuple[str, CamDesign]],
               switches: Mapping[str, Any]) -> None:
        """Take new designs: offsets blended, other changes at a common place or at once."""
        first = axes[0][1].config
        config, values = MasterConfig.from_config(first), first.parameters
        statuses = design_statuses(self._node, axes)
        limit, table = _speed_limit(axes), switch_table(switches)
        self._watch_timer.timer_period_ns = int(config.timeout / 4.0 * 1e9)
        with self._lock:
            self._design_statuses, self._config = statuses, config
            self._topics.config = config
            tracker = self._tracker
            tracker.timeout_ns = int(config.timeout * 1e9)
            tracker.speed.window_ns = int(values['master.velocity_window'] * 1e9)
            tracker.bound, tracker.nominal = config.max_speed, _nominal_speed(axes)
            self._speed_limit, tracker.max_speed = limit, limit[0]
            self._units = [AxisUnit.of(design.config) for _, design in axes]
            self._feedback.watches = watches(axes)
            said = []
            for (name, design), follower, unit in zip(axes, self._axes.followers, self._units):
                cam = design.electronic_cam
                if not self._machine and follower.cam.mapping != cam.mapping:
                    self._tracks = SwitchTracks(table)  # the cam angle of the switches moved
                follower.unit = unit
                # Said under the lock: the master thread cannot apply it (and say so) before.
                said.append(follower.change(
                    cam, EngageConfig.from_parameters(design.config.parameters),
                    SlaveLimits.from_config(design.config)))
            self._axes.interfaces = _interfaces(axes)
            if not table.same(self._tracks.table):
                self._tracks = SwitchTracks(table)  # the next master sample says the states
            self._last_handover = by_axis(self._axes.names, said)
            last = tracker.last
            self._changes += 1
            self._changed_after = None if last is None else last.stamp_ns
            self._node.get_logger().info(f'design change {self._last_handover}')
            self._publish_state()

    def stop(self) -> None:
        """Stop taking master messages (before the node is destroyed)."""
        self._intake.stop()

    def activate(self) -> None:
        """Send commands again: every axis engages in its mode from where it is held."""
        with self._lock:
            self._active = True
            self._publish_state()

    def deactivate(self) -> None:
        """Send one hold command for every axis, then nothing (master messages stay tracked)."""
        with self._lock:
            self._axes.lose('inactive')
            self._hold()
            self._active = False
            self._publish_state()

    # Master messages, slave state, ~/engage ----------------------------------------------
    def _on_master(self, message: JointState) -> None:
        with self._lock:
            try:
                self._follow(message)
            except Exception as err:  # a bug must cost one message, not the master thread
                self._node.get_logger().error(f'master message not followed: {err!r}',
                                              throttle_duration_sec=5.0)

    def _follow(self, message: JointState) -> None:
        tracker, before = self._tracker, self._tracker.status
        try:
            position, velocity = read_master(self._config.joint, message.name, message.position,
                                             message.velocity, message.effort)
            state = tracker.accept(stamp_ns(message.header.stamp), position, velocity,
                                   self._node.get_clock().now().nanoseconds)
        except BadMaster as bad:
            tracker.drop(bad.reason)
            self._node.get_logger().warning(
                f'dropped a master message: {bad.reason} ({tracker.dropped[bad.reason]} so far)',
                throttle_duration_sec=5.0)
            return
        if not self._active:  # tracked (the speed estimate stays warm), nothing commanded
            return
        if state.origin:
            self._node.get_logger().warning(
                f'new master origin: the master moved {tracker.jump:.6g} rad in '
                f'{tracker.jump_time:.6g} s, more than {JUMP_FACTOR:g} x '
                f'{tracker.plausible_speed():.6g} rad/s allows ({tracker.jumps} so far): the '
                f'slaves hold and engage again from where they are')
        handovers = [follower.handover for follower in self._axes.followers]
        commands = self._axes.command(state)
        if commands is not None:
            self._topics.sample(message.header, state, commands)
            self._history.add(state.stamp_ns, commands.position, commands.velocity)
        self._say_events()
        for name, handover, follower, unit in zip(self._axes.names, handovers,
                                                  self._axes.followers, self._units):
            if handover is not None and follower.handover is None:
                self._said_applied(name, handover.old, handover.new, state, unit)
        mapping = CamMapping() if self._machine else self._axes.followers[0].cam.mapping
        for word in self._tracks.update(float(mapping.turns(state.track)),
                                        state.omega / mapping.master_scaling):
            self._switches_pub.publish(UInt32(data=word))
            self._log.switched(message.header.stamp, state.position, word)
        self._publish_state()
        if before != OK:
            self._node.get_logger().info(f'master {before} -> ok')
        if tracker.overspeed and not self._overspeed_said:
            self._node.get_logger().warning(
                f'master speed {state.omega:.6g} rad/s over {self._speed_limit[1]} '
                f'({self._speed_limit[0]:.6g} rad/s)')
        self._overspeed_said = tracker.overspeed

    def _say_events(self) -> None:
        """Log what the followers noted: blends over the cam's peaks, refusals, stops."""
        logger = self._node.get_logger()
        for event in self._axes.events():  # one call site per severity, as rclpy requires
            if 'stopping:' in event:
                logger.warning(event)
            else:
                logger.info(event)

    def _said_applied(self, name: str, old: ElectronicCam, new: ElectronicCam,
                      state: MasterState, unit: AxisUnit) -> None:
        """Say where a pending design took over and how far the position command moved."""
        step = float(new.setpoints(state.track).position - old.setpoints(state.track).position)
        angle = np.degrees(float(new.mapping.cam_angle(state.track)))
        applied = f'at cam angle {angle:.3f} deg, position command moved {unit.say(step)}'
        self._last_handover = applied if len(self._axes) == 1 else f'{name}: {applied}'
        self._node.get_logger().info(f'design change applied {self._last_handover}')

    def _fault(self, axis: str, error: float, limit: float, stamp: int) -> None:
        """Hold every axis at its last command: the machine stops as one (lock held)."""
        unit = self._units[self._axes.names.index(axis)]
        self._axes.fault('following error')
        self._hold()
        self._node.get_logger().error(
            f'following error of {axis}: {unit.say(error)} over slave.following_error_limit '
            f'{unit.say(limit)} at stamp {stamp} ns: every axis holds (~/engage true clears)')
        self._publish_state()

    def _engage(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        with self._lock:
            response.success, response.message = self._axes.engage(request.data)
            if not request.data and not any(follower.phase == STOPPING
                                            for follower in self._axes.followers):
                self._hold()
            self._say_events()
            self._publish_state()
            last = self._tracker.last
            self._log.engaged(request, response, None if last is None else last.stamp_ns)
        self._node.get_logger().info(f'~/engage {request.data}: {response.message}')
        return response

    def _watch(self) -> None:
        with self._lock:
            self._hold_when_lost()

    def _hold_when_lost(self) -> None:
        """Notice master silence: hold every axis once the master is lost."""
        status = self._tracker.check(self._node.get_clock().now().nanoseconds)
        if status != LOST or not self._active:
            return
        self._axes.lose()
        self._tracks.reset()
        held = ', '.join('nothing' if position is None else unit.say(position)
                         for position, unit in zip(self._axes.held, self._units))
        self._node.get_logger().warning(
            f'master silent for {self._config.timeout:g} s: holding '
            f'{"the follower" if len(self._axes) == 1 else ", ".join(self._axes.names)} at '
            f'{held}')
        self._hold()
        self._publish_state()

    def _hold(self) -> None:
        """Command the held positions at rest (nothing unless every axis was commanded)."""
        values = self._axes.hold_values()
        if values is None:
            return
        last, held = self._tracker.last, self._axes.held
        self._topics.hold(values, [float(position) for position in held],  # type: ignore[arg-type]
                          last.position if last else 0.0, self._node.get_clock().now().to_msg())
        self._history.stop()  # the hold keeps the last command's positions

    def _publish_state(self) -> None:
        """Publish ~/state when the slaves' status, the switch word or the design changed."""
        now = (self._axes.status, self._tracks.word, self._changes)
        if now != self._said:
            self._said = now
            self._state_pub.publish(self._engagement_status())

    # Diagnostics ----------------------------------------------------------------------------
    def _publish_diagnostics(self) -> None:
        array = DiagnosticArray()
        array.header.stamp = self._node.get_clock().now().to_msg()
        with self._lock:
            array.status = [*self._design_statuses, self._master_status(),
                            self._engagement_status(),
                            recording_status(self._node, self._recorder())]
        self._diagnostics_pub.publish(array)

    def _engagement_status(self) -> DiagnosticStatus:
        return engagement_status(
            self._node, self._axes, self._tracks,
            **{MASTER_TOPIC_KEY: self._master_sub.topic_name, DESIGN_CHANGES_KEY: self._changes,
               CHANGED_AFTER_KEY: ('none' if self._changed_after is None
                                   else self._changed_after)},
            slave_state_topic=', '.join(self._slave_topics) or 'none',
            slave_states_dropped=self._feedback.dropped,
            slave_states_unmatched=self._feedback.unmatched)

    def _master_status(self) -> DiagnosticStatus:
        pending = [(name, follower.handover.describe())
                   for name, follower in zip(self._axes.names, self._axes.followers)
                   if follower.handover is not None]
        return master_status(self._node, self._tracker, self._speed_limit,
                             topic=self._master_sub.topic_name,
                             design_change=by_axis([name for name, _ in pending],
                                                   [said for _, said in pending]) or 'none',
                             last_design_change=self._last_handover)


def _interfaces(axes: Sequence[tuple[str, CamDesign]]) -> list[str]:
    """Return each axis's command.interface ('position' or 'velocity')."""
    return [design.config.parameters['command.interface'] for _, design in axes]


def _speed_limit(axes: Sequence[tuple[str, CamDesign]]) -> tuple[float, str]:
    """Return the master speed to warn above and what sets it, over every axis."""
    return min(MasterConfig.from_config(design.config).speed_limit(jump_speed(design))
               for _, design in axes)


def _nominal_speed(axes: Sequence[tuple[str, CamDesign]]) -> float:
    """Return the master speed at cam_speed (the same for every axis of a machine)."""
    return MasterConfig.from_config(axes[0][1].config).nominal_speed
