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
                 const std::vector<BodyOutline>* bodies) {
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
  if (bodies != nullptr && !bodies->empty()) {
    const Eigen::Vector2d o(s.x, s.y);
    // The furthest return of each run of kBin beams (and of all), before the bodies: a body whose
    // circle lies beyond them is hidden by the world.
    const int bins = (n + kBin - 1) / kBin;
    bin_far_.assign(bins, 0.0);
    double far = 0.0;
    for (int i = 0; i < n; ++i) bin_far_[i / kBin] = std::max(bin_far_[i / kBin], true_ranges_[i]);
    for (double f : bin_far_) far = std::max(far, f);
    // Nearest first, so that near bodies hide far ones.
    near_.clear();
    for (std::size_t k = 0; k < bodies->size(); ++k) {
      const BodyOutline& b = (*bodies)[k];
      if (b.outline == nullptr || b.outline->size() < 3) continue;
      const double dist = (b.centre - o).norm();
      if (dist - b.radius > reach || dist - b.radius >= far) continue;
      near_.push_back(NearBody{dist - b.radius, dist, k});
    }
    std::sort(near_.begin(), near_.end(), [](const NearBody& a, const NearBody& b) {
      return a.closest < b.closest || (a.closest == b.closest && a.index < b.index);
    });
    for (const NearBody& near : near_) {
      const BodyOutline& body = (*bodies)[near.index];
      const double dist = near.dist, radius = body.radius;
      placed_.clear();  // the outline in the world frame, placed when a beam first needs it
      // Beams within the cone the polygon's circle subtends (all of them from inside it).
      const double cos_half =
          dist > radius ? std::sqrt(std::max(0.0, 1.0 - (radius / dist) * (radius / dist))) : -2.0;
      const Eigen::Vector2d to = body.centre - o;
      const Eigen::Vector2d u = dist > 0.0 ? Eigen::Vector2d(to / dist) : Eigen::Vector2d(1, 0);
      const auto cast = [&](int i) {
        // A beam already stopped before the circle cannot hit the polygon inside it.
        if (true_ranges_[i] <= near.closest) return;
        if (dir_x_[i] * u.x() + dir_y_[i] * u.y() < cos_half) return;
        if (placed_.empty()) {
          const minibot3d_common::PoseTransform place(body.pose);
          for (const auto& v : *body.outline) placed_.push_back(place(v));
        }
        const double t = RayPolygon(o, Eigen::Vector2d(dir_x_[i], dir_y_[i]), placed_);
        if (t < true_ranges_[i] && t <= reach) true_ranges_[i] = t;
      };
      if (cos_half <= 0.0 || !(increment_ > 0.0)) {
        for (int i = 0; i < n; ++i) cast(i);
        continue;
      }
      // Only the beams whose index falls in the cone's angular range (one beam wider each side;
      // the cone test above decides): the cone's middle relative to the first beam, in [0, 2π).
      const double half = std::acos(cos_half);
      double mid = std::atan2(u.y(), u.x()) - (s.yaw + spec_.min_angle);
      mid -= 2.0 * M_PI * std::floor(mid / (2.0 * M_PI));
      for (const double shift : {-2.0 * M_PI, 0.0, 2.0 * M_PI}) {
        const double lo = (mid + shift - half) / increment_ - 1.0;
        const double hi = (mid + shift + half) / increment_ + 1.0;
        if (hi < 0.0 || lo > n - 1) continue;
        const int i0 = std::max(0, static_cast<int>(std::ceil(lo)));
        const int i1 = std::min(n - 1, static_cast<int>(std::floor(hi)));
        bool open = false;
        for (int b = i0 / kBin; b <= i1 / kBin && !open; ++b) open = bin_far_[b] > near.closest;
        if (!open) continue;
        for (int i = i0; i <= i1; ++i) cast(i);
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
