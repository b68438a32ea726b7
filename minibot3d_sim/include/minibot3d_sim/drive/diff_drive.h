// libgazebo_ros_diff_drive.so: two driven wheels, as ROS Noetic's plugin drives them.
//
// Every update period (1 / updateRate): each wheel's rim speed target v ∓ ω·b/2 from the last
// command (stopped once older than the simulator's cmd_timeout; Gazebo's plugin has no timeout),
// sent to the joint's motor as target / r, limited by wheelTorque. With wheelAcceleration a > 0 the
// plugin ramps as Gazebo's does: while both wheels are more than 1 cm/s from their targets, each
// instructed speed moves towards its target by at most a·Δt per update, Δt the time since the last
// update (from the previous instruction, not from the measured speed).
// Odometry: odometrySource world reports the true pose and the true velocity in the body frame;
// encoder integrates the wheel joints' speeds every physics step with Gazebo's midpoint formula
// (x += s̄·cos(θ + Δs/2b), y likewise, θ += Δs/b), so it drifts when the wheels slip. Covariance:
// Gazebo's fixed pose diagonal, zero twist covariance.
#ifndef MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_H_
#define MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_H_

#include <string>

#include "minibot3d_sim/drive.h"

namespace minibot3d_sim {

class DiffDrive : public DrivePlugin {
 public:
  DiffDrive(const RobotModel& robot, const DriveSettings& settings);

  std::string name() const override { return "libgazebo_ros_diff_drive.so"; }
  void OnCommand(const Twist2& command, double t) override;
  DriveTargets Actuate(double t, double dt) override;
  void Observe(const DriveState& state) override;
  Pose2 odometry_pose() const override { return odom_pose_; }
  Twist2 odometry_twist() const override { return odom_twist_; }
  void Reset() override;
  void Stop() override;

 private:
  DiffDriveOptions options_;
  WheelKinematics kinematics_;
  bool encoder_ = false;
  double radius_ = 0.0;
  double update_period_ = 0.0;
  double cmd_timeout_ = 0.5;
  double cmd_v_ = 0.0, cmd_w_ = 0.0, cmd_time_ = -1e9;
  double last_update_ = 0.0;
  bool updated_ = false;
  double instructed_[2] = {0.0, 0.0};  // rim speeds (m/s) of the acceleration ramp
  double joint_targets_[2] = {0.0, 0.0};
  double measured_[2] = {0.0, 0.0};    // joint speeds after the last step (rad/s)
  Pose2 odom_pose_;
  double encoder_yaw_ = 0.0;  // Gazebo's encoder heading is not wrapped
  Twist2 odom_twist_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_H_
