// libgazebo_ros_planar_move.so: a holonomic base moved at the commanded body velocity.
//
// Every physics step the body is given the last command's linear x, y and angular z (body frame),
// as the plugin sets the model's velocity; walls still stop it (the physics resolves contacts).
// A command older than cmdTimeout (or, when the plugin sets none, the simulator's cmd_timeout)
// stops it. Odometry is the true pose and velocity, published at odometryRate with Gazebo's fixed
// pose covariance.
#ifndef MINIBOT3D_SIM_DRIVE_PLANAR_MOVE_H_
#define MINIBOT3D_SIM_DRIVE_PLANAR_MOVE_H_

#include <string>

#include "minibot3d_sim/drive.h"

namespace minibot3d_sim {

class PlanarMove : public DrivePlugin {
 public:
  PlanarMove(const RobotModel& robot, const DriveSettings& settings);

  std::string name() const override { return "libgazebo_ros_planar_move.so"; }
  void OnCommand(const Twist2& command, double t) override;
  DriveTargets Actuate(double t, double dt) override;
  void Observe(const DriveState& state) override;
  Pose2 odometry_pose() const override { return odom_pose_; }
  Twist2 odometry_twist() const override { return odom_twist_; }
  void Reset() override;
  void Stop() override;

 private:
  size_t wheels_ = 0;
  double cmd_timeout_ = 0.5;
  Twist2 command_;
  double cmd_time_ = -1e9;
  Pose2 odom_pose_;
  Twist2 odom_twist_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DRIVE_PLANAR_MOVE_H_
