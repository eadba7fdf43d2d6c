"""
Electronic cam on ROS 2: follow a master axis topic and command a ros2_control axis.

The CamNode creates a MasterFollower when master.source is topic. For every accepted master
message (sensor_msgs/JointState) it publishes ~/commands for a forward_command_controller
(position or velocity of the follower joint), ~/joint_states with the master's stamp and, with a
trajectory horizon, ~/joint_trajectory for a joint_trajectory_controller; /diagnostics about
once a second. Every number comes from cam_ros.core.ecam.master and cam_ros.core.ecam.handover.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray, UInt32
from std_srvs.srv import SetBool
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.core import CamDesign
from cam_ros.core.ecam.follow import EngageConfig, Follower, STOPPING
from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.core.ecam.master_tracker import (BadMaster, JUMP_FACTOR, LOST, MasterState,
                                              MasterTracker, OK, read_master)
from cam_ros.core.ecam.slave_limits import AxisUnit, SlaveLimits
from cam_ros.core.ecam.switches import switch_table, SwitchTracks
from cam_ros.recording import Recorder, TopicSpec
from cam_ros.recording.parameter_replay import (CHANGED_AFTER_KEY, DESIGN_CHANGES_KEY,
                                                MASTER_TOPIC_KEY)
from cam_ros.node.ecam_diagnostics import (design_status, engagement_status, master_status,
                                           recording_status)
from cam_ros.node.ecam_log import EcamLog
from cam_ros.node.joints import FOLLOWER_JOINT, JOINT_NAMES
from cam_ros.node.master_intake import master_intake, MASTER_QOS, refuse_rewiring, stamp_ns
from cam_ros.node.qos_events import publisher

COMMAND_QOS = QoSProfile(depth=10)
#: ~/switches and ~/state: a late subscriber gets the present state at once.
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
#: The slave's state: best effort matches the broadcaster whatever its reliability.
SLAVE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
DIAGNOSTICS_PERIOD_S = 1.0


class MasterFollower:
    """Turn master messages into follower commands; hand design changes over smoothly."""

    @classmethod
    def attach(cls, node: Node, design: CamDesign, joint_pub: Publisher,
               recorder: Callable[[], Recorder | None]) -> MasterFollower | None:
        """Return the component if the design's master.source is topic, else None."""
        refuse_rewiring(node)
        if MasterConfig.from_config(design.config).source != 'topic':
            return None
        return cls(node, design, joint_pub, recorder)

    def __init__(self, node: Node, design: CamDesign, joint_pub: Publisher,
                 recorder: Callable[[], Recorder | None]):
        self._node, self._joint_pub, self._recorder = node, joint_pub, recorder
        jump = jump_speed(design)
        self._design_status = design_status(node, design, jump)
        self._config = MasterConfig.from_config(design.config)
        values = design.config.parameters
        self._unit = AxisUnit.of(design.config)
        self._follower = Follower(ElectronicCam(design.program, self._config.mapping),
                                  EngageConfig.from_parameters(values),
                                  values['master.engage_on_start'],
                                  SlaveLimits.from_config(design.config), self._unit)
        self._tracks = SwitchTracks(switch_table(values))
        self._speed_limit = self._config.speed_limit(jump)
        self._tracker = MasterTracker(int(self._config.timeout * 1e9), self._speed_limit[0],
                                      int(values['master.velocity_window'] * 1e9),
                                      self._config.max_speed, self._config.nominal_speed)
        self._last_handover = 'none'
        # Design changes taken, and the stamp of the last master message before the latest one:
        # in ~/state, so a replay can make each recorded change at the same master message.
        self._changes = 0
        self._changed_after: int | None = None
        self._said: tuple[str, int | None, int] = ('', None, 0)  # status, switches, changes
        self._overspeed_said = False
        self._commands_pub = publisher(node, Float64MultiArray, '~/commands', COMMAND_QOS)
        self._trajectory_pub = publisher(node, JointTrajectory, '~/joint_trajectory', COMMAND_QOS)
        self._diagnostics_pub = publisher(node, DiagnosticArray, '/diagnostics', COMMAND_QOS)
        self._switches_pub = publisher(node, UInt32, '~/switches', LATCHED)
        self._state_pub = publisher(node, DiagnosticStatus, '~/state', LATCHED)
        self._lock = threading.Lock()  # master thread vs executor (timers, updates)
        self._slave_topic, self._slave_dropped = values['slave.state_topic'], 0
        self._log = EcamLog(node, LATCHED, self._slave_topic, SLAVE_QOS)
        if self._slave_topic:
            node.create_subscription(JointState, self._slave_topic, self._on_slave, SLAVE_QOS)
        node.create_service(SetBool, '~/engage', self._engage)
        self._intake = master_intake(node, self._config.topic, self._on_master)
        self._master_sub = self._intake.entity
        self._watch_timer = node.create_timer(self._config.timeout / 4.0, self._watch)
        node.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        self._publish_state()
        node.get_logger().info(
            f'electronic cam: following {self._master_sub.topic_name} (joint '
            f'{self._config.joint}), {self._config.interface} commands on '
            f'{self._commands_pub.topic_name}')

    def topics(self) -> list[TopicSpec]:
        """Return the master input and the command topics, for the recorder."""
        return [TopicSpec(self._master_sub.topic_name, JointState, MASTER_QOS)] + [
            TopicSpec(pub.topic_name, pub.msg_type, pub.qos_profile)
            for pub in (self._commands_pub, self._trajectory_pub, self._diagnostics_pub,
                        self._switches_pub, self._state_pub)] + self._log.topics()

    def change(self, design: CamDesign) -> None:
        """Take a new design: offsets blended, other changes at a common place or at once."""
        jump, config = jump_speed(design), MasterConfig.from_config(design.config)
        status, limit = design_status(self._node, design, jump), config.speed_limit(jump)
        values = design.config.parameters
        new = ElectronicCam(design.program, config.mapping)
        table = switch_table(values)
        self._watch_timer.timer_period_ns = int(config.timeout / 4.0 * 1e9)
        with self._lock:
            self._design_status, self._config = status, config
            self._tracker.timeout_ns = int(config.timeout * 1e9)
            self._tracker.speed.window_ns = int(values['master.velocity_window'] * 1e9)
            self._tracker.bound, self._tracker.nominal = config.max_speed, config.nominal_speed
            self._unit = AxisUnit.of(design.config)
            self._follower.unit = self._unit
            self._speed_limit, self._tracker.max_speed = limit, limit[0]
            if self._follower.cam.mapping != config.mapping or not _same(table, self._tracks):
                self._tracks = SwitchTracks(table)  # the next master sample says the states
            # Said under the lock: the master thread cannot apply it (and say so) before.
            self._last_handover = self._follower.change(
                new, EngageConfig.from_parameters(values), SlaveLimits.from_config(design.config))
            last = self._tracker.last
            self._changes += 1
            self._changed_after = None if last is None else last.stamp_ns
            self._node.get_logger().info(f'design change {self._last_handover}')
            self._publish_state()

    def stop(self) -> None:
        """Stop taking master messages (before the node is destroyed)."""
        self._intake.stop()

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
        if state.origin:
            self._node.get_logger().warning(
                f'new master origin: the master moved {tracker.jump:.6g} rad in '
                f'{tracker.jump_time:.6g} s, more than {JUMP_FACTOR:g} x '
                f'{tracker.plausible_speed():.6g} rad/s allows ({tracker.jumps} so far): the '
                f'slave holds and engages again from where it is')
        handover = self._follower.handover
        point = self._follower.command(state)
        if point is not None:
            self._publish(message, state, point)
        self._say_events()
        if handover is not None and self._follower.handover is None:
            self._said_applied(handover.old, handover.new, state)
        mapping = self._follower.cam.mapping
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
        """Log what the follower noted: blends over the cam's peaks, refusals, stops."""
        logger = self._node.get_logger()
        for event in self._follower.events:  # one call site per severity, as rclpy requires
            if event.startswith('stopping'):
                logger.warning(event)
            else:
                logger.info(event)
        self._follower.events.clear()

    def _publish(self, message: JointState, state: MasterState, point: Any) -> None:
        """Publish the commands first (the latency that matters), then the rest."""
        position, velocity = float(point.position), float(point.velocity)
        value = position if self._config.interface == 'position' else velocity
        self._commands_pub.publish(Float64MultiArray(data=[value]))
        joints = JointState(name=list(JOINT_NAMES), position=[state.position, position],
                            velocity=[state.omega, velocity])
        joints.header = message.header
        self._joint_pub.publish(joints)
        if self._config.trajectory_horizon > 0.0:
            count = self._config.trajectory_points
            times = self._config.trajectory_horizon / count * np.arange(1, count + 1)
            ahead = self._follower.ahead(state, times)
            self._trajectory_pub.publish(_trajectory(times, ahead.position, ahead.velocity,
                                                     ahead.acceleration))

    def _said_applied(self, old: ElectronicCam, new: ElectronicCam, state: MasterState) -> None:
        """Say where a pending design took over and how far the position command moved."""
        step = float(new.setpoints(state.track).position - old.setpoints(state.track).position)
        angle = np.degrees(float(new.mapping.cam_angle(state.track)))
        self._last_handover = (f'at cam angle {angle:.3f} deg, position command moved '
                               f'{self._unit.say(step)}')
        self._node.get_logger().info(f'design change applied {self._last_handover}')

    def _on_slave(self, message: JointState) -> None:
        """Note the driven axis's position (joint follower); where a first engagement starts."""
        try:
            position, _ = read_master(FOLLOWER_JOINT, message.name, message.position,
                                      message.velocity, message.effort)
        except BadMaster as bad:
            with self._lock:
                self._slave_dropped += 1
            self._node.get_logger().warning(
                f'dropped a {self._slave_topic} message: {bad.reason} '
                f'({self._slave_dropped} so far)', throttle_duration_sec=5.0)
            return
        with self._lock:
            self._follower.present = position

    def _engage(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        with self._lock:
            response.success, response.message = self._follower.engage(request.data)
            if not request.data and self._follower.phase != STOPPING:
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
        """Notice master silence: hold the follower once the master is lost."""
        status = self._tracker.check(self._node.get_clock().now().nanoseconds)
        if status != LOST:
            return
        self._follower.lose()
        self._tracks.reset()
        held = self._follower.held
        self._node.get_logger().warning(
            f'master silent for {self._config.timeout:g} s: holding the follower at '
            f'{"nothing" if held is None else self._unit.say(held)}')
        self._hold()
        self._publish_state()

    def _hold(self) -> None:
        """Command the held position at rest (nothing if nothing was ever commanded)."""
        held = self._follower.held
        if held is None:
            return
        self._commands_pub.publish(Float64MultiArray(
            data=[held if self._config.interface == 'position' else 0.0]))
        last = self._tracker.last
        joints = JointState(name=list(JOINT_NAMES), velocity=[0.0, 0.0],
                            position=[last.position if last else 0.0, held])
        joints.header.stamp = self._node.get_clock().now().to_msg()
        self._joint_pub.publish(joints)
        if self._config.trajectory_horizon > 0.0:
            self._trajectory_pub.publish(_trajectory(
                np.array([self._config.trajectory_horizon]), *np.array([[held], [0.0], [0.0]])))

    def _publish_state(self) -> None:
        """Publish ~/state when the slave's status, the switch word or the design changed."""
        now = (self._follower.status, self._tracks.word, self._changes)
        if now != self._said:
            self._said = now
            self._state_pub.publish(self._engagement_status())

    # Diagnostics ----------------------------------------------------------------------------
    def _publish_diagnostics(self) -> None:
        array = DiagnosticArray()
        array.header.stamp = self._node.get_clock().now().to_msg()
        with self._lock:
            array.status = [self._design_status, self._master_status(),
                            self._engagement_status(),
                            recording_status(self._node, self._recorder())]
        self._diagnostics_pub.publish(array)

    def _engagement_status(self) -> DiagnosticStatus:
        return engagement_status(
            self._node, self._follower, self._tracks,
            **{MASTER_TOPIC_KEY: self._master_sub.topic_name, DESIGN_CHANGES_KEY: self._changes,
               CHANGED_AFTER_KEY: ('none' if self._changed_after is None
                                   else self._changed_after)},
            slave_state_topic=self._slave_topic or 'none',
            slave_states_dropped=self._slave_dropped)

    def _master_status(self) -> DiagnosticStatus:
        handover = self._follower.handover
        return master_status(self._node, self._tracker, self._speed_limit,
                             topic=self._master_sub.topic_name,
                             design_change=handover.describe() if handover else 'none',
                             last_design_change=self._last_handover)


def _same(table: Any, tracks: SwitchTracks) -> bool:
    """Say whether a switch table equals the one the tracks run."""
    old = tracks.table
    return (table.names, table.hysteresis) == (old.names, old.hysteresis) and all(
        np.array_equal(a, b) for a, b in ((table.on, old.on), (table.off, old.off),
                                          (table.lead_time, old.lead_time)))


def jump_speed(design: CamDesign) -> float | None:
    """Return the design's jump speed (rad/s of cam), None without dynamics or jump."""
    report = design.dynamics_check
    return None if report is None else report.jump_speed


def _trajectory(times: np.ndarray, positions: np.ndarray, velocities: np.ndarray,
                accelerations: np.ndarray) -> JointTrajectory:
    """Build a follower trajectory starting now (stamp 0) with points at times (s)."""
    trajectory = JointTrajectory(joint_names=[FOLLOWER_JOINT])
    trajectory.points = [
        JointTrajectoryPoint(positions=[p], velocities=[v], accelerations=[a],
                             time_from_start=Duration(nanoseconds=round(t * 1e9)).to_msg())
        for t, p, v, a in zip(times.tolist(), positions.tolist(), velocities.tolist(),
                              accelerations.tolist())]
    return trajectory
