// Plain types shared by the SLAM core, its tools and the ROS node (no ROS here).
#ifndef MINIBOT3D_SLAM_TYPES_H_
#define MINIBOT3D_SLAM_TYPES_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_common/laser_scan.h"
#include "minibot3d_map_io/map_io.h"

namespace minibot3d_slam {

using minibot3d_common::Between;
using minibot3d_common::Compose;
using minibot3d_common::NormalizeAngle;
using minibot3d_common::Pose2;

// One laser scan (minibot3d_common). A no-return marks and clears nothing, except that with
// GmappingOptions::clearMaxRange a +inf or >= range_max reading clears free space out to maxUrange
// (ScanMatcher::Prepare).
using minibot3d_common::LaserScan;

// An occupancy grid as map_server and nav_msgs/OccupancyGrid see it: row-major from the origin
// (lower-left corner), x to the right, y up; values -1 unknown, 0 free … 100 occupied. The type
// of minibot3d_map_io, which reads and writes it in map_server's format.
using GridMap = minibot3d_map_io::OccupancyGrid;

struct StampedPose {
  double time = 0.0;
  Pose2 pose;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_TYPES_H_
