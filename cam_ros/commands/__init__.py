"""The `cam_ros` commands: one function per command, each returning the process exit code.

Exit codes: 0 ok; 1 the design violates one of its limits, or a ROS call failed; 2 invalid input
(config, arguments, files), reported as one line 'cam_ros <command>: <message>' on stderr.
"""
