// gazebo_ros_control with ros_controllers' diff_drive_controller/DiffDriveController: any number
// of wheels per side, configured on the parameter server as on a real base.
//
// Every control period (libgazebo_ros_control.so's controlPeriod, else every physics step), as the
// controller's update() does:
//   1. odometry from the wheel joints' positions (each side's mean × its radius; radii and
//      separation × their multipliers): Δs_l, Δs_r → linear = (Δs_r + Δs_l)/2,
//      angular = (Δs_r − Δs_l)/separation, integrated exactly on an arc (second-order Runge–Kutta
//      when |angular| < 1e-6); the reported twist is the mean of the last
//      velocity_rolling_window_size estimates. open_loop integrates the limited command instead.
//   2. the command, zero once older than cmd_vel_timeout, limited per axis in SpeedLimiter's order
//      jerk → acceleration → velocity (an unset minimum is −maximum);
//   3. wheel speeds ω_l = (v − ω·s/2)/r_l and ω_r = (v + ω·s/2)/r_r to every joint of a side.
// The velocity joints are driven by the URDF's effort limits, as DefaultRobotHWSim drives them.
#ifndef MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_CONTROLLER_H_
#define MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_CONTROLLER_H_

#include <deque>
#include <string>

#include "minibot3d_sim/drive.h"

namespace minibot3d_sim {

// ros_controllers' SpeedLimiter for one axis.
struct SpeedLimiter {
  bool has_velocity_limits = false, has_acceleration_limits = false, has_jerk_limits = false;
  double min_velocity = 0.0, max_velocity = 0.0;
  double min_acceleration = 0.0, max_acceleration = 0.0;
  double min_jerk = 0.0, max_jerk = 0.0;
  // v: the wanted value; v0, v1: the last two limited values; dt: the control period.
  double Limit(double v, double v0, double v1, double dt) const;
};

class DiffDriveController : public DrivePlugin {
 public:
  DiffDriveController(const RobotModel& robot, const DriveSettings& settings);

  std::string name() const override { return "diff_drive_controller/DiffDriveController"; }
  void OnCommand(const Twist2& command, double t) override;
  DriveTargets Actuate(double t, double dt) override;
  void Observe(const DriveState& state) override;
  Pose2 odometry_pose() const override { return odom_pose_; }
  Twist2 odometry_twist() const override { return odom_twist_; }
  Twist2 executed_command() const override { return Twist2{last0_.vx, 0.0, last0_.wz}; }
  void Reset() override;
  void Stop() override;

 private:
  void UpdateOdometry(double t);
  void Integrate(double linear, double angular);

  DiffDriveControllerOptions o_;
  WheelKinematics kinematics_;
  size_t per_side_ = 0;
  double separation_ = 0.0, left_radius_ = 0.0, right_radius_ = 0.0;
  double period_ = 0.0;  // 0: every physics step
  SpeedLimiter linear_, angular_;
  Twist2 command_;
  double cmd_time_ = -1e9;
  Twist2 last0_, last1_;  // the last two limited commands
  double last_update_ = 0.0;
  bool started_ = false;
  double wheels_[2] = {0.0, 0.0};  // targets per side (rad/s)
  std::vector<double> positions_;  // joint positions after the last step
  // Odometry state.
  bool odom_started_ = false;
  double odom_time_ = 0.0;
  double left_old_ = 0.0, right_old_ = 0.0;
  double heading_ = 0.0;
  std::deque<double> linear_window_, angular_window_;
  Pose2 odom_pose_;
  Twist2 odom_twist_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DRIVE_DIFF_DRIVE_CONTROLLER_H_
