"""Keyboard teleop for minibot3d: keymap is the ROS-free core of diff_wheeled_robot_key."""
