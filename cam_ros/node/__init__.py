"""cam_node: everything that runs the cam design on rclpy (node, parameters, recording, master).

Its process is cam_ros.node.process (`python -m cam_ros.node`, the cam_node script). Nothing is
imported here: the `cam_ros` commands take cam_ros.node.middleware alone, without the node, its
recorder and their libraries (twice the command's start-up, and a slower exit).
"""
