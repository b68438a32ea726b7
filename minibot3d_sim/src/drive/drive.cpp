#include "minibot3d_sim/drive.h"

#include <cmath>
#include <stdexcept>

#include "minibot3d_sim/drive/diff_drive.h"
#include "minibot3d_sim/drive/diff_drive_controller.h"
#include "minibot3d_sim/drive/planar_move.h"
#include "minibot3d_sim/drive/skid_steer_drive.h"

namespace minibot3d_sim {

std::unique_ptr<DrivePlugin> MakeDrive(const RobotModel& robot, const DriveSettings& settings) {
  if (!(settings.cmd_timeout > 0.0)) {
    throw std::invalid_argument("cmd_timeout must be > 0 s, got " + std::to_string(settings.cmd_timeout));
  }
  switch (robot.drive.kind) {
    case DriveKind::kSkidSteer:
      return std::make_unique<SkidSteerDrive>(robot, settings);
    case DriveKind::kDiffDrive:
      return std::make_unique<DiffDrive>(robot, settings);
    case DriveKind::kPlanarMove:
      return std::make_unique<PlanarMove>(robot, settings);
    case DriveKind::kDiffDriveController:
      return std::make_unique<DiffDriveController>(robot, settings);
  }
  throw std::invalid_argument("unknown drive");
}

WheelKinematics::WheelKinematics(const RobotModel& robot) {
  double left_y = 0.0, right_y = 0.0;
  int left = 0, right = 0;
  for (const auto& w : robot.wheels) {
    radius_.push_back(w.radius);
    left_.push_back(w.left);
    (w.left ? left_y : right_y) += w.position.y();
    ++(w.left ? left : right);
  }
  if (left > 0 && right > 0) track_ = left_y / left - right_y / right;
}

Twist2 WheelKinematics::operator()(const std::vector<double>& wheel_speeds) const {
  double left = 0.0, right = 0.0;
  int nl = 0, nr = 0;
  for (size_t i = 0; i < wheel_speeds.size() && i < radius_.size(); ++i) {
    (left_[i] ? left : right) += wheel_speeds[i] * radius_[i];
    ++(left_[i] ? nl : nr);
  }
  if (nl == 0 || nr == 0 || !(track_ > 0.0)) return Twist2{};
  left /= nl;
  right /= nr;
  return Twist2{0.5 * (left + right), 0.0, (right - left) / track_};
}

Pose2 IntegrateTwist(const Pose2& p, const Twist2& twist, double dt) {
  const double dth = twist.wz * dt;
  Pose2 d;
  if (twist.vy == 0.0) {
    if (std::abs(dth) < 1e-9) {
      d = Pose2{twist.vx * dt, 0.0, dth};
    } else {
      const double r = twist.vx / twist.wz;
      d = Pose2{r * std::sin(dth), r * (1.0 - std::cos(dth)), dth};
    }
  } else if (std::abs(dth) < 1e-9) {
    d = Pose2{twist.vx * dt, twist.vy * dt, dth};
  } else {
    // The body frame turns at wz while moving at (vx, vy) in it.
    const double s = std::sin(dth), c = 1.0 - std::cos(dth);
    d = Pose2{(twist.vx * s - twist.vy * c) / twist.wz, (twist.vx * c + twist.vy * s) / twist.wz,
              dth};
  }
  return minibot3d_common::Compose(p, d);
}

}  // namespace minibot3d_sim
