"""Run the command line: `python -m cam_ros.cli ARGS` (as the `cam_ros` executable)."""
import sys

from cam_ros.cli import main

sys.exit(main())
