"""ROS plumbing the rospy nodes share with the C++ ones (minibot3d_ros/*.h)."""
from minibot3d_ros.frames import FrameNames, load_frame_names  # noqa: F401
