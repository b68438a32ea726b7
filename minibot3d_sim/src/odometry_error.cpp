#include "minibot3d_sim/odometry_error.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "minibot3d_common/options.h"

namespace minibot3d_sim {

void ValidateOdometryError(const OdometryErrorOptions& o) {
  using minibot3d_common::options::Num;
  const auto finite = [](const char* name, double v) {
    if (!std::isfinite(v)) {
      throw std::invalid_argument(std::string("odom_error_") + name + "=" + Num(v) +
                                  " must be finite");
    }
  };
  const auto scale = [&](const char* name, double v) {
    finite(name, v);
    if (!(v > -1.0)) {
      throw std::invalid_argument(std::string("odom_error_") + name + "=" + Num(v) +
                                  " must be > -1 (a relative error)");
    }
  };
  const auto noise = [&](const char* name, double v) {
    finite(name, v);
    if (v < 0.0) {
      throw std::invalid_argument(std::string("odom_error_") + name + "=" + Num(v) +
                                  " must be >= 0 (a standard deviation)");
    }
  };
  scale("scale", o.scale);
  scale("turn_scale", o.turn_scale);
  finite("heading_drift", o.heading_drift);
  noise("distance_noise", o.distance_noise);
  noise("turn_noise", o.turn_noise);
  noise("heading_noise", o.heading_noise);
}

OdometryError::OdometryError(const OdometryErrorOptions& options, unsigned seed)
    : o_(options), rng_(0x6f646f6dULL * 2654435761ULL + seed) {
  ValidateOdometryError(o_);
}

void OdometryError::Update(const Pose2& drive_pose, const Twist2& drive_twist) {
  const Pose2 d = minibot3d_common::Between(last_drive_, drive_pose);
  last_drive_ = drive_pose;
  const double dist = std::hypot(d.x, d.y);
  const double s = d.x < 0.0 ? -dist : dist;  // signed by the direction of travel
  double translation = 1.0 + o_.scale;
  if (o_.distance_noise > 0.0 && dist > 0.0) {
    translation += o_.distance_noise * normal_(rng_) / std::sqrt(dist);
  }
  double rotation = d.yaw * (1.0 + o_.turn_scale) + o_.heading_drift * s;
  if (o_.turn_noise > 0.0 && d.yaw != 0.0) {
    rotation += o_.turn_noise * std::sqrt(std::abs(d.yaw)) * normal_(rng_);
  }
  if (o_.heading_noise > 0.0 && dist > 0.0) {
    rotation += o_.heading_noise * std::sqrt(dist) * normal_(rng_);
  }
  pose_ = minibot3d_common::Compose(pose_, Pose2{d.x * translation, d.y * translation, rotation});
  twist_ = Twist2{drive_twist.vx * (1.0 + o_.scale), drive_twist.vy * (1.0 + o_.scale),
                  drive_twist.wz * (1.0 + o_.turn_scale) + o_.heading_drift * drive_twist.vx};
}

void OdometryError::Reset() {
  last_drive_ = Pose2{};
  pose_ = Pose2{};
  twist_ = Twist2{};
}

}  // namespace minibot3d_sim
