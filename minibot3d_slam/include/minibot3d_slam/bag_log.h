// Reading a ROS bag for offline SLAM: laser scans from one topic, odometry from /tf (odom → base)
// or from a nav_msgs/Odometry topic, the sensor's pose from /tf_static or /tf (base → laser).
// Lives outside the ROS-free core: it needs rosbag and tf2.
#ifndef MINIBOT3D_SLAM_BAG_LOG_H_
#define MINIBOT3D_SLAM_BAG_LOG_H_

#include <memory>
#include <string>

#include "minibot3d_slam/log_reader.h"

namespace minibot3d_slam {

struct BagLogOptions {
  std::string scan_topic = "/scan";
  std::string odom_topic;  // empty: odometry from /tf odom_frame → base_frame
  std::string odom_frame = "odom";
  std::string base_frame = "base_footprint";
};

// Opens a bag for streaming (log_reader.h). Open only reads the bag's index (message counts);
// Next() reads the bag in time order, all topics together, and yields a scan once the odometry
// (transforms, or --odom-topic messages) is known a second past its stamp: the reader holds the
// last 30 s of transforms and odometry (static transforms for good) and the scans waiting, not
// the bag. Scans that cannot be placed (no odometry or sensor pose at their time) are skipped,
// counted in report().skipped under "scan without tf" and described in warnings during the first
// pass. Throws std::runtime_error naming the bag (unreadable, no message on the scan topic).
std::unique_ptr<LogReader> OpenBagLog(const std::string& path, const BagLogOptions& options);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_BAG_LOG_H_
