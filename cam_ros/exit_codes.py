"""The exit codes of cam_ros's programs (the `cam_ros` commands and cam_node)."""
EXIT_OK = 0
EXIT_FAILED = 1  # the design violates a limit, or a ROS call failed
EXIT_INVALID = 2  # invalid config, arguments or input file
