"""cam_ros: disk-cam / follower kinematics served to ROS 2."""
