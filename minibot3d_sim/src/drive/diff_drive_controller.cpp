#include "minibot3d_sim/drive/diff_drive_controller.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace minibot3d_sim {
namespace {

SpeedLimiter MakeLimiter(bool hv, bool ha, bool hj, double max_v, double min_v, double max_a,
                         double min_a, double max_j, double min_j) {
  SpeedLimiter l;
  l.has_velocity_limits = hv;
  l.has_acceleration_limits = ha;
  l.has_jerk_limits = hj;
  l.max_velocity = max_v;
  l.min_velocity = std::isnan(min_v) ? -max_v : min_v;
  l.max_acceleration = max_a;
  l.min_acceleration = std::isnan(min_a) ? -max_a : min_a;
  l.max_jerk = max_j;
  l.min_jerk = std::isnan(min_j) ? -max_j : min_j;
  return l;
}

double Mean(const std::deque<double>& d) {
  return d.empty() ? 0.0 : std::accumulate(d.begin(), d.end(), 0.0) / static_cast<double>(d.size());
}

}  // namespace

double SpeedLimiter::Limit(double v, double v0, double v1, double dt) const {
  if (has_jerk_limits) {
    const double dv = v - v0, dv0 = v0 - v1;
    const double dt2 = 2.0 * dt * dt;
    const double da = std::clamp(dv - dv0, min_jerk * dt2, max_jerk * dt2);
    v = v0 + dv0 + da;
  }
  if (has_acceleration_limits) {
    v = v0 + std::clamp(v - v0, min_acceleration * dt, max_acceleration * dt);
  }
  if (has_velocity_limits) v = std::clamp(v, min_velocity, max_velocity);
  return v;
}

DiffDriveController::DiffDriveController(const RobotModel& robot, const DriveSettings& settings)
    : o_(robot.drive.controller), kinematics_(robot) {
  per_side_ = o_.left_wheel.size();
  if (robot.wheels.size() != 2 * per_side_ || per_side_ == 0) {
    throw std::invalid_argument("diff_drive_controller: the wheel lists do not match the model");
  }
  separation_ = o_.wheel_separation * o_.wheel_separation_multiplier;
  // wheel_radius_multiplier, when set, overrides both sides' (the parser leaves the per-side ones
  // at 1 then); it multiplies the per-side ones otherwise, which are 1 unless given.
  left_radius_ = o_.wheel_radius * o_.wheel_radius_multiplier * o_.left_wheel_radius_multiplier;
  right_radius_ = o_.wheel_radius * o_.wheel_radius_multiplier * o_.right_wheel_radius_multiplier;
  period_ = robot.drive.ros_control.control_period > 0.0 ? robot.drive.ros_control.control_period
                                                          : settings.physics_step;
  linear_ = MakeLimiter(o_.linear_has_velocity_limits, o_.linear_has_acceleration_limits,
                        o_.linear_has_jerk_limits, o_.linear_max_velocity, o_.linear_min_velocity,
                        o_.linear_max_acceleration, o_.linear_min_acceleration,
                        o_.linear_max_jerk, o_.linear_min_jerk);
  angular_ = MakeLimiter(o_.angular_has_velocity_limits, o_.angular_has_acceleration_limits,
                         o_.angular_has_jerk_limits, o_.angular_max_velocity,
                         o_.angular_min_velocity, o_.angular_max_acceleration,
                         o_.angular_min_acceleration, o_.angular_max_jerk, o_.angular_min_jerk);
  const std::string ns = robot.drive.robot_namespace;
  const std::string c = robot.drive.controller_name;
  DriveInterface& i = interface_;
  i.robot_namespace = ns;
  i.command_topic = c + "/cmd_vel";
  i.odometry_topic = c + "/odom";
  i.odometry_frame = o_.odom_frame_id;
  i.base_frame = o_.base_frame_id;
  i.odometry_tf = o_.enable_odom_tf;
  i.odometry_rate = o_.publish_rate;
  for (int k = 0; k < 6; ++k) {
    i.pose_covariance[7 * k] = std::stod(o_.pose_covariance_diagonal[k]);
    i.twist_covariance[7 * k] = std::stod(o_.twist_covariance_diagonal[k]);
  }
  if (o_.publish_cmd) i.command_out_topic = c + "/cmd_vel_out";
  if (!robot.drive.joint_state_controller_name.empty() &&
      robot.drive.joint_state_controller.publish_rate > 0.0) {
    i.joint_state_topic = "joint_states";
    i.joint_state_rate = robot.drive.joint_state_controller.publish_rate;
    i.joint_state_all_joints = true;
  }
  positions_.assign(robot.wheels.size(), 0.0);
}

void DiffDriveController::OnCommand(const Twist2& command, double t) {
  command_ = command;
  cmd_time_ = t;
}

void DiffDriveController::Integrate(double linear, double angular) {
  if (std::abs(angular) < 1e-6) {
    const double direction = heading_ + angular * 0.5;
    odom_pose_.x += linear * std::cos(direction);
    odom_pose_.y += linear * std::sin(direction);
    heading_ += angular;
  } else {
    const double heading_old = heading_;
    const double r = linear / angular;
    heading_ += angular;
    odom_pose_.x += r * (std::sin(heading_) - std::sin(heading_old));
    odom_pose_.y += -r * (std::cos(heading_) - std::cos(heading_old));
  }
  odom_pose_.yaw = minibot3d_common::NormalizeAngle(heading_);
}

void DiffDriveController::UpdateOdometry(double t) {
  if (!odom_started_) {
    odom_started_ = true;
    odom_time_ = t;
    double l = 0.0, r = 0.0;
    for (size_t k = 0; k < per_side_; ++k) {
      l += positions_[k];
      r += positions_[per_side_ + k];
    }
    left_old_ = l / per_side_ * left_radius_;
    right_old_ = r / per_side_ * right_radius_;
    return;
  }
  const double dt = t - odom_time_;
  if (o_.open_loop) {
    Integrate(last0_.vx * dt, last0_.wz * dt);
    odom_twist_ = Twist2{last0_.vx, 0.0, last0_.wz};
    odom_time_ = t;
    return;
  }
  double l = 0.0, r = 0.0;
  for (size_t k = 0; k < per_side_; ++k) {
    l += positions_[k];
    r += positions_[per_side_ + k];
  }
  const double left = l / per_side_ * left_radius_, right = r / per_side_ * right_radius_;
  const double dl = left - left_old_, dr = right - right_old_;
  left_old_ = left;
  right_old_ = right;
  const double linear = (dr + dl) * 0.5, angular = (dr - dl) / separation_;
  Integrate(linear, angular);
  if (dt < 1e-4) return;  // too short a period to estimate the velocity from
  odom_time_ = t;
  linear_window_.push_back(linear / dt);
  angular_window_.push_back(angular / dt);
  while (static_cast<int>(linear_window_.size()) > o_.velocity_rolling_window_size) {
    linear_window_.pop_front();
    angular_window_.pop_front();
  }
  odom_twist_ = Twist2{Mean(linear_window_), 0.0, Mean(angular_window_)};
}

DriveTargets DiffDriveController::Actuate(double t, double /*dt*/) {
  if (!started_ || t - last_update_ >= period_ - 1e-9) {
    UpdateOdometry(t);
    Twist2 wanted = t - cmd_time_ <= o_.cmd_vel_timeout + 1e-12 ? command_ : Twist2{};
    const double dt = period_;
    Twist2 limited;
    limited.vx = linear_.Limit(wanted.vx, last0_.vx, last1_.vx, dt);
    limited.wz = angular_.Limit(wanted.wz, last0_.wz, last1_.wz, dt);
    last1_ = last0_;
    last0_ = limited;
    wheels_[0] = (limited.vx - limited.wz * separation_ / 2.0) / left_radius_;
    wheels_[1] = (limited.vx + limited.wz * separation_ / 2.0) / right_radius_;
    last_update_ = started_ ? last_update_ + period_ : t;
    started_ = true;
  }
  DriveTargets out;
  out.wheel_speeds.assign(2 * per_side_, 0.0);
  for (size_t k = 0; k < per_side_; ++k) {
    out.wheel_speeds[k] = wheels_[0];
    out.wheel_speeds[per_side_ + k] = wheels_[1];
  }
  if (per_side_ == 1) {
    out.body_twist = kinematics_(out.wheel_speeds);
  } else {
    // Several wheels a side skid when the base turns: no-slip kinematics cannot say how far it
    // turns. The wheels roll at their true radii; the base turns about the controller's effective
    // track (wheel_separation x wheel_separation_multiplier, the skid calibration), as the
    // skid-steer plugin's base turns about its wheelSeparation, and as Bullet's slipping wheels
    // turn it when the multiplier is calibrated.
    const Twist2 rolled = kinematics_(out.wheel_speeds);
    const double side_difference = rolled.wz * kinematics_.track();  // right - left rim speed
    out.body_twist = Twist2{rolled.vx, 0.0, side_difference / separation_};
  }
  return out;
}

void DiffDriveController::Observe(const DriveState& s) { positions_ = *s.wheel_positions; }

void DiffDriveController::Reset() {
  odom_pose_ = Pose2{};
  odom_twist_ = Twist2{};
  heading_ = 0.0;
  odom_started_ = false;
  linear_window_.clear();
  angular_window_.clear();
  Stop();
}

void DiffDriveController::Stop() {
  command_ = Twist2{};
  cmd_time_ = -1e9;
  last0_ = last1_ = Twist2{};
  wheels_[0] = wheels_[1] = 0.0;
}

}  // namespace minibot3d_sim
