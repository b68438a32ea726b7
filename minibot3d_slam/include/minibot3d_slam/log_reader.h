// Laser logs read one reading at a time, so offline SLAM holds one reading, not the whole log,
// whatever the log's length (CARMEN logs: carmen_log.h; ROS bags: bag_log.h).
#ifndef MINIBOT3D_SLAM_LOG_READER_H_
#define MINIBOT3D_SLAM_LOG_READER_H_

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

struct LogScan {
  LaserScan scan;          // ranges with no-return readings already mapped to +inf
  Pose2 odom;              // the robot's odometry pose at the scan
  double timestamp = 0.0;  // ipc_timestamp / header stamp, the time relations files refer to
};

// What a reader learnt about the log while opening it (and, for what can only be judged reading
// by reading, during its first pass).
struct LogReport {
  std::map<std::string, int> skipped;  // message type (or topic, or reason) → count not used
  std::vector<std::string> warnings;   // malformed lines / unplaceable scans, naming where, capped
  int lines = 0;                       // lines (CARMEN) or messages (bag) in the log
};

// Lifecycle: a reader is made by its Open function (OpenCarmenLog, OpenBagLog), which learns what
// holds for the whole log — a CARMEN log's no-return value and sensor mounting, by reading it once;
// a bag's message counts, from its index — and throws std::runtime_error naming the file when it
// cannot be read or holds no laser reading. Next() then yields the readings in log order, one at a
// time; Rewind() starts over and the same readings come again (slam_offline's second pass). The
// reader holds one reading (a bag reader: a window of seconds) plus what its Open gathered, which
// does not grow with the log's length.
class LogReader {
 public:
  virtual ~LogReader() = default;
  // Fills *scan with the next reading and returns true; false at the end of the log. Throws
  // std::runtime_error naming the file (and line, where there are lines) when the log cannot be
  // read on or no longer matches what Open read (the file changed in between).
  virtual bool Next(LogScan* scan) = 0;
  virtual void Rewind() = 0;
  const LogReport& report() const { return report_; }

 protected:
  LogReport report_;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_LOG_READER_H_
