#include "minibot3d_sim/drive/planar_move.h"

namespace minibot3d_sim {

PlanarMove::PlanarMove(const RobotModel& robot, const DriveSettings& settings) {
  const PlanarMoveOptions& o = robot.drive.planar_move;
  wheels_ = robot.wheels.size();
  cmd_timeout_ = o.cmd_timeout >= 0.0 ? o.cmd_timeout : settings.cmd_timeout;
  DriveInterface& i = interface_;
  i.robot_namespace = robot.drive.robot_namespace;
  i.command_topic = o.command_topic;
  i.odometry_topic = o.odometry_rate > 0.0 ? o.odometry_topic : "";
  i.odometry_frame = o.odometry_frame;
  i.base_frame = o.robot_base_frame;
  i.odometry_tf = o.odometry_rate > 0.0;
  i.odometry_rate = o.odometry_rate;
  i.pose_covariance = GazeboPoseCovariance();
}

void PlanarMove::OnCommand(const Twist2& command, double t) {
  command_ = command;
  cmd_time_ = t;
}

DriveTargets PlanarMove::Actuate(double t, double /*dt*/) {
  DriveTargets out;
  out.wheel_speeds.assign(wheels_, 0.0);
  out.body_velocity = true;
  if (t - cmd_time_ <= cmd_timeout_ + 1e-12) out.body_twist = command_;
  return out;
}

void PlanarMove::Observe(const DriveState& s) {
  odom_pose_ = s.pose;
  odom_twist_ = s.twist;
}

void PlanarMove::Reset() {
  odom_pose_ = Pose2{};
  odom_twist_ = Twist2{};
  Stop();
}

void PlanarMove::Stop() {
  command_ = Twist2{};
  cmd_time_ = -1e9;
}

}  // namespace minibot3d_sim
