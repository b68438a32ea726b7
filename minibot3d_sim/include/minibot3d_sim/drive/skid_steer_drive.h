// libgazebo_ros_skid_steer_drive.so: four wheels, both of a side turning alike.
//
// Command: each side's rim speed v ∓ ω·b/2 (b = wheelSeparation × the simulator's
// cmd_wheel_separation_multiplier), as joint speeds (rim speed / r) clamped to the joints' URDF
// velocity limits, every physics step; a command older than the simulator's cmd_timeout stops it.
// Odometry: unlike Gazebo's plugin, which reports the true pose, the wheel joints' speeds
// integrated exactly over each step (a straight line or an arc) with the track b × the simulator's
// odom_wheel_separation_multiplier: it drifts when the wheels slip, as a real skid-steer base's.
#ifndef MINIBOT3D_SIM_DRIVE_SKID_STEER_DRIVE_H_
#define MINIBOT3D_SIM_DRIVE_SKID_STEER_DRIVE_H_

#include <string>
#include <vector>

#include "minibot3d_sim/drive.h"

namespace minibot3d_sim {

class SkidSteerDrive : public DrivePlugin {
 public:
  SkidSteerDrive(const RobotModel& robot, const DriveSettings& settings);

  std::string name() const override { return "libgazebo_ros_skid_steer_drive.so"; }
  void OnCommand(const Twist2& command, double t) override;
  DriveTargets Actuate(double t, double dt) override;
  void Observe(const DriveState& state) override;
  Pose2 odometry_pose() const override { return odom_pose_; }
  Twist2 odometry_twist() const override { return odom_twist_; }
  void Reset() override;
  void Stop() override;

  // Each side's speed (mean of its wheels) as a body twist, for a track and radius.
  static Twist2 TwistFromWheelSpeeds(const std::vector<double>& omega, double separation,
                                     double radius);

 private:
  double radius_ = 0.0;
  double separation_ = 0.0;       // the plugin's wheelSeparation
  double cmd_separation_ = 0.0;   // × cmd multiplier
  double odom_separation_ = 0.0;  // × odom multiplier
  double cmd_timeout_ = 0.5;
  std::vector<double> velocity_limits_;
  double cmd_v_ = 0.0, cmd_w_ = 0.0, cmd_time_ = -1e9;
  Pose2 odom_pose_;
  Twist2 odom_twist_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DRIVE_SKID_STEER_DRIVE_H_
