#include "minibot3d_sim/drive/skid_steer_drive.h"

#include <algorithm>
#include <stdexcept>

namespace minibot3d_sim {

SkidSteerDrive::SkidSteerDrive(const RobotModel& robot, const DriveSettings& settings) {
  const SkidSteerDriveOptions& o = robot.drive.skid_steer;
  if (robot.wheels.size() != 4) {
    throw std::invalid_argument("libgazebo_ros_skid_steer_drive.so needs four wheels");
  }
  radius_ = o.wheel_diameter / 2.0;
  separation_ = o.wheel_separation;
  cmd_separation_ = separation_ * settings.cmd_wheel_separation_multiplier;
  odom_separation_ = separation_ * settings.odom_wheel_separation_multiplier;
  cmd_timeout_ = settings.cmd_timeout;
  for (const auto& w : robot.wheels) velocity_limits_.push_back(w.velocity_limit);
  DriveInterface& i = interface_;
  i.robot_namespace = robot.drive.robot_namespace;
  i.command_topic = o.command_topic;
  i.odometry_topic = o.odometry_topic;
  i.odometry_frame = o.odometry_frame;
  i.base_frame = o.robot_base_frame;
  i.odometry_tf = o.broadcast_tf;
  i.odometry_rate = o.update_rate;
  // Gazebo's plugin: x, y and yaw from the tags, the rest fixed by the floor.
  for (auto* cov : {&i.pose_covariance, &i.twist_covariance}) {
    (*cov)[0] = o.covariance_x;
    (*cov)[7] = o.covariance_y;
    (*cov)[14] = (*cov)[21] = (*cov)[28] = 1e12;
    (*cov)[35] = o.covariance_yaw;
  }
}

Twist2 SkidSteerDrive::TwistFromWheelSpeeds(const std::vector<double>& omega, double separation,
                                            double radius) {
  // Wheels in the plugin's order: left front, right front, left rear, right rear.
  const double left = 0.5 * (omega[0] + omega[2]) * radius;
  const double right = 0.5 * (omega[1] + omega[3]) * radius;
  return Twist2{0.5 * (left + right), 0.0, (right - left) / separation};
}

void SkidSteerDrive::OnCommand(const Twist2& command, double t) {
  cmd_v_ = command.vx;
  cmd_w_ = command.wz;
  cmd_time_ = t;
}

DriveTargets SkidSteerDrive::Actuate(double t, double /*dt*/) {
  DriveTargets out;
  out.wheel_speeds.assign(4, 0.0);
  if (t - cmd_time_ <= cmd_timeout_ + 1e-12) {
    const double left = (cmd_v_ - cmd_w_ * cmd_separation_ / 2.0) / radius_;
    const double right = (cmd_v_ + cmd_w_ * cmd_separation_ / 2.0) / radius_;
    out.wheel_speeds = {left, right, left, right};
    // The motors cannot exceed the joints' velocity limits.
    for (int i = 0; i < 4; ++i) {
      const double limit = velocity_limits_[i];
      if (limit > 0) out.wheel_speeds[i] = std::clamp(out.wheel_speeds[i], -limit, limit);
    }
  }
  out.body_twist = TwistFromWheelSpeeds(out.wheel_speeds, separation_, radius_);
  return out;
}

void SkidSteerDrive::Observe(const DriveState& s) {
  // Wheel odometry: what the encoders say, integrated exactly over the step.
  const Twist2 wheels = TwistFromWheelSpeeds(*s.wheel_velocities, odom_separation_, radius_);
  odom_twist_ = wheels;
  odom_pose_ = IntegrateTwist(odom_pose_, wheels, s.dt);
}

void SkidSteerDrive::Reset() {
  odom_pose_ = Pose2{};
  odom_twist_ = Twist2{};
  Stop();
}

void SkidSteerDrive::Stop() {
  cmd_v_ = cmd_w_ = 0.0;
  cmd_time_ = -1e9;
}

}  // namespace minibot3d_sim
