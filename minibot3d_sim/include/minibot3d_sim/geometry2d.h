// Small planar geometry types shared by the simulator core.
#ifndef MINIBOT3D_SIM_GEOMETRY2D_H_
#define MINIBOT3D_SIM_GEOMETRY2D_H_

#include <cmath>

#include <Eigen/Core>

namespace minibot3d_sim {

// A planar pose: position in metres, heading in radians (counter-clockwise from +x).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// A planar twist expressed in the body frame: forward, leftward (m/s) and yaw rate (rad/s).
struct Twist2 {
  double vx = 0.0;
  double vy = 0.0;
  double wz = 0.0;
};

inline double NormalizeAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

// p ⊕ d: the pose d, given in p's frame, expressed in p's parent frame.
inline Pose2 Compose(const Pose2& p, const Pose2& d) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return Pose2{p.x + c * d.x - s * d.y, p.y + s * d.x + c * d.y, NormalizeAngle(p.yaw + d.yaw)};
}

// Transforms a point given in the frame of `p` into p's parent frame.
inline Eigen::Vector2d TransformPoint(const Pose2& p, const Eigen::Vector2d& q) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return Eigen::Vector2d(p.x + c * q.x() - s * q.y(), p.y + s * q.x() + c * q.y());
}

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_GEOMETRY2D_H_
