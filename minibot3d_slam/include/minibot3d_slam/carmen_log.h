// Reading CARMEN logs (FLASER, ROBOTLASER1, ODOM, PARAM) for offline SLAM.
#ifndef MINIBOT3D_SLAM_CARMEN_LOG_H_
#define MINIBOT3D_SLAM_CARMEN_LOG_H_

#include <map>
#include <string>
#include <vector>

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

struct LogScan {
  LaserScan scan;       // ranges with no-return readings already mapped to +inf
  Pose2 odom;           // the robot's odometry pose at the scan
  double timestamp = 0.0;  // ipc_timestamp, the time relations files refer to
};

struct CarmenLog {
  std::vector<LogScan> scans;
  std::map<std::string, int> skipped;  // message type → count of lines not used
  std::vector<std::string> warnings;   // malformed lines (line number and why), capped
  int lines = 0;
};

// Parses a CARMEN log. The no-return value is detected without being told: a saturated maximum
// reading (the most common reading at the top of the range, e.g. 50.0 or 81.83), or the
// robot_front_laser_max PARAM. Throws std::runtime_error naming the file when it cannot be read
// or holds no laser message; malformed lines are skipped and reported in warnings.
CarmenLog ReadCarmenLog(const std::string& path);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_CARMEN_LOG_H_
