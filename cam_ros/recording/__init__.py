"""
Record, inspect and replay ROS topics as rosbag2-compatible MCAP files.

Recorder writes the exact wire bytes of chosen topics (plus text attachments such as the cam
design) into one .mcap file that `ros2 bag`, Foxglove, PlotJuggler and rosbags open;
open_recording / info / format_info inspect and decode it (also after a crash), parameter_changes
lists the parameter events it holds; recover rewrites a file cut short by a killed recorder into a
finished one; replay (or a Player) publishes it back with the recorded QoS and timing.
"""

from cam_ros.recording.reader import open_recording, RecordedMessage, Recording, TopicInfo
from cam_ros.recording.parameters import (CONFIG_ATTACHMENT, ParameterChange,
                                          PARAMETERS_ATTACHMENT, parameter_changes, params_file)
from cam_ros.recording.recover import recover, Recovery
from cam_ros.recording.replay import Player, replay
from cam_ros.recording.summary import format_info, info
from cam_ros.recording.writer import PARAMETER_EVENTS, Recorder, TopicSpec

__all__ = [
    'CONFIG_ATTACHMENT',
    'PARAMETERS_ATTACHMENT',
    'PARAMETER_EVENTS',
    'ParameterChange',
    'Player',
    'RecordedMessage',
    'Recorder',
    'Recording',
    'Recovery',
    'TopicInfo',
    'TopicSpec',
    'format_info',
    'info',
    'open_recording',
    'parameter_changes',
    'params_file',
    'recover',
    'replay',
]
