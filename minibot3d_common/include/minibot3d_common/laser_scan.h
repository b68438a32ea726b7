// One planar laser scan as the ROS-free cores take it (SLAM, localization, costmaps): what a
// sensor_msgs/LaserScan carries, with each beam's bearing spelled out and the sensor's mount.
//
// A reading that is NaN, ±inf, below range_min or at/beyond range_max is a no-return (REP 117:
// +inf nothing within range, -inf too close); each core says what it does with those.
#ifndef MINIBOT3D_COMMON_LASER_SCAN_H_
#define MINIBOT3D_COMMON_LASER_SCAN_H_

#include <vector>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_common {

struct LaserScan {
  double time = 0.0;            // s
  std::vector<double> ranges;   // m
  std::vector<double> angles;   // rad, one per range, in the sensor frame
  double range_min = 0.0;       // m
  double range_max = 0.0;       // m
  Pose2 sensor_in_base;         // the sensor's pose in the robot's base frame
};

// Beam bearings angle_min + i * angle_increment, i = 0 .. count - 1, as sensor_msgs/LaserScan
// defines them.
inline std::vector<double> MakeBeamAngles(double angle_min, double angle_increment, int count) {
  std::vector<double> angles(count > 0 ? count : 0);
  for (int i = 0; i < count; ++i) angles[i] = angle_min + i * angle_increment;
  return angles;
}

}  // namespace minibot3d_common

#endif  // MINIBOT3D_COMMON_LASER_SCAN_H_
