#include "minibot3d_sim/lidar.h"

#include <algorithm>
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

namespace {

// Distance along the ray o + t d (|d| = 1) to its first crossing of the closed polygon's edges
// (t >= 0); +inf when it misses.
double RayPolygon(const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                  const std::vector<Eigen::Vector2d>& poly) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-15) continue;
    const Eigen::Vector2d w = a - o;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;
    const double u = (w.x() * d.y() - w.y() * d.x()) / den;
    if (t >= 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

}  // namespace

void Lidar::Scan(const Pose2& root_pose, std::vector<float>* ranges,
                 const std::vector<std::vector<Eigen::Vector2d>>* bodies) {
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
  if (bodies != nullptr) {
    const Eigen::Vector2d o(s.x, s.y);
    for (const auto& poly : *bodies) {
      if (poly.size() < 3) continue;
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const auto& v : poly) centre += v;
      centre /= static_cast<double>(poly.size());
      double radius = 0.0;
      for (const auto& v : poly) radius = std::max(radius, (v - centre).norm());
      const Eigen::Vector2d to = centre - o;
      const double dist = to.norm();
      if (dist - radius > reach) continue;
      // Beams within the cone the polygon's circle subtends (all of them from inside it).
      const double cos_half =
          dist > radius ? std::sqrt(std::max(0.0, 1.0 - (radius / dist) * (radius / dist))) : -2.0;
      const Eigen::Vector2d u = dist > 0.0 ? Eigen::Vector2d(to / dist) : Eigen::Vector2d(1, 0);
      for (int i = 0; i < n; ++i) {
        if (dir_x_[i] * u.x() + dir_y_[i] * u.y() < cos_half) continue;
        const double t = RayPolygon(o, Eigen::Vector2d(dir_x_[i], dir_y_[i]), poly);
        if (t < true_ranges_[i] && t <= reach) true_ranges_[i] = t;
      }
    }
  }
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
