"""
The electronic cam's /diagnostics statuses: its design, its master, the engagement, recording.

Each is a diagnostic_msgs/DiagnosticStatus named '<node>: <what>' whose values are strings, as
diagnostic aggregators and rqt_robot_monitor show them.
"""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from rclpy.node import Node

from cam_ros.core import CamDesign
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.line_shaft import FILTERED, LineShaft
from cam_ros.core.ecam.master_tracker import LOST, MasterTracker, OK, STALE, WAITING
from cam_ros.core.ecam.switches import SwitchTracks
from cam_ros.recording import Recorder

LEVELS = {WAITING: DiagnosticStatus.WARN, OK: DiagnosticStatus.OK,
          STALE: DiagnosticStatus.WARN, LOST: DiagnosticStatus.ERROR}


def status(node: Node, what: str, level: bytes, message: str, **values: Any) -> DiagnosticStatus:
    """Return a status of the node about what, its values as strings."""
    return DiagnosticStatus(
        level=level, name=f'{node.get_name()}: {what}', message=message,
        hardware_id=node.get_fully_qualified_name(),
        values=[KeyValue(key=key, value=str(value)) for key, value in values.items()])


def design_status(node: Node, design: CamDesign, jump: float | None,
                  what: str = 'design') -> DiagnosticStatus:
    """Say whether the design meets its limits, with its checked figures and jump speed."""
    warnings = design.warnings()
    return status(
        node, what, DiagnosticStatus.WARN if warnings else DiagnosticStatus.OK,
        '; '.join(warnings) or 'meets its limits', **cam_figures(design),
        jump_speed_rad_s='none (no dynamics or no jump)' if jump is None else f'{jump:.6g}')


def master_status(node: Node, tracker: MasterTracker, speed_limit: tuple[float, str],
                  shaft: LineShaft, **values: Any) -> DiagnosticStatus:
    """Say how the master is (ok, stale, lost, over its speed limit, filtered by the line shaft),
    with its counts and the line shaft's lag."""
    last = tracker.last
    filtered = shaft.mode == FILTERED
    level = max(LEVELS[tracker.status], DiagnosticStatus.WARN if tracker.overspeed or filtered
                else DiagnosticStatus.OK)
    message = tracker.status + (f', over {speed_limit[1]}' if tracker.overspeed else '') + (
        ', filtered' if filtered else '')
    dropped = {f'dropped: {reason}': count for reason, count in tracker.dropped.items()}
    topic = values.pop('topic')
    return status(node, 'master', level, message, topic=topic, accepted=tracker.accepted,
                  new_origins=tracker.jumps, dropped=sum(tracker.dropped.values()), **dropped,
                  speed=last.omega if last else 0.0,
                  speed_limit=f'{speed_limit[0]:.6g} ({speed_limit[1]})',
                  line_shaft=shaft.mode + (f': {shaft.why}' if shaft.why else ''),
                  lag_deg=f'{np.degrees(shaft.lag):.6g}', filtered_steps=shaft.filtered,
                  **values)


def engagement_status(node: Node, axes: SlaveAxes, tracks: SwitchTracks, faulted: bool,
                      **values: Any) -> DiagnosticStatus:
    """Say what the slaves do (ERROR while a fault stops them), their engage mode and the cam
    switches' states."""
    level = DiagnosticStatus.ERROR if faulted \
        else DiagnosticStatus.OK if axes.engaged else DiagnosticStatus.WARN
    word = tracks.word or 0
    switches = {f'switch {name}': 'on' if word >> index & 1 else 'off'
                for index, name in enumerate(tracks.table.names)}
    config = axes.followers[0].config
    return status(node, 'engagement', level, axes.status, engage_mode=config.mode,
                  periodic=config.periodic, **values, switches=word, **switches)


def recording_status(node: Node, recorder: Recorder | None) -> DiagnosticStatus:
    """Say whether the node records, where, and how many messages so far."""
    if recorder is None:
        return status(node, 'recording', DiagnosticStatus.OK, 'off')
    if recorder.failed:
        return status(node, 'recording', DiagnosticStatus.ERROR, str(recorder.error))
    return status(node, 'recording', DiagnosticStatus.OK, f'recording to {recorder.path}',
                  messages=recorder.message_count)


def cam_figures(design: CamDesign) -> dict[str, Any]:
    """Return the cam's checked figures for the diagnostics (none for a motion-only design)."""
    if design.follower is None:
        return {'motion_only': True}
    check = design.check
    return dict(max_pressure_angle_deg=f'{np.degrees(check.max_pressure_angle):.3f}',
                pressure_angle_limit_deg=f'{np.degrees(design.config.pressure_angle_limit):.3f}',
                min_radius_of_curvature_m=f'{check.min_radius:.6g}',
                radius_of_curvature_limit_m=f'{design.config.min_radius_of_curvature:.6g}',
                undercut=check.undercut)


def design_statuses(node: Node,
                    axes: Sequence[tuple[str, CamDesign]]) -> list[DiagnosticStatus]:
    """Return each axis's design diagnostics ('design', or 'design NAME' in a machine)."""
    return [design_status(node, design, jump_speed(design),
                          'design' if len(axes) == 1 else f'design {name}')
            for name, design in axes]


def jump_speed(design: CamDesign) -> float | None:
    """Return the design's jump speed (rad/s of cam), None without dynamics or jump."""
    report = design.dynamics_check
    return None if report is None else report.jump_speed
