#include "minibot3d_sim/lidar.h"

#include <cmath>
#include <limits>

namespace minibot3d_sim {

Lidar::Lidar(const LidarSpec& spec, const WorldSlice* slice, unsigned seed)
    : spec_(spec), slice_(slice), rng_(seed), noise_(spec.noise_mean, spec.noise_stddev) {
  const Eigen::Isometry3d& p = spec.pose_in_root;
  const Eigen::Vector3d x_axis = p.linear() * Eigen::Vector3d::UnitX();
  sensor_in_root_ = Pose2{p.translation().x(), p.translation().y(),
                          std::atan2(x_axis.y(), x_axis.x())};
  increment_ = spec.samples > 1 ? (spec.max_angle - spec.min_angle) / (spec.samples - 1) : 0.0;
  cos_.resize(spec.samples);
  sin_.resize(spec.samples);
  for (int i = 0; i < spec.samples; ++i) {
    const double a = spec.min_angle + i * increment_;
    cos_[i] = std::cos(a);
    sin_[i] = std::sin(a);
  }
}

void Lidar::Scan(const Pose2& root_pose, std::vector<float>* ranges) {
  const Pose2 s = Compose(root_pose, sensor_in_root_);
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const Eigen::Vector2d origin(s.x, s.y);
  const double inf = std::numeric_limits<double>::infinity();
  ranges->resize(spec_.samples);
  for (int i = 0; i < spec_.samples; ++i) {
    const Eigen::Vector2d dir(c * cos_[i] - sn * sin_[i], sn * cos_[i] + c * sin_[i]);
    // Cast a little past max_range so noise can still push a far return inside the limit.
    const double reach = spec_.max_range + 5.0 * spec_.noise_stddev;
    double r = slice_->CastRay(origin, dir, reach).range;
    if (std::isfinite(r)) {
      if (spec_.noise_stddev > 0 || spec_.noise_mean != 0) r += noise_(rng_);
      if (spec_.resolution > 0) r = std::round(r / spec_.resolution) * spec_.resolution;
      if (r > spec_.max_range) r = inf;
      else if (r < spec_.min_range) r = -inf;
    } else {
      r = inf;
    }
    (*ranges)[i] = static_cast<float>(r);
  }
  rays_cast_ += spec_.samples;
}

}  // namespace minibot3d_sim
