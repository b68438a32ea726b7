// Forward simulation of velocity commands for the dynamic window approach
// (Fox, Burgard & Thrun, "The dynamic window approach to collision
// avoidance", IEEE Robotics & Automation Magazine 4(1), 1997), in the form of
// base_local_planner's TrajectoryPlanner with dwa = true.
//
// The dynamic window is the set of commands reachable within one control
// period T = 1/controller_frequency from the measured velocity (v0, w0):
//   vx in [max(min_vel_x, v0 - acc_lim_x*T), min(max_vel_x, v0 + acc_lim_x*T)]
//   vth in [max(min_vel_theta, w0 - acc_lim_theta*T),
//           min(max_vel_theta, w0 + acc_lim_theta*T)]
// (with dwa = false, TrajectoryPlanner uses sim_time instead of T).  Each
// sampled command is rolled out for sim_time: the velocity ramps from (v0, w0)
// towards the command at the acceleration limits, then stays constant; poses
// are recorded every sim_granularity metres / angular_sim_granularity radians.
//
// Stopping check (Fox et al.'s "admissible velocities": v <= sqrt(2 *
// dist(v, w) * acc), i.e. the robot can stop before the nearest obstacle on
// its path).  A rollout of sim_time at constant speed does not show that
// when the stopping distance is longer than the rollout, nor the ground the
// robot covers before the next control cycle can brake.  So every trajectory
// also carries a braking tail: apply the command for one control period T,
// then brake at acc_lim_x and acc_lim_theta to a standstill.  The critics
// treat a collision anywhere on the tail like one on the rollout, so a chosen
// command always leaves a collision-free way to stop, whatever the velocity
// limits and the controller rate (by induction, as long as the world does not
// change and the base follows its acceleration limits).  The window is also
// capped at v <= 2*acc_lim_x*sim_time (and likewise for theta) so that the
// rollout at constant speed, v*sim_time, is never shorter than the stopping
// distance v^2/(2*acc_lim_x).
#ifndef MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_H_
#define MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_H_

#include <vector>

#include "minibot3d_navigation/dwa/dwa_options.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

enum class TrajectoryKind {
  kSampled,  // a command from the dynamic window
  kInPlace,  // vx = 0, |vth| >= min_in_place_vel_theta
  kStop,     // brake to a standstill at the acceleration limits
  kEscape,   // back up at escape_vel (tolerates the inscribed band)
};

const char* TrajectoryKindName(TrajectoryKind kind);

struct Trajectory {
  Twist2 command;  // the velocity command this trajectory simulates
  TrajectoryKind kind = TrajectoryKind::kSampled;
  // The forward velocity the rollout starts from (the robot's, now).
  double start_vx = 0.0;
  // Rollout over sim_time; poses[0] is the start pose, poses[i] the pose
  // i * dt later.
  std::vector<Pose2> poses;
  double dt = 0.0;
  // Braking tail: the state after applying `command` for one control period,
  // then braking at the acceleration limits until stopped.
  // braking_poses[k] is the pose braking_t0 + k * braking_dt after the start.
  std::vector<Pose2> braking_poses;
  double braking_t0 = 0.0;
  double braking_dt = 0.0;
  // Distance travelled before braking_poses.front() (metres, along the arc).
  double braking_start_distance = 0.0;
  // Total cost; negative = illegal (set by the planner from the critics).
  double cost = -1.0;

  void Clear() {
    poses.clear();
    braking_poses.clear();
    braking_start_distance = 0.0;
    dt = braking_t0 = braking_dt = 0.0;
    cost = -1.0;
  }
  const Pose2& end() const { return poses.back(); }
};

// Bounds of the sampled velocities for one control cycle.
struct VelocityWindow {
  double min_vx = 0.0;
  double max_vx = 0.0;
  double min_vth = 0.0;
  double max_vth = 0.0;
};

class TrajectoryGenerator {
 public:
  // `options` must have passed ValidateDwaOptions.
  explicit TrajectoryGenerator(const DwaOptions& options);

  // 1 / controller_frequency.
  double sim_period() const { return sim_period_; }

  // The dynamic window around `current` (see the file comment).
  VelocityWindow Window(const Twist2& current) const;

  // Fills `traj` (reusing its buffers) with the rollout and braking tail of
  // `command` from `start` at velocity `current`.
  void Generate(const Pose2& start, const Twist2& current,
                const Twist2& command, TrajectoryKind kind,
                Trajectory* traj) const;

  // Velocity after one control period of braking from `current` at the
  // acceleration limits (TrajectoryPlannerROS::stopWithAccLimits).
  Twist2 BrakingCommand(const Twist2& current) const;

  // v^2 / (2 a).
  static double StoppingDistance(double v, double acc) {
    return v * v / (2.0 * acc);
  }

  // One integration step of the unicycle at constant (v, w) for dt (heading
  // at the step's midpoint), exposed for tests and simulation.
  static Pose2 Step(const Pose2& p, double v, double w, double dt);

 private:
  DwaOptions options_;
  double sim_period_;
  double angular_granularity_;
};

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_H_
