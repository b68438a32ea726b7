// Parameters of the dynamic-window local planner (dwa_planner.h).
//
// Names and defaults are base_local_planner's TrajectoryPlannerROS ones, so a
// move_base YAML written for TrajectoryPlannerROS loads parameter by parameter
// through DwaOptionTable().  The DWAPlannerROS spellings that mean the same thing
// for a differential / skid-steer base are accepted as aliases
// (DwaAliasOptionTable()).  Parameters of either planner that only matter for holonomic
// robots or for ROS plumbing are accepted and ignored (DwaIgnoredOptionNames());
// holonomic_robot itself must stay false: minibot3d is a skid-steer.
#ifndef MINIBOT3D_NAVIGATION_DWA_DWA_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_DWA_DWA_OPTIONS_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

struct DwaOptions {
  // --- Robot configuration (TrajectoryPlannerROS) ---
  double acc_lim_x = 2.5;      // m/s^2
  double acc_lim_y = 2.5;      // m/s^2, accepted for YAML compatibility, unused
  double acc_lim_theta = 3.2;  // rad/s^2 (alias acc_lim_th)
  double max_vel_x = 0.5;      // m/s
  // m/s; may be negative (sampled windows then include reversing).
  double min_vel_x = 0.1;
  // rad/s.  Aliases max_rot_vel / max_rotational_vel set max_vel_theta = v
  // and min_vel_theta = -v (DWAPlannerROS bounds |vtheta| symmetrically).
  double max_vel_theta = 1.0;
  // rad/s, the most negative (clockwise) rotational velocity.  NOTE: in
  // DWAPlannerROS (melodic+) `min_vel_theta` means the smallest |vtheta|;
  // that is min_in_place_vel_theta here, and a positive min_vel_theta is
  // rejected by ValidateDwaOptions with that hint.
  double min_vel_theta = -1.0;
  // rad/s, smallest |vtheta| of an in-place rotation (the base cannot turn
  // slower on the spot).  Aliases min_rot_vel, min_in_place_rotational_vel.
  double min_in_place_vel_theta = 0.4;
  // m/s, the backing-up speed of the escape trajectory (<= 0; 0 disables
  // escaping).  Alias backup_vel (deprecated in TrajectoryPlannerROS).
  double escape_vel = -0.1;
  // Must be false: the robot cannot move sideways.  (ROS defaults to true.)
  bool holonomic_robot = false;

  // --- Goal tolerance ---
  double yaw_goal_tolerance = 0.05;  // rad
  double xy_goal_tolerance = 0.10;   // m
  // Once within xy_goal_tolerance, stay "in position" and only rotate, even
  // if rotating drifts the robot back out of the tolerance.
  bool latch_xy_goal_tolerance = false;
  // Below these speeds the robot counts as stopped (goal reached, start of
  // the final in-place rotation).  DWAPlannerROS names; alias
  // theta_stopped_vel for rot_stopped_vel.
  double trans_stopped_vel = 0.1;  // m/s
  double rot_stopped_vel = 0.1;    // rad/s

  // --- Forward simulation ---
  double sim_time = 1.0;         // s, length of each rollout
  double sim_granularity = 0.025;  // m between checked poses
  // rad between checked poses; < 0 (default): same as sim_granularity.
  double angular_sim_granularity = -1.0;
  int vx_samples = 3;       // >= 1
  int vtheta_samples = 20;  // >= 1 (alias vth_samples)
  // Hz of the control loop (move_base's parameter).  1/controller_frequency
  // is the period the dynamic window and the stopping check are built on.
  double controller_frequency = 20.0;

  // --- Trajectory scoring ---
  // cost = path_distance_bias * path_dist + goal_distance_bias * goal_dist
  //        + occdist_scale * max_footprint_cost
  // path_dist / goal_dist in cells, or in metres when meter_scoring (then, as
  // TrajectoryPlannerROS, occdist_scale is multiplied by the resolution too).
  double path_distance_bias = 0.6;  // (TrajectoryPlannerROS alias pdist_scale)
  double goal_distance_bias = 0.8;  // (alias gdist_scale)
  double occdist_scale = 0.01;
  // m: an in-place rotation is picked by the goal distance at this point in
  // front of the rotated robot.
  double heading_lookahead = 0.325;
  bool dwa = true;  // sample the window reachable in one period (alias use_dwa)
  bool meter_scoring = false;
  // m the robot must travel before in-place rotation direction flips and
  // forward/backward flips are allowed again.
  double oscillation_reset_dist = 0.05;
  // Escaping (backing up) ends after this much travel / rotation.
  double escape_reset_dist = 0.10;
  double escape_reset_theta = kPi / 4.0;
  bool prune_plan = true;  // drop the part of the plan the robot has passed

  // --- Not ROS parameters ---
  // rad: if the plan ahead lies further than this off the robot's heading,
  // stop and rotate in place towards it before following it (back to normal
  // following below an eighth of this angle); at creeping speed or stopped,
  // already beyond a quarter of it.  >= pi disables.
  double rotate_to_path_angle = kPi / 2.0;
  // m/s^2: sampled commands keep |vx * vtheta| (the centripetal acceleration
  // of the arc) at or below this; 0 (default, as TrajectoryPlannerROS) means
  // no limit.  A skid-steer base turns by sliding its wheels sideways, and the
  // harder it corners the less its yaw rate follows the command: minibot3d in
  // the simulator over-rotates by 3 % at 1 m/s^2, 8 % at 1.5 and 18 % at 2, so
  // arcs flown above the limit are tighter than the rollouts predicted and
  // wheel odometry under-reports the turn.  Fast commands then have to slow
  // down before they turn hard, as a car does.
  double max_centripetal_acc = 0.0;
  // m/s (not in TrajectoryPlannerROS): the speed from which the footprint's
  // outline keeps the whole inscribed band (one inscribed radius) from
  // obstacles; below it the margin shrinks linearly, to none at creeping
  // speed (max(min_vel_x, |escape_vel|)), so the robot drives through a gap
  // as fast as the room it has allows instead of creeping as soon as the
  // band is entered.  The margin is for slip and for obstacles the costmap
  // shows late, both of which grow with the speed actually driven, so it is
  // a speed, not a fraction of max_vel_x (min(this, max_vel_x) is used).
  double full_margin_vel = 0.5;

  // --- Moving obstacles (moving_obstacle_critic.h; not in TrajectoryPlannerROS) ---
  // Weight of the proximity cost (0..1) to the predicted obstacles, in the
  // units of the other terms (cells, or metres with meter_scoring, times the
  // biases); 0 keeps only the legality check.
  double moving_obstacle_scale = 40.0;
  // s ahead that predictions at constant velocity are trusted.
  double moving_obstacle_horizon = 2.0;
  // m: a trajectory whose footprint comes nearer than this to a predicted
  // obstacle (nearer than standing still would) is illegal.
  double moving_obstacle_margin = 0.05;
  // m/s: how fast an obstacle may stray from its constant-velocity
  // prediction; the margin grows by this times the prediction's time
  // (0: the prediction is trusted).
  double moving_obstacle_deviation = 0.0;
  // m: nearer than this to a predicted obstacle costs (proxemics' intimate
  // zone, Hall 1966, is 0.45 m).
  double personal_distance = 0.45;
  // s the robot stands yielding before it may back away from an obstacle
  // that stopped within moving_obstacle_margin (a standoff).
  double moving_obstacle_wait = 2.0;
};

// Throws std::invalid_argument whose message lists every offending parameter
// with its value, e.g. "invalid DWA local planner (TrajectoryPlannerROS)
// parameters: min_vel_x=0.6 > max_vel_x=0.5; vx_samples=0 must be >= 1".
void ValidateDwaOptions(const DwaOptions& options);

// The canonical options (TrajectoryPlannerROS names), each with its
// documentation.  Setting does not validate ranges: call ValidateDwaOptions()
// after setting them all.
const minibot3d_common::options::OptionTable<DwaOptions>& DwaOptionTable();

// The other spellings of the same fields (older TrajectoryPlannerROS names,
// DWAPlannerROS names).  The symmetric rotation limits (IsSymmetricRotationName)
// set max_vel_theta here; ApplySymmetricRotation then sets min_vel_theta.
const minibot3d_common::options::OptionTable<DwaOptions>& DwaAliasOptionTable();

// max_rot_vel (DWAPlannerROS up to kinetic) and max_rotational_vel
// (TrajectoryPlannerROS): one bound |vtheta| <= v.
bool IsSymmetricRotationName(const std::string& name);
// min_vel_theta = -max_vel_theta, after a symmetric name has set max_vel_theta.
void ApplySymmetricRotation(DwaOptions* options);

// Sets the option called `name` (TrajectoryPlannerROS / DWAPlannerROS name or
// alias) from its text form ("0.25", "20", "true").  Ignored names (see
// DwaIgnoredOptionNames) are accepted and change nothing.  Throws
// std::invalid_argument for an unknown name or text that does not parse as the
// option's type.  Does not validate ranges: call ValidateDwaOptions() after
// setting them all.
void SetDwaOption(const std::string& name, const std::string& text,
                  DwaOptions* options);

// True if SetDwaOption() accepts `name` (option, alias or ignored name).
bool IsDwaOptionName(const std::string& name);

// True if `name` is accepted but has no effect (holonomic-only, ROS
// plumbing, or a DWAPlannerROS cost term this planner does not have).
bool IsIgnoredDwaOptionName(const std::string& name);

// Canonical option names (no aliases), in declaration order.
std::vector<std::string> DwaOptionNames();

// Names accepted and ignored, e.g. y_vels, max_vel_y, vy_samples,
// heading_scoring, publish_cost_grid_pc, forward_point_distance.
std::vector<std::string> DwaIgnoredOptionNames();

// angular_sim_granularity with the "< 0: same as sim_granularity" rule
// applied.
double EffectiveAngularSimGranularity(const DwaOptions& options);

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_DWA_OPTIONS_H_
