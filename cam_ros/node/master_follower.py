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
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import SetParametersResult
from rclpy.duration import Duration
from rclpy.exceptions import InvalidHandle
from rclpy.guard_condition import GuardCondition
from rclpy.event_handler import SubscriptionEventCallbacks
# rclpy has no public wait set; its executors and wait_for_message use this one.
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cam_ros.core import CamDesign
from cam_ros.core.ecam.handover import Handover
from cam_ros.core.ecam.master import (BadMaster, ElectronicCam, LOST, MasterConfig, MasterState,
                                      MasterTracker, OK, read_master, STALE, WAITING)
from cam_ros.recording import Recorder, TopicSpec
from cam_ros.node.qos_events import publisher
from cam_ros.rclpy_gaps import wait_set
from cam_ros.recording.intake import TakenByIntake

#: Reliable, keep last 1000: a 1 kHz master loses nothing while the node is held up for 1 s.
#: Best effort: it matches a best-effort master (the sensor-data QoS many drivers publish with)
#: and a reliable one alike; a reliable subscription would never hear the former.
MASTER_QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.BEST_EFFORT)
COMMAND_QOS = QoSProfile(depth=10)
DIAGNOSTICS_PERIOD_S = 1.0
#: Parameters that wire the node to the graph: fixed once the node runs.
WIRING = ('master.source', 'master.topic', 'master.joint')
FOLLOWER = 'follower'
LEVELS = {WAITING: DiagnosticStatus.WARN, OK: DiagnosticStatus.OK,
          STALE: DiagnosticStatus.WARN, LOST: DiagnosticStatus.ERROR}


def stamp_ns(stamp: Any) -> int:
    """Return a builtin_interfaces/Time as integer nanoseconds."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def refuse_rewiring(node: Node) -> None:
    """Make the node refuse updates of the WIRING parameters (they need a restart)."""
    def check(updates: list[Parameter]) -> SetParametersResult:
        for param in updates:
            if param.name in WIRING and param.value != node.get_parameter(param.name).value:
                return SetParametersResult(successful=False, reason=(
                    f'{param.name} = {param.value!r}: is fixed while the node runs (now '
                    f'{node.get_parameter(param.name).value!r}); restart the node to change it'))
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(check)


class MasterIntake:
    """
    Take master messages on a thread of their own, each as soon as it arrives.

    The node's executor rebuilds a wait set of all its services, timers and subscriptions for
    every message; this thread waits on the master subscription alone, so a busy node adds no
    latency between master and command. Callbacks run on this thread.
    """

    def __init__(self, node: Node, topic: str, callback: Callable[[JointState], None]):
        self._callback = callback
        self._stop = threading.Event()
        # No QoS event handlers (see TakenByIntake): best effort, volatile, no deadline and
        # automatic liveliness, MASTER_QOS matches every publisher, so none would ever fire.
        self.subscription = node.create_subscription(
            JointState, topic, callback, MASTER_QOS, callback_group=TakenByIntake(),
            event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False))
        self._wake = GuardCondition(None, None, context=node.context)
        self._wait_set = wait_set(node.context, 1, 1)
        self._node = node
        self._thread = threading.Thread(target=self._run, name='master', daemon=True)
        self._thread.start()

    def _run(self) -> None:
        subscription, wait_set = self.subscription, self._wait_set
        try:
            while not self._stop.is_set():
                with subscription.handle, self._wake.handle:
                    taken = subscription.handle.take_message(JointState, False)
                    if taken is not None:
                        self._callback(taken[0])
                        continue
                    wait_set.clear_entities()
                    wait_set.add_subscription(subscription.handle)
                    wait_set.add_guard_condition(self._wake.handle)
                    wait_set.wait(-1)
        except InvalidHandle:
            pass  # the node went away under the thread

    def stop(self) -> None:
        """End the thread and destroy the subscription."""
        self._stop.set()
        self._wake.trigger()
        self._thread.join()
        self._node.destroy_subscription(self.subscription)
        self._wake.destroy()


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
        self._design_status = self._design_diagnostics(design, jump)
        self._config = MasterConfig.from_config(design.config)
        self._cam = ElectronicCam(design.program, self._config.mapping)
        self._speed_limit = self._config.speed_limit(jump)
        self._tracker = MasterTracker(int(self._config.timeout * 1e9), self._speed_limit[0])
        self._handover: Handover | None = None
        self._last_handover = 'none'
        self._last_position = 0.0  # last commanded follower position
        self._overspeed_said = False
        self._commands_pub = publisher(node, Float64MultiArray, '~/commands', COMMAND_QOS)
        self._trajectory_pub = publisher(node, JointTrajectory, '~/joint_trajectory', COMMAND_QOS)
        self._diagnostics_pub = publisher(node, DiagnosticArray, '/diagnostics', COMMAND_QOS)
        self._lock = threading.Lock()  # master thread vs executor (timers, updates)
        self._intake = MasterIntake(node, self._config.topic, self._on_master)
        self._master_sub = self._intake.subscription
        self._watch_timer = node.create_timer(self._config.timeout / 4.0, self._watch)
        node.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        node.get_logger().info(
            f'electronic cam: following {self._master_sub.topic_name} (joint '
            f'{self._config.joint}), {self._config.interface} commands on '
            f'{self._commands_pub.topic_name}')

    def topics(self) -> list[TopicSpec]:
        """Return the master input and the command topics, for the recorder."""
        return [TopicSpec(self._master_sub.topic_name, JointState, MASTER_QOS)] + [
            TopicSpec(pub.topic_name, pub.msg_type, pub.qos_profile)
            for pub in (self._commands_pub, self._trajectory_pub, self._diagnostics_pub)]

    def change(self, design: CamDesign) -> None:
        """Take a new design: at once if the master is not moving, else at a common place."""
        jump, config = jump_speed(design), MasterConfig.from_config(design.config)
        status, limit = self._design_diagnostics(design, jump), config.speed_limit(jump)
        new = ElectronicCam(design.program, config.mapping)
        self._watch_timer.timer_period_ns = int(config.timeout / 4.0 * 1e9)
        with self._lock:
            self._design_status, self._config = status, config
            self._tracker.timeout_ns = int(config.timeout * 1e9)
            self._speed_limit, self._tracker.max_speed = limit, limit[0]
            if self._tracker.status in (WAITING, LOST):
                self._cam, self._handover = new, None
                self._last_handover = 'applied at once (master not moving)'
                return
            self._handover = Handover(self._cam, new)
            # Said under the lock: the master thread cannot apply it (and say so) before.
            self._node.get_logger().info(f'design change pending: {self._handover.describe()}')

    def stop(self) -> None:
        """Stop taking master messages (before the node is destroyed)."""
        self._intake.stop()

    # Master messages ------------------------------------------------------------------------
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
        if self._handover is not None and self._handover.due(state.track, state.step,
                                                             state.omega):
            self._hand_over(state)
        self._publish(message, state)
        if before != OK:
            self._node.get_logger().info(f'master {before} -> ok')
        if tracker.overspeed and not self._overspeed_said:
            self._node.get_logger().warning(
                f'master speed {state.omega:.6g} rad/s over {self._speed_limit[1]} '
                f'({self._speed_limit[0]:.6g} rad/s)')
        self._overspeed_said = tracker.overspeed

    def _publish(self, message: JointState, state: MasterState) -> None:
        """Publish the commands first (the latency that matters), then the rest."""
        cam = self._cam
        point = cam.setpoints(state.track, state.omega, state.alpha)
        position, velocity = float(point.position), float(point.velocity)
        value = position if self._config.interface == 'position' else velocity
        self._commands_pub.publish(Float64MultiArray(data=[value]))
        self._last_position = position
        joints = JointState(name=['cam', FOLLOWER], position=[state.position, position],
                            velocity=[state.omega, velocity])
        joints.header = message.header
        self._joint_pub.publish(joints)
        if self._config.trajectory_horizon > 0.0:
            count = self._config.trajectory_points
            times = self._config.trajectory_horizon / count * np.arange(1, count + 1)
            ahead = cam.ahead(state.track, state.omega, times)
            self._trajectory_pub.publish(_trajectory(times, ahead.position, ahead.velocity,
                                                     ahead.acceleration))

    def _hand_over(self, state: MasterState) -> None:
        """Let the pending design take over at this master sample; say what happened."""
        assert self._handover is not None
        old, new = self._handover.old, self._handover.new
        step = float(new.setpoints(state.track).position - old.setpoints(state.track)
                     .position)
        angle = np.degrees(float(new.mapping.cam_angle(state.track)))
        self._cam, self._handover = new, None
        self._last_handover = f'at cam angle {angle:.3f} deg, position command moved {step:.3g}'
        self._node.get_logger().info(f'design change applied {self._last_handover}')

    def _watch(self) -> None:
        with self._lock:
            self._hold_when_lost()

    def _hold_when_lost(self) -> None:
        """Notice master silence: hold the follower once the master is lost."""
        status = self._tracker.check(self._node.get_clock().now().nanoseconds)
        if status != LOST:
            return
        self._node.get_logger().warning(
            f'master silent for {self._config.timeout:g} s: holding the follower at '
            f'{self._last_position:.9g}')
        hold = self._last_position if self._config.interface == 'position' else 0.0
        self._commands_pub.publish(Float64MultiArray(data=[hold]))
        last = self._tracker.last
        joints = JointState(name=['cam', FOLLOWER], velocity=[0.0, 0.0],
                            position=[last.position if last else 0.0, self._last_position])
        joints.header.stamp = self._node.get_clock().now().to_msg()
        self._joint_pub.publish(joints)
        if self._config.trajectory_horizon > 0.0:
            self._trajectory_pub.publish(_trajectory(
                np.array([self._config.trajectory_horizon]), *np.array([[self._last_position],
                                                                        [0.0], [0.0]])))

    # Diagnostics ----------------------------------------------------------------------------
    def _publish_diagnostics(self) -> None:
        array = DiagnosticArray()
        array.header.stamp = self._node.get_clock().now().to_msg()
        with self._lock:
            master = self._master_status()
        array.status = [self._design_status, master, self._recording_status()]
        self._diagnostics_pub.publish(array)

    def _status(self, what: str, level: bytes, message: str, **values: Any) -> DiagnosticStatus:
        return DiagnosticStatus(
            level=level, name=f'{self._node.get_name()}: {what}', message=message,
            hardware_id=self._node.get_fully_qualified_name(),
            values=[KeyValue(key=key, value=str(value)) for key, value in values.items()])

    def _design_diagnostics(self, design: CamDesign, jump: float | None) -> DiagnosticStatus:
        warnings = design.warnings()
        return self._status(
            'design', DiagnosticStatus.WARN if warnings else DiagnosticStatus.OK,
            '; '.join(warnings) or 'meets its limits', **_cam_figures(design),
            jump_speed_rad_s='none (no dynamics or no jump)' if jump is None else f'{jump:.6g}')

    def _master_status(self) -> DiagnosticStatus:
        tracker = self._tracker
        last = tracker.last
        level = max(LEVELS[tracker.status], DiagnosticStatus.WARN if tracker.overspeed
                    else DiagnosticStatus.OK)
        message = tracker.status + (f', over {self._speed_limit[1]}' if tracker.overspeed
                                    else '')
        dropped = {f'dropped: {reason}': count for reason, count in tracker.dropped.items()}
        pending = self._handover.describe() if self._handover else 'none'
        return self._status('master', level, message, topic=self._master_sub.topic_name,
                            accepted=tracker.accepted, dropped=sum(tracker.dropped.values()),
                            **dropped, speed=last.omega if last else 0.0,
                            speed_limit=f'{self._speed_limit[0]:.6g} ({self._speed_limit[1]})',
                            design_change=pending,
                            last_design_change=self._last_handover)

    def _recording_status(self) -> DiagnosticStatus:
        recorder = self._recorder()
        if recorder is None:
            return self._status('recording', DiagnosticStatus.OK, 'off')
        if recorder.failed:
            return self._status('recording', DiagnosticStatus.ERROR, str(recorder.error))
        return self._status('recording', DiagnosticStatus.OK, f'recording to {recorder.path}',
                            messages=recorder.message_count)


def _cam_figures(design: CamDesign) -> dict[str, Any]:
    """Return the cam's checked figures for the diagnostics (none for a motion-only design)."""
    if design.follower is None:
        return {'motion_only': True}
    check = design.check
    return dict(max_pressure_angle_deg=f'{np.degrees(check.max_pressure_angle):.3f}',
                pressure_angle_limit_deg=f'{np.degrees(design.config.pressure_angle_limit):.3f}',
                min_radius_of_curvature_m=f'{check.min_radius:.6g}',
                radius_of_curvature_limit_m=f'{design.config.min_radius_of_curvature:.6g}',
                undercut=check.undercut)


def jump_speed(design: CamDesign) -> float | None:
    """Return the design's jump speed (rad/s of cam), None without dynamics or jump."""
    report = design.dynamics_check
    return None if report is None else report.jump_speed


def _trajectory(times: np.ndarray, positions: np.ndarray, velocities: np.ndarray,
                accelerations: np.ndarray) -> JointTrajectory:
    """Build a follower trajectory starting now (stamp 0) with points at times (s)."""
    trajectory = JointTrajectory(joint_names=[FOLLOWER])
    trajectory.points = [
        JointTrajectoryPoint(positions=[p], velocities=[v], accelerations=[a],
                             time_from_start=Duration(nanoseconds=round(t * 1e9)).to_msg())
        for t, p, v, a in zip(times.tolist(), positions.tolist(), velocities.tolist(),
                              accelerations.tolist())]
    return trajectory
