"""Middleware set-up shared by cam_node and the cam_ros commands: the shipped Fast DDS profile.

Fast DDS reads its XML profiles once per process, when the first DDS participant is created, from
the file named by FASTRTPS_DEFAULT_PROFILES_FILE (FASTDDS_DEFAULT_PROFILES_FILE in Fast DDS 3).
So the variable must be set before rclpy.init() and before any other rclpy context in the process.
"""
from __future__ import annotations

import os
from typing import MutableMapping

from cam_ros.paths import fastdds_profile_path

PROFILE_VARIABLES = ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE')


def use_shipped_profile(environ: MutableMapping[str, str] = os.environ) -> None:
    """Point Fast DDS at config/fastdds.xml unless the user set either variable (even to '')."""
    if not any(name in environ for name in PROFILE_VARIABLES):
        environ[PROFILE_VARIABLES[0]] = str(fastdds_profile_path())
