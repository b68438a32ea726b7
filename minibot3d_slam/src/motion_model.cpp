// Sampling odometry motion model (see motion_model.h).
#include "motion_model.h"

#include <cmath>

namespace minibot3d_slam {

Pose2 MotionModel::Sample(const Pose2& pose, const Pose2& odom_old, const Pose2& odom_new,
                          std::mt19937_64* rng) const {
  const Pose2 u = Between(odom_old, odom_new);
  const double ax = std::fabs(u.x), ay = std::fabs(u.y), at = std::fabs(u.yaw);
  const double sxy = 0.3 * srr_;
  const double sigma_x = srr_ * ax + sxy * ay + srt_ * at;
  const double sigma_y = srr_ * ay + sxy * ax + srt_ * at;
  const double sigma_t = str_ * std::hypot(u.x, u.y) + stt_ * at;
  std::normal_distribution<double> unit(0.0, 1.0);
  Pose2 noisy = u;
  // Draw all three even when a sigma is zero so that the random stream does not depend on it.
  noisy.x += sigma_x * unit(*rng);
  noisy.y += sigma_y * unit(*rng);
  noisy.yaw = NormalizeAngle(noisy.yaw + sigma_t * unit(*rng));
  return Compose(pose, noisy);
}

}  // namespace minibot3d_slam
