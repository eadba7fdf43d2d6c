"""
Record, inspect and replay ROS topics as rosbag2-compatible MCAP files.

Recorder writes the exact wire bytes of chosen topics (plus text attachments such as the cam
design) into one .mcap file that `ros2 bag`, Foxglove, PlotJuggler and rosbags open;
open_recording / info / format_info inspect and decode it (also after a crash); replay publishes
it back with the recorded QoS and timing.
"""

from cam_ros.recording.reader import (format_info, info, open_recording, RecordedMessage,
                                      Recording, TopicInfo)
from cam_ros.recording.replay import replay
from cam_ros.recording.writer import PARAMETER_EVENTS, Recorder, TopicSpec

__all__ = [
    'PARAMETER_EVENTS',
    'RecordedMessage',
    'Recorder',
    'Recording',
    'TopicInfo',
    'TopicSpec',
    'format_info',
    'info',
    'open_recording',
    'replay',
]
