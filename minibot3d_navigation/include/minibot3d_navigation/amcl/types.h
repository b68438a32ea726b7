// Basic value types shared by the ROS-free AMCL core (Monte Carlo localization,
// Thrun, Burgard & Fox, "Probabilistic Robotics", ch. 8).
#ifndef MINIBOT3D_NAVIGATION_AMCL_TYPES_H_
#define MINIBOT3D_NAVIGATION_AMCL_TYPES_H_

#include <cmath>
#include <cstdint>
#include <vector>

namespace minibot3d_navigation {
namespace amcl {

constexpr double kPi = 3.14159265358979323846;

// Wraps an angle to [-pi, pi).  Used everywhere a yaw is stored so that
// angle differences and histogram bins never see unbounded angles.
inline double NormalizeAngle(double a) {
  if (a >= -kPi && a < kPi) return a;
  double r = std::fmod(a + kPi, 2.0 * kPi);
  if (r < 0.0) r += 2.0 * kPi;
  return r - kPi;
}

// Smallest signed difference a - b, in [-pi, pi).
inline double AngleDiff(double a, double b) { return NormalizeAngle(a - b); }

// A planar pose: position in metres, yaw in radians (counter-clockwise).
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

inline bool IsFinite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw);
}

// Pose composition a (+) b: b expressed in the frame of a, returned in the
// frame a is expressed in.
inline Pose2D Compose(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y,
          NormalizeAngle(a.yaw + b.yaw)};
}

// Inverse composition (-)a (+) b: pose b expressed in the frame of a.
inline Pose2D Between(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, AngleDiff(b.yaw, a.yaw)};
}

// One particle: a pose hypothesis and its importance weight.  Weights of the
// filter's particle set are kept normalised (sum 1).
struct Particle {
  Pose2D pose;
  double weight = 0.0;
  // Drawn at random by augmented MCL's recovery (or descended from such a
  // draw) since the hypotheses were last set (a pose, a map-wide search, a
  // spread over free space).  A mode made of such particles was found by
  // resampling, not among the places the filter was told to consider.
  bool injected = false;
  // The seeded hypothesis (a map-wide search candidate, AmclFilter::
  // hypotheses()) this particle descends from; -1: none (a pose the user
  // gave, a uniform spread, or an injected draw).
  int16_t hypothesis = -1;
};

// One laser scan as the filter consumes it.  The ROS node fills this from a
// sensor_msgs/LaserScan plus the laser->base transform.
struct LaserScan {
  std::vector<float> ranges;   // metres; NaN/inf allowed (sensor_model.h)
  std::vector<double> angles;  // beam bearing in the laser frame, radians
  double range_min = 0.0;      // sensor limits from the message
  double range_max = 0.0;
  Pose2D laser_pose;           // laser pose in the robot base frame
};

// Beam angles angle_min + i * angle_increment, i = 0..count-1, as in
// sensor_msgs/LaserScan.
inline std::vector<double> MakeBeamAngles(double angle_min,
                                          double angle_increment, int count) {
  std::vector<double> angles(count > 0 ? count : 0);
  for (int i = 0; i < count; ++i) angles[i] = angle_min + i * angle_increment;
  return angles;
}

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_TYPES_H_
