"""Run cam_node: `python -m cam_ros.node --ros-args ...`."""
import sys

from .process import main

sys.exit(main())
