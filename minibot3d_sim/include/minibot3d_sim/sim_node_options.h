// The simulator node's parameters (~name): one options struct read and validated through one
// option table, which also writes docs/parameters/simulator.md. ROS-free, so the docs and the
// tests need no master.
#ifndef MINIBOT3D_SIM_SIM_NODE_OPTIONS_H_
#define MINIBOT3D_SIM_SIM_NODE_OPTIONS_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_sim/simulator.h"

namespace minibot3d_sim {

struct SimNodeOptions {
  // The world and the robot.
  std::string world;  // empty: the package's worlds/default.world
  double floorplan_wall_height = 1.0;
  double x = 0.0, y = 0.0, yaw = 0.0;  // spawn pose of the robot's root link
  std::string robot_namespace = "/";   // given to every plugin without <robotNamespace>
  std::vector<std::string> robots;     // several robots' names; empty: one robot, unnamed
  // Physics and time.
  std::string physics = "bullet";
  double physics_step = 0.001;
  double cmd_timeout = 0.5;
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  // The odometry error (OdometryErrorOptions' fields).
  double odom_error_scale = 0.0;
  double odom_error_turn_scale = 0.0;
  double odom_error_heading_drift = 0.0;
  double odom_error_distance_noise = 0.0;
  double odom_error_turn_noise = 0.0;
  double odom_error_heading_noise = 0.0;
  int seed = 1;
  double real_time_factor = 1.0;
  bool paused = false;
  double clock_period = 0.005;
  double pub_clock_frequency = 1000.0;
  // Extras beyond Gazebo's plugins.
  std::string world_frame = "world";
  bool publish_ground_truth = true;
  double actor_radius = 0.25;
  double actor_height = 1.8;
  double actors_rate = 20.0;
  // Lock-step time (when /use_lockstep is true).
  double lockstep_quantum = 0.005;
  double lockstep_timeout = 0.0;  // 0: a participant is dropped only when its process is gone
  double lockstep_start_timeout = 60.0;
  std::vector<std::string> lockstep_participants;
};

const minibot3d_common::options::OptionTable<SimNodeOptions>& SimNodeOptionTable();

// One robot of several (~NAME/...): its spawn pose, odometry calibration and error. The node's own
// values of the same names are the defaults.
struct RobotNodeOptions {
  double x = 0.0, y = 0.0, yaw = 0.0;
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  double odom_error_scale = 0.0;
  double odom_error_turn_scale = 0.0;
  double odom_error_heading_drift = 0.0;
  double odom_error_distance_noise = 0.0;
  double odom_error_turn_noise = 0.0;
  double odom_error_heading_noise = 0.0;
};

const minibot3d_common::options::OptionTable<RobotNodeOptions>& RobotNodeOptionTable();
// The node's values as a robot's defaults.
RobotNodeOptions RobotDefaults(const SimNodeOptions& options);
// Throws std::invalid_argument naming the robot and every bad value.
RobotOptions ToRobotOptions(const std::string& name, const RobotNodeOptions& options);
// A robot's name must be a ROS name of one level ("robot1", not "a/b" or "1a"); the problem, or
// empty.
std::string RobotNameProblem(const std::string& name);

// Throws std::invalid_argument naming every bad value (lockstep: whether lock-step is on, which
// adds the quantum's checks).
void ValidateSimNodeOptions(const SimNodeOptions& options, bool lockstep);

OdometryErrorOptions ToOdometryErrorOptions(const SimNodeOptions& options);
SimulatorOptions ToSimulatorOptions(const SimNodeOptions& options);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SIM_NODE_OPTIONS_H_
