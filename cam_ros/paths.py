"""Where cam_ros finds its shipped config files."""
from __future__ import annotations

from pathlib import Path

from ament_index_python.packages import get_package_share_directory


def config_dir() -> Path:
    """Return the shipped config folder: the installed share dir, else the source checkout's.

    The ament index raises OSError when AMENT_PREFIX_PATH is unset (a venv used without
    sourcing a ROS setup file), and LookupError when cam_ros is not in it.
    """
    try:
        return Path(get_package_share_directory('cam_ros')) / 'config'
    except (LookupError, OSError, ValueError):
        return Path(__file__).resolve().parents[1] / 'config'


def default_config_path() -> Path:
    """Return the embedded default design, config/default.yaml."""
    return config_dir() / 'default.yaml'


def fastdds_profile_path() -> Path:
    """Return the shipped Fast DDS profile, config/fastdds.xml (see cam_ros.node.middleware)."""
    return config_dir() / 'fastdds.xml'
