"""
Electronic cam on ROS 2: follow a master axis topic and command a ros2_control axis.

The CamNode creates a MasterFollower when master.source is topic, for the axes it serves (a
machine's, or the single cam's joint follower: one path for both). The axes follow the machine's
line shaft (cam_ros.core.ecam.line_shaft), stepped by the newest master message (sensor_msgs/
JointState; a backlog is skipped and counted) and, while the master is silent for
COAST_INTERVALS of its intervals (and COAST_SHARE of master.timeout) or the line shaft stops,
by a clock thread of its own. Each step publishes ~/commands for a forward_command_controller
(position or velocity of every axis joint, in the axes' order), ~/joint_states (the master joint
and every axis joint, stamps always increasing) and, with a trajectory horizon,
~/joint_trajectory for a joint_trajectory_controller (command_topics.py sends those);
/diagnostics about once a second. A master loss, a following error, ~/engage false and
deactivating are synchronized stops of the line shaft, never a stop in one message. One master
subscription, one speed estimate for all axes; every number comes from
cam_ros.core.ecam.
"""
from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.node import Node
from rclpy.publisher import Publisher
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt32
from std_srvs.srv import SetBool

from cam_ros.core import CamDesign
from cam_ros.core.ecam.axes import by_axis, Commands, SlaveAxes
from cam_ros.core.ecam.engagement import CheckMoves
from cam_ros.core.ecam.follow import Follower
from cam_ros.core.ecam.line_shaft import INACTIVE, LOST as HALTED_LOST
from cam_ros.core.ecam.following_error import CommandHistory
from cam_ros.core.ecam.master import CamMapping, ElectronicCam, MasterConfig
from cam_ros.core.ecam.master_tracker import (BadMaster, JUMP_FACTOR, LOST, MasterState,
                                              MasterTracker, OK, read_master)
from cam_ros.core.ecam.slave_limits import AxisUnit, SlaveLimits
from cam_ros.core.ecam.switches import SwitchTracks
from cam_ros.recording import Recorder, TopicSpec
from cam_ros.recording.parameter_replay import (CHANGED_AFTER_KEY, DESIGN_CHANGES_KEY,
                                                MASTER_TOPIC_KEY)
from cam_ros.node.ecam_designs import EcamDesigns
from cam_ros.node.ecam_diagnostics import engagement_status, master_status, recording_status
from cam_ros.node.ecam_log import EcamLog
from cam_ros.node.slave_feedback import SLAVE_QOS, SlaveFeedback, watches
from cam_ros.node.master_intake import master_intake, MASTER_QOS, refuse_rewiring, stamp_ns
from cam_ros.node.command_topics import COMMAND_QOS, CommandTopics
from cam_ros.node.shaft_clock import PERIOD_S as CLOCK_PERIOD_S, ShaftClock
from cam_ros.node.qos_events import LATCHED, publisher

DIAGNOSTICS_PERIOD_S = 1.0
#: The master silence after which the line shaft's clock steps it instead of the master's
#: messages: COAST_INTERVALS of the master's own intervals, at least COAST_SHARE of
#: master.timeout (a master's jitter is not silence).
COAST_INTERVALS, COAST_SHARE = 3, 0.1
#: Longest deactivate waits for the synchronized stop to come to rest.
STOP_WAIT_S = 10.0


class MasterFollower:
    """Turn master messages into every axis's commands along the line shaft; hand design
    changes over smoothly.

    axes: (joint name, design) per axis; their machine-wide parameters (master.*, switches.*,
    command.trajectory_*) are the first axis's. switches: the switches.* values, on the machine
    angle (the master position) when machine, else on the single cam's angle.
    """

    @classmethod
    def attach(cls, node: Node, axes: Sequence[tuple[str, CamDesign]],
               switches: Mapping[str, Any], machine: bool, joint_pub: Publisher,
               recorder: Callable[[], Recorder | None], check: Optional[CheckMoves] = None,
               active: bool = True) -> MasterFollower | None:
        """Return the component if master.source is topic, else None."""
        refuse_rewiring(node)
        if MasterConfig.from_config(axes[0][1].config).source != 'topic':
            return None
        return cls(node, axes, switches, machine, joint_pub, recorder, check, active)

    def __init__(self, node: Node, axes: Sequence[tuple[str, CamDesign]],
                 switches: Mapping[str, Any], machine: bool, joint_pub: Publisher,
                 recorder: Callable[[], Recorder | None], check: Optional[CheckMoves] = None,
                 active: bool = True):
        """Follow the master; inactive (a managed node's state) until activate() unless active.

        check: the machine's check of the moves onto the cams (interference pairs)."""
        self._node, self._recorder = node, recorder
        self._machine = machine
        self._designs = designs = EcamDesigns.of(node, axes, switches)
        self._config = designs.master
        values = designs.values
        # Moves onto the cams are planned here, off the master thread (SlaveAxes).
        self._planner = ThreadPoolExecutor(max_workers=1, thread_name_prefix='move planning')
        self._axes = SlaveAxes(
            designs.names,
            [Follower(cam, engage, values['master.engage_on_start'], limits, unit)
             for cam, engage, limits, unit in zip(designs.cams, designs.engage, designs.limits,
                                                  designs.units)],
            designs.interfaces, check, self._planner.submit)
        self._tracks = SwitchTracks(designs.switches)
        self._tracker = MasterTracker(int(self._config.timeout * 1e9), designs.speed_limit[0],
                                      int(values['master.velocity_window'] * 1e9),
                                      self._config.max_speed, self._config.nominal_speed)
        self._last_handover = 'none'
        # Design changes taken, and the stamp of the last master message before the latest one:
        # in ~/state, so a replay can make each recorded change at the same master message.
        self._changes = 0
        self._changed_after: int | None = None
        self._said: tuple[str, int | None, int] = ('', None, 0)  # status, switches, changes
        self._overspeed_said = False
        self._active = active  # a managed node's inactive state sends nothing once at rest
        self._faulted = ''  # the axis whose following error stopped the line shaft
        self._arrived_ns = 0  # when the newest master message arrived (node clock)
        self._interval_ns = 0  # the master's last stamp interval
        self._skipped = 0  # master messages skipped behind a newer one
        self._rested = True  # the line shaft's rest was sent (or nothing moved yet)
        self._topics = CommandTopics(node, self._axes, joint_pub, self._config)
        self._diagnostics_pub = publisher(node, DiagnosticArray, '/diagnostics', COMMAND_QOS)
        self._switches_pub = publisher(node, UInt32, '~/switches', LATCHED)
        self._state_pub = publisher(node, DiagnosticStatus, '~/state', LATCHED)
        self._lock = threading.Lock()  # master and clock threads vs executor (timers, updates)
        self._slave_topics = sorted({parameters['slave.state_topic']
                                     for parameters in designs.parameters} - {''})
        self._log = EcamLog(node, LATCHED, self._slave_topics, SLAVE_QOS)
        self._history = CommandHistory()
        self._feedback = SlaveFeedback(node, self._axes, self._slave_topics, self._history,
                                       watches(axes), self._lock, self._fault)
        node.create_service(SetBool, '~/engage', self._engage)
        self._intake = master_intake(node, self._config.topic, self._on_master)
        self._master_sub = self._intake.entity
        self._watch_timer = node.create_timer(self._config.timeout / 4.0, self._watch)
        node.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        self._clock = ShaftClock(node, self._lock, self._tick)
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
        """Take new designs: an offset change is a move onto the new cam (line shaft at rest),
        other changes at a common place or at once; the line shaft's limits are those of the
        new designs (computed before the lock; taken once the moves onto them begin)."""
        designs = EcamDesigns.of(self._node, axes, switches)
        config, values, table = designs.master, designs.values, designs.switches
        path = designs.path_limits()
        with self._lock:
            running = self._running()
        meanwhile = designs.path_limits(also=running)  # the old cams and the new
        self._watch_timer.timer_period_ns = int(config.timeout / 4.0 * 1e9)
        with self._lock:
            if self._running() != running:  # a handover applied since: rare
                running = self._running()
                meanwhile = designs.path_limits(also=running)
            before, self._designs, self._config = self._designs, designs, config
            self._topics.config = config
            tracker = self._tracker
            tracker.timeout_ns = int(config.timeout * 1e9)
            tracker.speed.window_ns = int(values['master.velocity_window'] * 1e9)
            tracker.bound, tracker.nominal = config.max_speed, config.nominal_speed
            tracker.max_speed = designs.speed_limit[0]
            self._feedback.watches = watches(axes)
            said = []
            for name, follower, cam, unit, engage, limits, old, new in zip(
                    designs.names, self._axes.followers, designs.cams, designs.units,
                    designs.engage, designs.limits, before.parameters, designs.parameters):
                if not self._machine and follower.cam.mapping != cam.mapping:
                    self._tracks = SwitchTracks(table)  # the cam angle of the switches moved
                follower.unit = unit
                # Said under the lock: the master thread cannot apply it (and say so) before.
                told = follower.change(cam, engage, limits)
                if new != old:
                    said.append((name, told))
            self._axes.retarget(path, designs.one_way, meanwhile,
                                designs.one_way or any(limits.direction for _, limits in running))
            self._axes.interfaces = designs.interfaces
            if not table.same(self._tracks.table):
                self._tracks = SwitchTracks(table)  # the next master sample says the states
            self._last_handover = '; '.join(
                told if len(self._axes) == 1 else f'{name}: {told}' for name, told in said
            ) or 'no axis changed'
            last = tracker.last
            self._changes += 1
            self._changed_after = None if last is None else last.stamp_ns
            self._node.get_logger().info(f'design change {self._last_handover}')
            self._publish_state()

    def _running(self) -> list[tuple[ElectronicCam, SlaveLimits]]:
        """Return each axis's cam and limits as it runs them (lock held)."""
        return [(follower.cam, follower.limits) for follower in self._axes.followers]

    def stop(self) -> None:
        """Stop taking master messages and the clock (before the node is destroyed)."""
        self._clock.end()
        self._planner.shutdown(wait=False, cancel_futures=True)
        self._intake.stop()

    def activate(self) -> None:
        """Send commands again: the line shaft catches up with the master."""
        with self._lock:
            self._active = True
            if self._axes.shaft.why == INACTIVE:
                self._axes.shaft.follow()
                self._rested = False
            self._publish_state()

    def deactivate(self) -> None:
        """Stop the line shaft on the cams and wait (up to STOP_WAIT_S) until it rests; then
        send nothing (master messages stay tracked)."""
        with self._lock:
            self._axes.shaft.halt(INACTIVE)
            self._active = False
            self._publish_state()
        deadline = time.monotonic() + STOP_WAIT_S
        while time.monotonic() < deadline:
            with self._lock:
                if self._rested or self._tracker.last is None:
                    return
            time.sleep(CLOCK_PERIOD_S)

    # Master messages, the clock, slave state, ~/engage -------------------------------------
    def _on_master(self, message: JointState, arrived_ns: int, skipped: int) -> None:
        with self._lock:
            self._skipped += skipped
            try:
                self._follow(message, arrived_ns)
            except Exception as err:  # a bug must cost one message, not the master thread
                if self._node.context.ok():  # at shutdown the publishers go first: no bug
                    self._node.get_logger().error(f'master message not followed: {err!r}',
                                                  throttle_duration_sec=5.0)

    def _follow(self, message: JointState, arrived_ns: int) -> None:
        tracker, before = self._tracker, self._tracker.status
        arrived_ns = arrived_ns or self._node.get_clock().now().nanoseconds
        try:
            position, velocity = read_master(self._config.joint, message.name, message.position,
                                             message.velocity, message.effort)
            last = tracker.last
            state = tracker.accept(stamp_ns(message.header.stamp), position, velocity,
                                   arrived_ns)
        except BadMaster as bad:
            tracker.drop(bad.reason)
            self._node.get_logger().warning(
                f'dropped a master message: {bad.reason} ({tracker.dropped[bad.reason]} so far)',
                throttle_duration_sec=5.0)
            return
        self._arrived_ns = arrived_ns
        if last is not None:
            self._interval_ns = state.stamp_ns - last.stamp_ns
        if not self._sending():  # tracked (the speed estimate stays warm), nothing commanded
            return
        if state.origin:
            self._node.get_logger().warning(
                f'new master origin: the master moved {tracker.jump:.6g} rad in '
                f'{tracker.jump_time:.6g} s, more than {JUMP_FACTOR:g} x '
                f'{tracker.plausible_speed():.6g} rad/s allows ({tracker.jumps} so far): the '
                f'line shaft takes its position modulo a machine cycle')
        shaft = self._axes.shaft
        if before == LOST and shaft.why == HALTED_LOST and not self._faulted:
            shaft.follow()
            self._rested = False
            self._node.get_logger().info('master back: the line shaft catches up with it')
        handovers = [follower.handover for follower in self._axes.followers]
        self._send(state.stamp_ns, state.position, state.omega, self._axes.command(state))
        self._say_events()
        for name, handover, follower, unit in zip(self._axes.names, handovers,
                                                  self._axes.followers, self._designs.units):
            if handover is not None and follower.handover is None:
                self._said_applied(name, handover.old, handover.new, state, unit)
        self._publish_state()
        if before != OK:
            self._node.get_logger().info(f'master {before} -> ok')
        if tracker.overspeed and not self._overspeed_said:
            self._node.get_logger().warning(
                f'master speed {state.omega:.6g} rad/s over {self._designs.speed_limit[1]} '
                f'({self._designs.speed_limit[0]:.6g} rad/s)')
        self._overspeed_said = tracker.overspeed

    def _sending(self) -> bool:
        """Say whether commands go out: active, or the line shaft has not come to rest yet."""
        return self._active or not self._rested

    def _send(self, stamp: int, master: float, speed: float,
              commands: Optional[Commands]) -> None:
        """Send the commands of a line shaft step (none before every axis has one); note the
        line shaft's rest."""
        if commands is None:
            return
        self._topics.sample(stamp, master, speed, commands)
        self._history.add(self._topics.stamp_ns, commands.position, commands.velocity)
        virtual = self._axes.virtual  # the switches are on the line shaft, as the axes
        assert virtual is not None
        mapping = CamMapping() if self._machine else self._axes.followers[0].cam.mapping
        for word in self._tracks.update(float(mapping.turns(virtual.track)),
                                        virtual.omega / mapping.master_scaling):
            self._switches_pub.publish(UInt32(data=word))
            self._log.switched(self._topics.stamp_ns, master, word)
        self._rested = self._axes.resting
        if self._rested:
            self._history.stop()

    def _tick(self) -> None:
        """Step the line shaft on the clock once the master has been silent for
        COAST_INTERVALS of its intervals, unless it rests (and said so) already."""
        last, shaft = self._tracker.last, self._axes.shaft
        if last is None or self._rested or not self._sending():
            return
        silent = self._node.get_clock().now().nanoseconds - self._arrived_ns
        coast = max(COAST_INTERVALS * self._interval_ns, self._tracker.timeout_ns * COAST_SHARE)
        if silent < coast:
            return
        stamp = last.stamp_ns + silent  # the master's clock, carried on
        self._send(stamp, last.position, 0.0, self._axes.tick(stamp, last.position))
        if not shaft.following:
            self._publish_state()

    def _say_events(self) -> None:
        """Log what the followers noted: moves, refusals, stops."""
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
        """Stop the line shaft on the cams: the machine stops as one (lock held). Said once
        until ~/engage clears it."""
        if self._faulted:
            return
        self._faulted = axis
        unit = self._designs.units[self._axes.names.index(axis)]
        self._axes.shaft.halt(f'following error of {axis}')
        self._node.get_logger().error(
            f'following error of {axis}: {unit.say(error)} over slave.following_error_limit '
            f'{unit.say(limit)} at stamp {stamp} ns: the line shaft stops every axis on its '
            f'cam (~/engage true clears once the error is within the limit)')
        self._publish_state()

    def _engage(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        with self._lock:
            over = self._feedback.over_limit(self._designs.units) if request.data else ''
            if over:
                response.success = False
                response.message = f'not engaged: {over}'
            else:
                rejoin = [self._faulted] if request.data and self._faulted else []
                if rejoin:
                    self._node.get_logger().info(
                        f'following error of {self._faulted} cleared: every axis within '
                        f'slave.following_error_limit')
                    self._faulted = ''
                response.success, response.message = self._axes.engage(request.data, rejoin)
                self._rested = self._rested and not request.data
            self._say_events()
            self._publish_state()
            last = self._tracker.last
            self._log.engaged(request, response, None if last is None else last.stamp_ns)
        self._node.get_logger().info(f'~/engage {request.data}: {response.message}')
        return response

    def _watch(self) -> None:
        with self._lock:
            self._stop_when_lost()

    def _stop_when_lost(self) -> None:
        """Notice master silence: the line shaft stops every axis on its cam."""
        status = self._tracker.check(self._node.get_clock().now().nanoseconds)
        if status != LOST or not self._sending():
            return
        self._axes.shaft.halt(HALTED_LOST)
        self._tracks.reset()
        self._node.get_logger().warning(
            f'master silent for {self._config.timeout:g} s: the line shaft stops '
            f'{"the follower" if len(self._axes) == 1 else ", ".join(self._axes.names)} on '
            f'{"its cam" if len(self._axes) == 1 else "their cams"}')
        self._publish_state()

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
            array.status = [*self._designs.statuses, self._master_status(),
                            self._engagement_status(),
                            recording_status(self._node, self._recorder())]
        self._diagnostics_pub.publish(array)

    def _engagement_status(self) -> DiagnosticStatus:
        return engagement_status(
            self._node, self._axes, self._tracks, bool(self._faulted),
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
        return master_status(self._node, self._tracker, self._designs.speed_limit,
                             self._axes.shaft, topic=self._master_sub.topic_name,
                             skipped=self._skipped,
                             design_change=by_axis([name for name, _ in pending],
                                                   [said for _, said in pending]) or 'none',
                             last_design_change=self._last_handover)
