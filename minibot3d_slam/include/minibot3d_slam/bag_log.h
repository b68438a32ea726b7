// Reading a ROS bag for offline SLAM: laser scans from one topic, odometry from /tf (odom → base)
// or from a nav_msgs/Odometry topic, the sensor's pose from /tf_static or /tf (base → laser).
// Lives outside the ROS-free core: it needs rosbag and tf2.
#ifndef MINIBOT3D_SLAM_BAG_LOG_H_
#define MINIBOT3D_SLAM_BAG_LOG_H_

#include <string>

#include "minibot3d_slam/carmen_log.h"

namespace minibot3d_slam {

struct BagLogOptions {
  std::string scan_topic = "/scan";
  std::string odom_topic;  // empty: odometry from /tf odom_frame → base_frame
  std::string odom_frame = "odom";
  std::string base_frame = "base_footprint";
};

// Scans that cannot be placed (no odometry or sensor pose at their time) are skipped and counted in
// CarmenLog::skipped under "scan without tf". Throws std::runtime_error naming the bag (unreadable,
// no message on the scan topic).
CarmenLog ReadBagLog(const std::string& path, const BagLogOptions& options);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_BAG_LOG_H_
