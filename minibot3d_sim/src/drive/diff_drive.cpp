#include "minibot3d_sim/drive/diff_drive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace minibot3d_sim {

std::array<double, 36> GazeboPoseCovariance() {
  std::array<double, 36> c{};
  c[0] = c[7] = 1e-5;
  c[14] = c[21] = c[28] = 1e12;
  c[35] = 1e-3;
  return c;
}

DiffDrive::DiffDrive(const RobotModel& robot, const DriveSettings& settings)
    : options_(robot.drive.diff_drive), kinematics_(robot) {
  if (robot.wheels.size() != 2) {
    throw std::invalid_argument("libgazebo_ros_diff_drive.so needs two wheels");
  }
  encoder_ = options_.odometry_source == "encoder";
  radius_ = options_.wheel_diameter / 2.0;
  update_period_ = options_.update_rate > 0.0 ? 1.0 / options_.update_rate : 0.0;
  cmd_timeout_ = settings.cmd_timeout;
  DriveInterface& i = interface_;
  i.robot_namespace = robot.drive.robot_namespace;
  i.command_topic = options_.command_topic;
  // publishTf false: the plugin neither advertises nor publishes odometry.
  i.odometry_topic = options_.publish_tf ? options_.odometry_topic : "";
  i.odometry_frame = options_.odometry_frame;
  i.base_frame = options_.robot_base_frame;
  i.odometry_tf = options_.publish_tf && options_.publish_odom_tf;
  i.odometry_rate = options_.update_rate;
  i.pose_covariance = GazeboPoseCovariance();
  i.wheel_tf = options_.publish_wheel_tf;
  if (options_.publish_wheel_joint_state) {
    i.joint_state_topic = "joint_states";
    i.joint_state_rate = options_.update_rate;
  }
}

void DiffDrive::OnCommand(const Twist2& command, double t) {
  cmd_v_ = command.vx;
  cmd_w_ = command.wz;
  cmd_time_ = t;
}

DriveTargets DiffDrive::Actuate(double t, double /*dt*/) {
  const double since = t - last_update_;
  if (!updated_ || since > update_period_) {
    const bool active = t - cmd_time_ <= cmd_timeout_ + 1e-12;
    const double v = active ? cmd_v_ : 0.0, w = active ? cmd_w_ : 0.0;
    const double b = options_.wheel_separation;
    const double target[2] = {v - w * b / 2.0, v + w * b / 2.0};
    const double current[2] = {measured_[0] * radius_, measured_[1] * radius_};
    const double a = options_.wheel_acceleration;
    if (a == 0.0 || std::abs(target[0] - current[0]) < 0.01 ||
        std::abs(target[1] - current[1]) < 0.01) {
      joint_targets_[0] = target[0] / radius_;
      joint_targets_[1] = target[1] / radius_;
    } else {
      const double step = a * (updated_ ? since : update_period_);
      for (int k = 0; k < 2; ++k) {
        instructed_[k] += std::clamp(target[k] - current[k], -step, step);
        joint_targets_[k] = instructed_[k] / radius_;
      }
    }
    last_update_ = updated_ ? last_update_ + update_period_ : t;
    updated_ = true;
  }
  DriveTargets out;
  out.wheel_speeds = {joint_targets_[0], joint_targets_[1]};
  out.body_twist = kinematics_(out.wheel_speeds);
  return out;
}

void DiffDrive::Observe(const DriveState& s) {
  measured_[0] = (*s.wheel_velocities)[0];
  measured_[1] = (*s.wheel_velocities)[1];
  if (!encoder_) {
    odom_pose_ = s.pose;
    odom_twist_ = s.twist;
    return;
  }
  const double b = options_.wheel_separation;
  const double sl = measured_[0] * radius_ * s.dt, sr = measured_[1] * radius_ * s.dt;
  const double ssum = sl + sr, sdiff = sr - sl;
  const double dx = ssum / 2.0 * std::cos(encoder_yaw_ + sdiff / (2.0 * b));
  const double dy = ssum / 2.0 * std::sin(encoder_yaw_ + sdiff / (2.0 * b));
  const double dth = sdiff / b;
  odom_pose_.x += dx;
  odom_pose_.y += dy;
  encoder_yaw_ += dth;
  odom_pose_.yaw = minibot3d_common::NormalizeAngle(encoder_yaw_);
  if (s.dt > 0.0) {
    odom_twist_ = Twist2{std::copysign(std::hypot(dx, dy) / s.dt, ssum), 0.0, dth / s.dt};
  }
}

void DiffDrive::Reset() {
  odom_pose_ = Pose2{};
  odom_twist_ = Twist2{};
  encoder_yaw_ = 0.0;
  instructed_[0] = instructed_[1] = 0.0;
  Stop();
}

void DiffDrive::Stop() {
  cmd_v_ = cmd_w_ = 0.0;
  cmd_time_ = -1e9;
  joint_targets_[0] = joint_targets_[1] = 0.0;
}

}  // namespace minibot3d_sim
