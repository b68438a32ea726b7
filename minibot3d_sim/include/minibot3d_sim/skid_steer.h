// Skid-steer kinematics, as Gazebo's libgazebo_ros_skid_steer_drive.so maps a body twist to the
// four wheel speeds (both wheels of a side turn alike) and as odometry maps them back.
#ifndef MINIBOT3D_SIM_SKID_STEER_H_
#define MINIBOT3D_SIM_SKID_STEER_H_

#include <array>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/robot_model.h"

namespace minibot3d_sim {

using minibot3d_common::Compose;
using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

struct SkidSteerGeometry {
  double wheel_separation = 0.0;  // distance between left and right wheel centres (m)
  double wheel_radius = 0.0;      // m
};

// Wheel joint speeds (rad/s, WheelIndex order) for forward speed v (m/s) and yaw rate w (rad/s).
inline std::array<double, 4> WheelSpeedsForTwist(double v, double w, const SkidSteerGeometry& g) {
  const double left = (v - w * g.wheel_separation / 2.0) / g.wheel_radius;
  const double right = (v + w * g.wheel_separation / 2.0) / g.wheel_radius;
  std::array<double, 4> omega{};
  omega[kFrontLeft] = left;
  omega[kRearLeft] = left;
  omega[kFrontRight] = right;
  omega[kRearRight] = right;
  return omega;
}

// The body twist the wheels would give without slip (each side's speed is the mean of its wheels).
inline Twist2 TwistFromWheelSpeeds(const std::array<double, 4>& omega, const SkidSteerGeometry& g) {
  const double left = 0.5 * (omega[kFrontLeft] + omega[kRearLeft]) * g.wheel_radius;
  const double right = 0.5 * (omega[kFrontRight] + omega[kRearRight]) * g.wheel_radius;
  return Twist2{0.5 * (left + right), 0.0, (right - left) / g.wheel_separation};
}

// Exact integration of a constant body twist (vx, wz) over dt: a straight line or a circular arc.
inline Pose2 IntegrateTwist(const Pose2& p, double vx, double wz, double dt) {
  const double dth = wz * dt;
  Pose2 d;
  if (std::abs(dth) < 1e-9) {
    d = Pose2{vx * dt, 0.0, dth};
  } else {
    const double r = vx / wz;
    d = Pose2{r * std::sin(dth), r * (1.0 - std::cos(dth)), dth};
  }
  return Compose(p, d);
}

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SKID_STEER_H_
