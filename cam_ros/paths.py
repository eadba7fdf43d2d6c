"""Where cam_ros finds its shipped config files."""
from __future__ import annotations

from pathlib import Path

from ament_index_python.packages import PackageNotFoundError, get_package_share_directory


def config_dir() -> Path:
    """Return the shipped config folder: the installed share dir, else the source checkout's."""
    try:
        return Path(get_package_share_directory('cam_ros')) / 'config'
    except (PackageNotFoundError, ValueError, LookupError):
        return Path(__file__).resolve().parents[1] / 'config'


def default_config_path() -> Path:
    """Return the embedded default design, config/default.yaml."""
    return config_dir() / 'default.yaml'
