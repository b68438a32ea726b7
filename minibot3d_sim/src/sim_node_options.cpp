#include "minibot3d_sim/sim_node_options.h"

#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace minibot3d_sim {

using minibot3d_common::options::Field;
using minibot3d_common::options::Num;
using minibot3d_common::options::OptionTable;
using minibot3d_common::options::Problems;

const OptionTable<SimNodeOptions>& SimNodeOptionTable() {
  using O = SimNodeOptions;
  static const OptionTable<O> t(
      "minibot3d_sim",
      {Field("world", &O::world,
             "The world: a Gazebo SDF .world/.sdf, or a map_server floor plan .yaml (occupied "
             "pixels become walls); empty: the package's worlds/default.world."),
       Field("floorplan_wall_height", &O::floorplan_wall_height,
             "Height (m) of the walls a floor plan's occupied pixels become."),
       Field("x", &O::x, "Spawn position x of the robot's root link (m, world frame)."),
       Field("y", &O::y, "Spawn position y (m)."),
       Field("yaw", &O::yaw, "Spawn heading (rad)."),
       Field("robot_namespace", &O::robot_namespace,
             "Namespace given to every plugin of robot_description without a <robotNamespace>, "
             "as Gazebo's spawn_model does."),
       Field("robots", &O::robots,
             "Several robots: their names (a list, names separated by spaces, or a number N for "
             "robot1 .. robotN). Robot NAME's "
             "description is NAME/robot_description, its plugins' topics and services are under "
             "NAME/, its frames prefixed NAME/, its spawn pose and odometry settings in ~NAME/ "
             "(below). Empty: one robot, robot_description, no prefix."),
       Field("physics", &O::physics,
             "bullet: planar rigid body with wheel slip, torque and friction limits and wall "
             "contacts; kinematic: the commanded motion exactly, steps into obstacles refused."),
       Field("physics_step", &O::physics_step, "Fixed physics step (s of sim time), in (0, 0.02]."),
       Field("cmd_timeout", &O::cmd_timeout,
             "A command older than this (s of sim time) stops drives without a timeout of their "
             "own (the skid-steer and diff-drive plugins)."),
       Field("odom_wheel_separation_multiplier", &O::odom_wheel_separation_multiplier,
             "Skid-steer plugin: the odometry's track as a multiple of wheelSeparation "
             "(diff_drive_controller's wheel_separation_multiplier; skid-steer bases slip "
             "sideways when they turn)."),
       Field("cmd_wheel_separation_multiplier", &O::cmd_wheel_separation_multiplier,
             "Skid-steer plugin: the same multiplier on the command side, so that commanded yaw "
             "rates are achieved despite the slip."),
       Field("odom_error_scale", &O::odom_error_scale,
             "Odometry error: relative error of the distance it reports (0.02: 2 % too far, as "
             "from a wheel radius 2 % too large)."),
       Field("odom_error_turn_scale", &O::odom_error_turn_scale,
             "Odometry error: relative error of the rotation it reports (-0.02: 2 % too little, "
             "as from a track 2 % too wide)."),
       Field("odom_error_heading_drift", &O::odom_error_heading_drift,
             "Odometry error: heading bias per metre driven (rad/m; 0.0175 is 1 deg/m, as from "
             "unequal wheels; positive curves the odometry left)."),
       Field("odom_error_distance_noise", &O::odom_error_distance_noise,
             "Odometry error: standard deviation of the distance error after 1 m (m/sqrt(m)); it "
             "grows with the square root of the distance."),
       Field("odom_error_turn_noise", &O::odom_error_turn_noise,
             "Odometry error: standard deviation of the rotation error after 1 rad turned "
             "(rad/sqrt(rad))."),
       Field("odom_error_heading_noise", &O::odom_error_heading_noise,
             "Odometry error: standard deviation of the heading error after 1 m driven "
             "(rad/sqrt(m))."),
       Field("seed", &O::seed,
             "Seed of every sensor's noise and of the odometry error (one stream each)."),
       Field("real_time_factor", &O::real_time_factor,
             "Sim seconds per wall second; 0: as fast as the CPU allows."),
       Field("paused", &O::paused, "Start paused (~unpause starts time)."),
       Field("clock_period", &O::clock_period,
             "Sim time between /clock messages when free-running (s), in [physics_step, 0.1]."),
       Field("pub_clock_frequency", &O::pub_clock_frequency,
             "At most this many /clock messages per wall second (Gazebo's pub_clock_frequency)."),
       Field("world_frame", &O::world_frame,
             "Frame of the ground truth and the collision reports."),
       Field("publish_ground_truth", &O::publish_ground_truth,
             "Publish the root link's true pose and twist on ground_truth/odom (in world_frame)."),
       Field("actor_radius", &O::actor_radius,
             "Radius of the upright cylinder that stands for each of the world's <actor>s (m)."),
       Field("actor_height", &O::actor_height, "Height of each actor's cylinder (m)."),
       Field("actors_rate", &O::actors_rate,
             "Rate of ~actors, the actors' poses and velocities (Hz of sim time)."),
       Field("lockstep_quantum", &O::lockstep_quantum,
             "Lock-step: sim time between rounds (s), a whole number of physics steps."),
       Field("lockstep_timeout", &O::lockstep_timeout,
             "Lock-step: wall seconds a participant may take to acknowledge a tick before it is "
             "dropped; 0: never (a participant is dropped only when its process is gone)."),
       Field("lockstep_start_timeout", &O::lockstep_start_timeout,
             "Lock-step: wall seconds to wait for lockstep_participants before time starts "
             "without them."),
       Field("lockstep_participants", &O::lockstep_participants,
             "Lock-step: nodes (a list, or names separated by spaces) time waits for before it "
             "starts.")});
  return t;
}

void ValidateSimNodeOptions(const SimNodeOptions& o, bool lockstep) {
  Problems p("minibot3d_sim");
  p.Require(o.physics == "bullet" || o.physics == "kinematic",
            "physics='" + o.physics + "' must be bullet or kinematic");
  p.Check(o.physics_step > 0.0 && o.physics_step <= 0.02, "physics_step", o.physics_step,
          "in (0, 0.02] s");
  p.Positive("cmd_timeout", o.cmd_timeout);
  p.Positive("odom_wheel_separation_multiplier", o.odom_wheel_separation_multiplier);
  p.Positive("cmd_wheel_separation_multiplier", o.cmd_wheel_separation_multiplier);
  try {
    ValidateOdometryError(ToOdometryErrorOptions(o));
  } catch (const std::invalid_argument& e) {
    p.Require(false, e.what());
  }
  p.Finite("x", o.x);
  p.Finite("y", o.y);
  p.Finite("yaw", o.yaw);
  p.Require(o.seed >= 0, "seed=" + std::to_string(o.seed) + " must be >= 0");
  p.Check(std::isfinite(o.real_time_factor) && o.real_time_factor >= 0.0, "real_time_factor",
          o.real_time_factor, ">= 0 (0: as fast as possible)");
  p.Check(o.clock_period >= o.physics_step && o.clock_period <= 0.1, "clock_period",
          o.clock_period, "in [physics_step = " + Num(o.physics_step) + ", 0.1] s");
  p.Positive("pub_clock_frequency", o.pub_clock_frequency);
  p.Positive("floorplan_wall_height", o.floorplan_wall_height);
  p.Require(!o.world_frame.empty(), "world_frame must not be empty");
  p.Positive("actor_radius", o.actor_radius);
  p.Positive("actor_height", o.actor_height);
  p.Positive("actors_rate", o.actors_rate);
  p.Positive("lockstep_quantum", o.lockstep_quantum);
  p.Check(std::isfinite(o.lockstep_timeout) && o.lockstep_timeout >= 0.0, "lockstep_timeout",
          o.lockstep_timeout, ">= 0 wall s (0: never drop a participant that is alive)");
  p.Positive("lockstep_start_timeout", o.lockstep_start_timeout);
  if (lockstep && o.physics_step > 0.0 && o.lockstep_quantum > 0.0) {
    const double q = o.lockstep_quantum / o.physics_step;
    p.Require(std::fabs(q - std::round(q)) <= 1e-6,
              "lockstep_quantum=" + Num(o.lockstep_quantum) +
                  " must be a whole number of physics_step=" + Num(o.physics_step));
  }
  p.ThrowIfAny();
}

const OptionTable<RobotNodeOptions>& RobotNodeOptionTable() {
  using R = RobotNodeOptions;
  static const OptionTable<R> t(
      "minibot3d_sim",
      {Field("x", &R::x, "Spawn position x of the robot's root link (m, world frame)."),
       Field("y", &R::y, "Spawn position y (m)."),
       Field("yaw", &R::yaw, "Spawn heading (rad)."),
       Field("odom_wheel_separation_multiplier", &R::odom_wheel_separation_multiplier,
             "Skid-steer plugin: the odometry's track as a multiple of wheelSeparation."),
       Field("cmd_wheel_separation_multiplier", &R::cmd_wheel_separation_multiplier,
             "Skid-steer plugin: the same on the command side."),
       Field("odom_error_scale", &R::odom_error_scale, "Odometry error: distance scale."),
       Field("odom_error_turn_scale", &R::odom_error_turn_scale, "Odometry error: rotation scale."),
       Field("odom_error_heading_drift", &R::odom_error_heading_drift,
             "Odometry error: heading bias per metre (rad/m)."),
       Field("odom_error_distance_noise", &R::odom_error_distance_noise,
             "Odometry error: distance noise after 1 m (m/sqrt(m))."),
       Field("odom_error_turn_noise", &R::odom_error_turn_noise,
             "Odometry error: rotation noise after 1 rad (rad/sqrt(rad))."),
       Field("odom_error_heading_noise", &R::odom_error_heading_noise,
             "Odometry error: heading noise after 1 m (rad/sqrt(m)).")});
  return t;
}

RobotNodeOptions RobotDefaults(const SimNodeOptions& o) {
  RobotNodeOptions r;
  r.x = o.x;
  r.y = o.y;
  r.yaw = o.yaw;
  r.odom_wheel_separation_multiplier = o.odom_wheel_separation_multiplier;
  r.cmd_wheel_separation_multiplier = o.cmd_wheel_separation_multiplier;
  r.odom_error_scale = o.odom_error_scale;
  r.odom_error_turn_scale = o.odom_error_turn_scale;
  r.odom_error_heading_drift = o.odom_error_heading_drift;
  r.odom_error_distance_noise = o.odom_error_distance_noise;
  r.odom_error_turn_noise = o.odom_error_turn_noise;
  r.odom_error_heading_noise = o.odom_error_heading_noise;
  return r;
}

RobotOptions ToRobotOptions(const std::string& name, const RobotNodeOptions& r) {
  Problems p("minibot3d_sim: robot " + name);
  p.Finite("x", r.x);
  p.Finite("y", r.y);
  p.Finite("yaw", r.yaw);
  p.Positive("odom_wheel_separation_multiplier", r.odom_wheel_separation_multiplier);
  p.Positive("cmd_wheel_separation_multiplier", r.cmd_wheel_separation_multiplier);
  RobotOptions o;
  o.name = name;
  o.spawn = Pose2{r.x, r.y, r.yaw};
  o.odom_wheel_separation_multiplier = r.odom_wheel_separation_multiplier;
  o.cmd_wheel_separation_multiplier = r.cmd_wheel_separation_multiplier;
  o.odom_error.scale = r.odom_error_scale;
  o.odom_error.turn_scale = r.odom_error_turn_scale;
  o.odom_error.heading_drift = r.odom_error_heading_drift;
  o.odom_error.distance_noise = r.odom_error_distance_noise;
  o.odom_error.turn_noise = r.odom_error_turn_noise;
  o.odom_error.heading_noise = r.odom_error_heading_noise;
  try {
    ValidateOdometryError(o.odom_error);
  } catch (const std::invalid_argument& e) {
    p.Require(false, e.what());
  }
  p.ThrowIfAny();
  return o;
}

std::string RobotNameProblem(const std::string& name) {
  if (name.empty()) return "a robot's name must not be empty";
  const bool first_ok = std::isalpha(static_cast<unsigned char>(name[0]));
  bool rest_ok = true;
  for (char c : name) {
    rest_ok &= std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  }
  if (!first_ok || !rest_ok) {
    return "robot name '" + name + "' is not a ROS name of one level (a letter, then letters, "
           "digits or '_')";
  }
  return "";
}

OdometryErrorOptions ToOdometryErrorOptions(const SimNodeOptions& o) {
  OdometryErrorOptions e;
  e.scale = o.odom_error_scale;
  e.turn_scale = o.odom_error_turn_scale;
  e.heading_drift = o.odom_error_heading_drift;
  e.distance_noise = o.odom_error_distance_noise;
  e.turn_noise = o.odom_error_turn_noise;
  e.heading_noise = o.odom_error_heading_noise;
  return e;
}

SimulatorOptions ToSimulatorOptions(const SimNodeOptions& o) {
  SimulatorOptions s;
  s.physics = o.physics;
  s.physics_step = o.physics_step;
  s.cmd_timeout = o.cmd_timeout;
  s.spawn = Pose2{o.x, o.y, o.yaw};
  s.seed = static_cast<unsigned>(o.seed);
  s.odom_wheel_separation_multiplier = o.odom_wheel_separation_multiplier;
  s.cmd_wheel_separation_multiplier = o.cmd_wheel_separation_multiplier;
  s.odom_error = ToOdometryErrorOptions(o);
  s.actor_radius = o.actor_radius;
  s.actor_height = o.actor_height;
  return s;
}

}  // namespace minibot3d_sim
