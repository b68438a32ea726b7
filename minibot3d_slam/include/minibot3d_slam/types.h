// Plain types shared by the SLAM core, its tools and the ROS node (no ROS here).
#ifndef MINIBOT3D_SLAM_TYPES_H_
#define MINIBOT3D_SLAM_TYPES_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "minibot3d_map_io/map_io.h"

namespace minibot3d_slam {

struct Pose2 {
  double x = 0.0, y = 0.0, theta = 0.0;
};

inline double NormalizeAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

// a ⊕ b: b (given in a's frame) in a's parent frame.
inline Pose2 Compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return Pose2{a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, NormalizeAngle(a.theta + b.theta)};
}

// a ⊖ b: the pose of a in b's frame (so Compose(b, Between(a, b)) == a).
inline Pose2 Between(const Pose2& a, const Pose2& b) {
  const double c = std::cos(b.theta), s = std::sin(b.theta);
  const double dx = a.x - b.x, dy = a.y - b.y;
  return Pose2{c * dx + s * dy, -s * dx + c * dy, NormalizeAngle(a.theta - b.theta)};
}

// One laser scan, in the sensor's frame. Beams may come in any order and any field of view.
// A reading that is NaN, ±inf, <= range_min or >= range_max is a no-return: it marks and clears
// nothing, except that with GmappingOptions::clearMaxRange a +inf or >= range_max reading clears
// free space out to maxUrange (ScanMatcher::Prepare).
struct LaserScan {
  double time = 0.0;                 // s
  std::vector<double> ranges;        // m
  std::vector<double> angles;        // rad, one per range, sensor frame
  double range_min = 0.0;
  double range_max = 0.0;            // readings at or beyond it are no-returns
  Pose2 sensor_in_base;              // pose of the sensor in the robot's base frame
};

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
