"""Where cam_ros finds its shipped config, with and without a ROS environment."""
from __future__ import annotations

from pathlib import Path

from cam_ros.paths import default_config_path

CHECKOUT_DEFAULT = Path(__file__).resolve().parents[1] / 'config' / 'default.yaml'


def test_default_config_is_the_shipped_one(monkeypatch):
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(Path(__file__).parent))  # no cam_ros in it
    assert default_config_path() == CHECKOUT_DEFAULT


def test_default_config_is_found_without_ament_prefix_path(monkeypatch):
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    path = default_config_path()
    assert path.read_bytes() == CHECKOUT_DEFAULT.read_bytes()
