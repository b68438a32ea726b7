// Poses of the readings between processed ones (see between_processed.h).
#include "minibot3d_slam/between_processed.h"

#include <algorithm>
#include <cmath>

namespace minibot3d_slam {

Pose2 PoseBetweenProcessed(const Pose2& pose0, const Pose2& odom0, const Pose2& odom,
                           const Pose2* pose1, const Pose2* odom1) {
  const Pose2 u = Between(odom0, odom);
  if (pose1 == nullptr || odom1 == nullptr) return Compose(pose0, u);
  const Pose2 u1 = Between(odom0, *odom1);
  const Pose2 v = Between(pose0, *pose1);
  const double total = std::hypot(u1.x, u1.y) + std::fabs(u1.yaw);
  // (Two processed readings at one odometry pose — temporalUpdate, standing still — leave nothing
  // to spread by: the readings between keep the first's pose.)
  const double f =
      total > 1e-9 ? std::min(1.0, (std::hypot(u.x, u.y) + std::fabs(u.yaw)) / total) : 0.0;
  const Pose2 rel{u.x + f * (v.x - u1.x), u.y + f * (v.y - u1.y),
                  NormalizeAngle(u.yaw + f * NormalizeAngle(v.yaw - u1.yaw))};
  return Compose(pose0, rel);
}

}  // namespace minibot3d_slam
