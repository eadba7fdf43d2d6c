"""Summarise a recording: what `cam_ros info FILE` prints, as data and as text."""
from __future__ import annotations

import datetime
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Union

from cam_ros.recording.parameters import parameter_changes, ParameterChange
from cam_ros.recording.reader import open_recording


def info(path: Union[str, os.PathLike]) -> dict[str, Any]:
    """Return a plain summary of a recording (what `cam_ros info FILE` prints)."""
    recording = open_recording(path)
    bag = recording.metadata.get('rosbag2', {})
    return {
        'path': str(recording.path),
        'size_bytes': recording.path.stat().st_size,
        'storage_identifier': 'mcap',
        'complete': recording.complete,
        'ros_distro': _ros_distro(bag.get('serialized_metadata', '')),
        'start_ns': recording.start_ns,
        'end_ns': recording.end_ns,
        'duration_ns': recording.duration_ns,
        'message_count': recording.message_count,
        'topics': [
            {'name': t.name, 'type': t.type, 'count': t.count,
             'serialization_format': t.serialization_format, 'qos': [dict(q) for q in t.qos],
             'type_hash': t.type_hash}
            for t in recording.topics.values()],
        'attachments': {name: len(text.encode('utf-8'))
                        for name, text in recording.attachments.items()},
        'description': dict(recording.metadata.get('cam_ros', {})),
        'parameter_changes': [
            {'time_ns': c.time_ns, 'node': c.node, 'name': c.name, 'kind': c.kind,
             'old': c.old, 'new': c.new} for c in parameter_changes(recording)],
    }


def _ros_distro(serialized_metadata: str) -> str:
    """Return the ros_distro of a rosbag2 metadata text ('' when absent)."""
    for line in serialized_metadata.splitlines():
        if line.startswith('ros_distro:'):
            return line.partition(':')[2].strip()
    return ''


def format_info(data: Mapping[str, Any]) -> str:
    """Return info() data as text laid out like `ros2 bag info`."""
    def stamp(ns: int) -> str:
        sec, nsec = divmod(ns, 10**9)
        local = datetime.datetime.fromtimestamp(sec).strftime('%b %d %Y %H:%M:%S')
        return f'{local}.{nsec:09d} ({sec}.{nsec:09d})'

    def qos(profiles: list[Mapping[str, Any]]) -> str:
        return '; '.join(
            f"{p['reliability']}, {p['durability']}, {p['history']} ({p['depth']})"
            for p in profiles) or 'unknown'

    topics = [
        f"Topic: {t['name']} | Type: {t['type']} | Count: {t['count']} | "
        f"Serialization Format: {t['serialization_format']} | QoS: {qos(t['qos'])}"
        for t in data['topics']] or ['']
    attachments = [f'{name} ({_file_size(size)})' for name, size in data['attachments'].items()]
    rows = [
        ('Files', Path(data['path']).name),
        ('Bag size', _file_size(data['size_bytes'])),
        ('Storage id', data['storage_identifier']),
        ('ROS Distro', data['ros_distro'] or 'unknown'),
        ('Complete', 'yes' if data['complete'] else 'no (no summary: recorder did not close)'),
        ('Duration', f"{data['duration_ns'] / 1e9:.9f}s"),
        ('Start', stamp(data['start_ns'])),
        ('End', stamp(data['end_ns'])),
        ('Messages', str(data['message_count'])),
        ('Topic information', '\n'.join(topics)),
        ('Attachments', '\n'.join(attachments) or 'none'),
    ]
    rows += [(f'Description {key}', value) for key, value in data['description'].items()]
    rows.append(('Parameter changes', '\n'.join(
        f"+{(c['time_ns'] - data['start_ns']) / 1e9:.3f}s {c['node']} "
        + ParameterChange(**c).text() for c in data['parameter_changes']) or 'none'))
    width = max(len(label) for label, _ in rows) + 2
    indent = '\n' + ' ' * width
    return '\n'.join(f'{label + ":":<{width}}{value.replace(chr(10), indent)}'
                     for label, value in rows)


def _file_size(size: int) -> str:
    """Return a byte count the way rosbag2 prints it (B, KiB, MiB, GiB)."""
    value = float(size)
    for unit in ('B', 'KiB', 'MiB'):
        if value < 1024:
            return f'{value:.1f} {unit}' if unit != 'B' else f'{size} B'
        value /= 1024
    return f'{value:.1f} GiB'
