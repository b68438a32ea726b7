// Reading CARMEN logs (FLASER, ROBOTLASER1, ODOM, PARAM) for offline SLAM.
#ifndef MINIBOT3D_SLAM_CARMEN_LOG_H_
#define MINIBOT3D_SLAM_CARMEN_LOG_H_

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_slam/log_reader.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

// Opens a CARMEN log for streaming (log_reader.h). Open reads the file once to find the no-return
// value without being told — a saturated maximum reading (the most common reading at the top of
// the range, e.g. 50.0 or 81.83), or the robot_front_laser_max PARAM — and the sensor mounting
// (holding 24 bytes per laser line meanwhile, freed when it returns, and the counts of the distinct
// readings in the upper half of the range); Next() then parses one line at a time. Malformed lines are skipped, counted in
// report().skipped and described in report().warnings as "FILE:LINE: why". Throws
// std::runtime_error naming the file when it cannot be read or holds no laser message.
std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path);

// The whole log in memory (for tests and small logs; slam_offline streams with OpenCarmenLog).
struct CarmenLog {
  std::vector<LogScan> scans;
  std::map<std::string, int> skipped;  // message type → count of lines not used
  std::vector<std::string> warnings;   // malformed lines (file, line number and why), capped
  int lines = 0;
};
CarmenLog ReadCarmenLog(const std::string& path);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_CARMEN_LOG_H_
