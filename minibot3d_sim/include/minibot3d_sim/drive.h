// The drive extension point: how a robot's velocity commands become actuator targets, and what its
// odometry says. One variant per Gazebo drive plugin (drive/*.h), as MVSim keeps one file per
// vehicle dynamics model.
//
// Lifecycle: made from the robot model (MakeDrive) → for each cmd_vel: OnCommand(twist, t) → for
// each physics step: Actuate(t, dt) before it (the wheel speed targets, or the body velocity of a
// holonomic base), Observe(state) after it (odometry) → odometry()/OdometryDue() read by the node.
// Reset() zeroes the odometry and the command. A drive never reads a clock: t is sim time.
#ifndef MINIBOT3D_SIM_DRIVE_H_
#define MINIBOT3D_SIM_DRIVE_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/robot_model.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

// What the physics is asked to do for one step.
struct DriveTargets {
  std::vector<double> wheel_speeds;  // rad/s, RobotModel::wheels order (wheeled drives)
  // A holonomic base (planar move) is moved at `body_twist` directly, its wheels (if any) idle.
  bool body_velocity = false;
  // The body twist the targets ask for without slip: what the kinematic backend integrates.
  Twist2 body_twist;
};

// What the physics did in the step just taken (true state, root frame).
struct DriveState {
  double time = 0.0;  // sim time after the step
  double dt = 0.0;
  Pose2 pose;
  Twist2 twist;  // body frame
  const std::vector<double>* wheel_positions = nullptr;   // rad, unwrapped
  const std::vector<double>* wheel_velocities = nullptr;  // rad/s
};

// Where and how the drive's odometry and commands appear on ROS (names as given; the node resolves
// them against `robot_namespace`).
struct DriveInterface {
  std::string robot_namespace;
  std::string command_topic;
  std::string odometry_topic;   // empty: no odometry published
  std::string odometry_frame;
  std::string base_frame;
  bool odometry_tf = true;      // odometry_frame -> base_frame on /tf
  double odometry_rate = 0.0;   // Hz, 0: every physics step
  std::array<double, 36> pose_covariance{};
  std::array<double, 36> twist_covariance{};
  // The controller's own extras: publish the limited command (diff_drive_controller's publish_cmd)
  // on this topic as TwistStamped; empty: none.
  std::string command_out_topic;
  // Wheel transforms (diff drive's publishWheelTF).
  bool wheel_tf = false;
  // Joint states of the wheels the drive publishes itself (diff drive's publishWheelJointState,
  // ros_control's joint_state_controller): topic and rate; empty topic: none.
  std::string joint_state_topic;
  double joint_state_rate = 0.0;
  bool joint_state_all_joints = false;  // joint_state_controller: every movable joint
};

class DrivePlugin {
 public:
  virtual ~DrivePlugin() = default;
  // The plugin's file name (libgazebo_ros_diff_drive.so, ...), for messages.
  virtual std::string name() const = 0;
  // A cmd_vel arrived at sim time t (body frame: linear x, y and angular z).
  virtual void OnCommand(const Twist2& command, double t) = 0;
  // The targets for the physics step from t to t + dt.
  virtual DriveTargets Actuate(double t, double dt) = 0;
  // The step just taken.
  virtual void Observe(const DriveState& state) = 0;
  // The odometry now (odometry_frame -> base_frame) and the body twist it reports.
  virtual Pose2 odometry_pose() const = 0;
  virtual Twist2 odometry_twist() const = 0;
  // The command the drive is executing after its own limits (what a controller's cmd_vel_out says).
  virtual Twist2 executed_command() const { return Twist2{}; }
  // Odometry and command to zero, as after a respawn.
  virtual void Reset() = 0;
  // The robot was moved by hand: forget the command (and a world-sourced odometry's history).
  virtual void Stop() = 0;
  const DriveInterface& interface() const { return interface_; }

 protected:
  DriveInterface interface_;
};

// Settings the simulator gives every drive besides the robot description.
struct DriveSettings {
  // A command older than this (s of sim time) stops drives without a timeout of their own
  // (the skid-steer and diff-drive plugins).
  double cmd_timeout = 0.5;
  // Skid-steer only: effective track of the odometry and of the command's conversion to wheel
  // speeds, as multiples of wheelSeparation (diff_drive_controller's wheel_separation_multiplier
  // on the odometry and on the command side).
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  double physics_step = 0.001;  // s
};

// The drive of `robot` (its RobotModel::drive). Throws std::invalid_argument naming what is wrong.
std::unique_ptr<DrivePlugin> MakeDrive(const RobotModel& robot, const DriveSettings& settings);

// The body twist wheel joint speeds give without slip, from the robot's true geometry: each side's
// mean rim speed (speed × the wheel's own radius), and the distance between the sides' mean
// lateral positions. What a wheeled drive's targets ask of the kinematic backend.
class WheelKinematics {
 public:
  explicit WheelKinematics(const RobotModel& robot);
  Twist2 operator()(const std::vector<double>& wheel_speeds) const;
  double track() const { return track_; }  // m between the sides

 private:
  std::vector<double> radius_;
  std::vector<bool> left_;
  double track_ = 0.0;
};

// Exact integration of a constant body twist over dt (a straight line or a circular arc; with a
// sideways component, the arc of the holonomic motion).
Pose2 IntegrateTwist(const Pose2& p, const Twist2& twist, double dt);

// Gazebo's hard-coded odometry covariance of the diff-drive and planar-move plugins.
std::array<double, 36> GazeboPoseCovariance();

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DRIVE_H_
