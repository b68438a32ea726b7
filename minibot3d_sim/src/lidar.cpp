#include "minibot3d_sim/lidar.h"

#include <cmath>
#include <limits>

namespace minibot3d_sim {

Lidar::Lidar(const LaserSpec& spec, const WorldSlice* slice, unsigned seed)
    : spec_(spec), slice_(slice), rng_(seed), noise_(spec.noise_mean, spec.noise_stddev) {
  const Eigen::Isometry3d& p = spec.pose_in_root;
  const Eigen::Vector3d x_axis = p.linear() * Eigen::Vector3d::UnitX();
  sensor_in_root_ = Pose2{p.translation().x(), p.translation().y(),
                          std::atan2(x_axis.y(), x_axis.x())};
  increment_ = spec.samples > 1 ? (spec.max_angle - spec.min_angle) / (spec.samples - 1) : 0.0;
  cos_.resize(spec.samples);
  sin_.resize(spec.samples);
  dir_x_.resize(spec.samples);
  dir_y_.resize(spec.samples);
  true_ranges_.resize(spec.samples);
  for (int i = 0; i < spec.samples; ++i) {
    const double a = spec.min_angle + i * increment_;
    cos_[i] = std::cos(a);
    sin_[i] = std::sin(a);
  }
}

void Lidar::Scan(const Pose2& root_pose, std::vector<float>* ranges) {
  const Pose2 s = Compose(root_pose, sensor_in_root_);
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const int n = spec_.samples;
  for (int i = 0; i < n; ++i) {
    dir_x_[i] = c * cos_[i] - sn * sin_[i];
    dir_y_[i] = sn * cos_[i] + c * sin_[i];
  }
  // Cast a little past max_range so noise can still bring a far return inside the limit.
  const double reach = spec_.max_range + 5.0 * spec_.noise_stddev;
  slice_->CastFan(Eigen::Vector2d(s.x, s.y), s.yaw + spec_.min_angle, increment_, n,
                  dir_x_.data(), dir_y_.data(), reach, true_ranges_.data());
  const double inf = std::numeric_limits<double>::infinity();
  const bool noisy = spec_.noise_stddev > 0 || spec_.noise_mean != 0;
  ranges->resize(n);
  for (int i = 0; i < n; ++i) {
    double r = true_ranges_[i];
    if (std::isfinite(r)) {
      if (noisy) r += noise_(rng_);
      if (spec_.resolution > 0) r = std::round(r / spec_.resolution) * spec_.resolution;
      if (r > spec_.max_range) r = inf;
      else if (r < spec_.min_range) r = -inf;
    } else {
      r = inf;
    }
    (*ranges)[i] = static_cast<float>(r);
  }
  rays_cast_ += n;
}

}  // namespace minibot3d_sim
