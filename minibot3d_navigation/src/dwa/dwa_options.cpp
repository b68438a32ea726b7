#include "minibot3d_navigation/dwa/dwa_options.h"

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

using options::Field;
using options::Num;
using O = DwaOptions;

constexpr char kOwner[] = "TrajectoryPlannerROS";

// One symmetric rotational limit |vtheta| <= v: DWAPlannerROS's max_rot_vel (up
// to kinetic) and TrajectoryPlannerROS's max_rotational_vel.
const char* const kSymmetricRotationNames[] = {"max_rot_vel", "max_rotational_vel"};

// Accepted and ignored.  Holonomic-only: y_vels, *_vel_y, vy_samples.
// TrajectoryPlannerROS scoring variants we do not implement: heading_scoring,
// heading_scoring_timestep, simple_attractor (both default false there).
// DWAPlannerROS terms with no TrajectoryPlannerROS equivalent: the
// translational-speed bounds (for a diff-drive max_vel_x bounds them),
// forward_point_distance / twirling_scale / scaling_speed /
// max_scaling_factor / stop_time_buffer (our stopping check replaces the
// latter), oscillation_reset_angle (we reset on distance, as
// TrajectoryPlannerROS).  ROS plumbing: publishers, frames, world_model.
const char* const kIgnoredNames[] = {
    "y_vels",
    "max_vel_y",
    "min_vel_y",
    "vy_samples",
    "heading_scoring",
    "heading_scoring_timestep",
    "simple_attractor",
    "max_vel_trans",
    "min_vel_trans",
    "max_trans_vel",
    "min_trans_vel",
    "acc_lim_trans",
    "forward_point_distance",
    "twirling_scale",
    "scaling_speed",
    "max_scaling_factor",
    "stop_time_buffer",
    "oscillation_reset_angle",
    "sum_scores",
    "publish_cost_grid_pc",
    "publish_cost_grid",
    "publish_traj_pc",
    "global_frame_id",
    "world_model",
    "restore_defaults",
};

}  // namespace

const options::OptionTable<DwaOptions>& DwaOptionTable() {
  static const options::OptionTable<O> table(
      kOwner,
      {Field("acc_lim_x", &O::acc_lim_x,
             "Forward acceleration limit (m/s^2): bounds the dynamic window and the braking the "
             "safety check assumes."),
       Field("acc_lim_y", &O::acc_lim_y,
             "Sideways acceleration limit (m/s^2): accepted, not used (the base cannot move "
             "sideways)."),
       Field("acc_lim_theta", &O::acc_lim_theta,
             "Rotational acceleration limit (rad/s^2): bounds the dynamic window, the braking and "
             "the final rotation to the goal yaw."),
       Field("max_vel_x", &O::max_vel_x, "Largest forward speed (m/s)."),
       Field("min_vel_x", &O::min_vel_x,
             "Smallest forward speed (m/s) of a sampled command other than a rotation on the "
             "spot; negative: the window includes reversing."),
       Field("max_vel_theta", &O::max_vel_theta,
             "Largest rotational speed (rad/s, counter-clockwise)."),
       Field("min_vel_theta", &O::min_vel_theta,
             "Most negative (clockwise) rotational speed (rad/s), < 0 as in TrajectoryPlannerROS; "
             "DWAPlannerROS's min_vel_theta (the smallest absolute speed) is "
             "min_in_place_vel_theta here."),
       Field("min_in_place_vel_theta", &O::min_in_place_vel_theta,
             "Smallest absolute rotational speed (rad/s) of a rotation on the spot."),
       Field("escape_vel", &O::escape_vel,
             "Speed (m/s, <= 0) of backing up when the robot is stuck in the inscribed band; 0 "
             "disables escaping."),
       Field("holonomic_robot", &O::holonomic_robot,
             "Must be false: the skid-steer base cannot move sideways (TrajectoryPlannerROS's "
             "default is true)."),
       Field("yaw_goal_tolerance", &O::yaw_goal_tolerance,
             "Heading error (rad) within which the goal's yaw counts as reached."),
       Field("xy_goal_tolerance", &O::xy_goal_tolerance,
             "Distance (m) to the goal within which its position counts as reached."),
       Field("latch_xy_goal_tolerance", &O::latch_xy_goal_tolerance,
             "Once within xy_goal_tolerance, only rotate to the goal yaw, even if rotating moves "
             "the robot out of the tolerance."),
       Field("trans_stopped_vel", &O::trans_stopped_vel,
             "Forward speed (m/s) at or below which the robot counts as stopped (goal reached, "
             "start of the final rotation)."),
       Field("rot_stopped_vel", &O::rot_stopped_vel,
             "Rotational speed (rad/s) at or below which the robot counts as stopped "
             "(DWAPlannerROS's name up to kinetic)."),
       Field("sim_time", &O::sim_time,
             "Time (s) each sampled command is simulated forward; at least one control period."),
       Field("sim_granularity", &O::sim_granularity,
             "Largest distance (m) between the poses of a simulated trajectory that are checked "
             "against the costmap."),
       Field("angular_sim_granularity", &O::angular_sim_granularity,
             "Largest rotation (rad) between checked poses; < 0: same as sim_granularity."),
       Field("vx_samples", &O::vx_samples, "Forward speeds sampled from the window."),
       Field("vtheta_samples", &O::vtheta_samples,
             "Rotational speeds sampled per forward speed, and rotations on the spot sampled."),
       Field("controller_frequency", &O::controller_frequency,
             "Control rate (Hz): one period is the dynamic window's span and the time a command "
             "is held before braking; move_base sets it from its own controller_frequency."),
       Field("path_distance_bias", &O::path_distance_bias,
             "Weight of a trajectory end's distance from the plan in its cost."),
       Field("goal_distance_bias", &O::goal_distance_bias,
             "Weight of a trajectory end's distance from the plan's end (the local goal) in its "
             "cost."),
       Field("occdist_scale", &O::occdist_scale,
             "Weight of the highest costmap cost under the footprint along a trajectory in its "
             "cost."),
       Field("heading_lookahead", &O::heading_lookahead,
             "Distance (m) ahead of a rotated robot at which a rotation on the spot is scored by "
             "its distance to the goal; also the least distance of the plan point whose bearing "
             "rotate_to_path_angle is checked against."),
       Field("dwa", &O::dwa,
             "Sample the commands reachable within one control period (dynamic window); false: "
             "within sim_time (trajectory rollout)."),
       Field("meter_scoring", &O::meter_scoring,
             "Path and goal distances in metres instead of cells (occdist_scale is scaled by the "
             "resolution too)."),
       Field("oscillation_reset_dist", &O::oscillation_reset_dist,
             "Distance (m) the robot must travel before a flip between turning left and right, or "
             "forward and backward, is allowed again."),
       Field("escape_reset_dist", &O::escape_reset_dist,
             "Backing up ends once the robot has moved this far (m)."),
       Field("escape_reset_theta", &O::escape_reset_theta,
             "Backing up ends once the robot has turned this far (rad)."),
       Field("prune_plan", &O::prune_plan,
             "Drop the part of the plan behind the pose nearest the robot."),
       Field("rotate_to_path_angle", &O::rotate_to_path_angle,
             "With the plan ahead more than this (rad) off the heading (a quarter of it at "
             "creeping speed or stopped), stop and turn on the spot towards it first; >= pi "
             "disables."),
       Field("max_centripetal_acc", &O::max_centripetal_acc,
             "Largest centripetal acceleration, abs(vx x vtheta) (m/s^2), of a sampled arc, since "
             "a skid-steer base turns tighter than commanded when it corners hard; 0: no limit."),
       Field("full_margin_vel", &O::full_margin_vel,
             "Speed (m/s) from which trajectories keep the footprint a whole inscribed radius "
             "from obstacles; slower, the margin shrinks to none at creeping speed "
             "(the larger of min_vel_x and -escape_vel)."),
       Field("moving_obstacle_scale", &O::moving_obstacle_scale,
             "Weight of the cost of coming within personal_distance of a moving obstacle's "
             "predicted position (0..1, more the nearer and sooner), in the units of the path "
             "and goal terms; 0: only the legality check."),
       Field("moving_obstacle_horizon", &O::moving_obstacle_horizon,
             "How far ahead (s) moving obstacles are predicted at constant velocity."),
       Field("moving_obstacle_margin", &O::moving_obstacle_margin,
             "A command whose way to a stop (one control period, then braking) brings the "
             "footprint nearer than this (m) to a moving obstacle's predicted position is "
             "illegal; the robot brakes and stands instead."),
       Field("moving_obstacle_deviation", &O::moving_obstacle_deviation,
             "Speed (m/s) at which a moving obstacle may stray from its constant-velocity "
             "prediction (a person turning, slowing, stepping aside): the margin of the way to "
             "a stop grows by this times the time ahead; 0 trusts the prediction. Raise it when "
             "the tracker's velocities lag (the robot then stands for more people)."),
       Field("personal_distance", &O::personal_distance,
             "Distance (m) from a moving obstacle's predicted position within which a trajectory "
             "costs."),
       Field("moving_obstacle_wait", &O::moving_obstacle_wait,
             "Time (s) the robot stands yielding to moving obstacles before it may back away "
             "from one that stopped within moving_obstacle_margin (a standoff).")});
  return table;
}

const options::OptionTable<DwaOptions>& DwaAliasOptionTable() {
  static const options::OptionTable<O> table(
      kOwner,
      {Field("acc_lim_th", &O::acc_lim_theta,
             "Same as acc_lim_theta (the name older TrajectoryPlannerROS releases use)."),
       Field("min_in_place_rotational_vel", &O::min_in_place_vel_theta,
             "Same as min_in_place_vel_theta (the name TrajectoryPlannerROS deprecates)."),
       Field("min_rot_vel", &O::min_in_place_vel_theta,
             "Same as min_in_place_vel_theta (the name DWAPlannerROS uses up to kinetic)."),
       Field("backup_vel", &O::escape_vel,
             "Same as escape_vel (the name TrajectoryPlannerROS deprecates)."),
       Field("theta_stopped_vel", &O::rot_stopped_vel,
             "Same as rot_stopped_vel (the name DWAPlannerROS uses since melodic)."),
       Field("vth_samples", &O::vtheta_samples,
             "Same as vtheta_samples (the name DWAPlannerROS uses)."),
       Field("pdist_scale", &O::path_distance_bias,
             "Same as path_distance_bias (the name TrajectoryPlannerROS deprecates)."),
       Field("gdist_scale", &O::goal_distance_bias,
             "Same as goal_distance_bias (the name TrajectoryPlannerROS deprecates)."),
       Field("use_dwa", &O::dwa, "Same as dwa (the name DWAPlannerROS uses)."),
       Field(kSymmetricRotationNames[0], &O::max_vel_theta,
             "Sets max_vel_theta to the value and min_vel_theta to minus it (the name "
             "DWAPlannerROS uses up to kinetic)."),
       Field(kSymmetricRotationNames[1], &O::max_vel_theta,
             "Sets max_vel_theta to the value and min_vel_theta to minus it (the name "
             "TrajectoryPlannerROS reads).")});
  return table;
}

bool IsSymmetricRotationName(const std::string& name) {
  return name == kSymmetricRotationNames[0] || name == kSymmetricRotationNames[1];
}

void ApplySymmetricRotation(DwaOptions* options) {
  options->min_vel_theta = -options->max_vel_theta;
}


double EffectiveAngularSimGranularity(const DwaOptions& o) {
  return o.angular_sim_granularity < 0.0 ? o.sim_granularity
                                         : o.angular_sim_granularity;
}

void SetDwaOption(const std::string& name, const std::string& text,
                  DwaOptions* options) {
  if (DwaAliasOptionTable().Has(name)) {
    DwaAliasOptionTable().Set(name, text, options);
    if (IsSymmetricRotationName(name)) ApplySymmetricRotation(options);
  } else if (!IsIgnoredDwaOptionName(name)) {
    DwaOptionTable().Set(name, text, options);  // throws for an unknown name
  }
}

bool IsIgnoredDwaOptionName(const std::string& name) {
  for (const char* n : kIgnoredNames) {
    if (name == n) return true;
  }
  return false;
}

bool IsDwaOptionName(const std::string& name) {
  return DwaOptionTable().Has(name) || DwaAliasOptionTable().Has(name) ||
         IsIgnoredDwaOptionName(name);
}

std::vector<std::string> DwaOptionNames() { return DwaOptionTable().Names(); }

std::vector<std::string> DwaIgnoredOptionNames() {
  return std::vector<std::string>(std::begin(kIgnoredNames),
                                  std::end(kIgnoredNames));
}

void ValidateDwaOptions(const DwaOptions& o) {
  options::Problems problems("DWA local planner (TrajectoryPlannerROS)");
  auto require = [&problems](bool ok, const std::string& what) {
    problems.Require(ok, what);
  };

  require(!o.holonomic_robot,
          "holonomic_robot=true is not supported: minibot3d is a skid-steer "
          "(non-holonomic) base that cannot move sideways; set "
          "holonomic_robot: false");

  problems.Positive("acc_lim_x", o.acc_lim_x);
  problems.NonNegative("acc_lim_y", o.acc_lim_y);
  problems.Positive("acc_lim_theta", o.acc_lim_theta);
  problems.Positive("max_vel_x", o.max_vel_x);
  require(std::isfinite(o.min_vel_x),
          "min_vel_x=" + Num(o.min_vel_x) + " must be finite");
  if (std::isfinite(o.min_vel_x) && std::isfinite(o.max_vel_x)) {
    require(o.min_vel_x <= o.max_vel_x, "min_vel_x=" + Num(o.min_vel_x) +
                                            " > max_vel_x=" +
                                            Num(o.max_vel_x));
  }
  problems.Positive("max_vel_theta", o.max_vel_theta);
  require(std::isfinite(o.min_vel_theta) && o.min_vel_theta < 0.0,
          "min_vel_theta=" + Num(o.min_vel_theta) +
              " must be < 0 (it is the most negative rotational velocity, "
              "as in TrajectoryPlannerROS; for DWAPlannerROS's smallest "
              "|rotation| use min_in_place_vel_theta)");
  problems.NonNegative("min_in_place_vel_theta", o.min_in_place_vel_theta);
  if (std::isfinite(o.min_in_place_vel_theta) &&
      std::isfinite(o.max_vel_theta) && o.max_vel_theta > 0.0) {
    require(o.min_in_place_vel_theta <= o.max_vel_theta,
            "min_in_place_vel_theta=" + Num(o.min_in_place_vel_theta) +
                " > max_vel_theta=" + Num(o.max_vel_theta));
  }
  if (std::isfinite(o.min_in_place_vel_theta) &&
      std::isfinite(o.min_vel_theta) && o.min_vel_theta < 0.0) {
    require(o.min_in_place_vel_theta <= -o.min_vel_theta,
            "min_in_place_vel_theta=" + Num(o.min_in_place_vel_theta) +
                " > -min_vel_theta=" + Num(-o.min_vel_theta));
  }
  require(std::isfinite(o.escape_vel) && o.escape_vel <= 0.0,
          "escape_vel=" + Num(o.escape_vel) +
              " must be <= 0 (the backing-up speed; 0 disables escaping)");
  if (std::isfinite(o.escape_vel) && std::isfinite(o.max_vel_x)) {
    require(-o.escape_vel <= o.max_vel_x,
            "|escape_vel|=" + Num(-o.escape_vel) + " > max_vel_x=" +
                Num(o.max_vel_x));
  }

  problems.Positive("yaw_goal_tolerance", o.yaw_goal_tolerance);
  problems.Positive("xy_goal_tolerance", o.xy_goal_tolerance);
  problems.NonNegative("trans_stopped_vel", o.trans_stopped_vel);
  problems.NonNegative("rot_stopped_vel", o.rot_stopped_vel);

  problems.Positive("sim_time", o.sim_time);
  problems.Positive("sim_granularity", o.sim_granularity);
  require(std::isfinite(o.angular_sim_granularity) &&
              o.angular_sim_granularity != 0.0,
          "angular_sim_granularity=" + Num(o.angular_sim_granularity) +
              " must be > 0 (or < 0 for 'same as sim_granularity')");
  require(o.vx_samples >= 1,
          "vx_samples=" + std::to_string(o.vx_samples) + " must be >= 1");
  require(o.vtheta_samples >= 1, "vtheta_samples=" +
                                     std::to_string(o.vtheta_samples) +
                                     " must be >= 1");
  problems.Positive("controller_frequency", o.controller_frequency);

  problems.NonNegative("path_distance_bias", o.path_distance_bias);
  problems.NonNegative("goal_distance_bias", o.goal_distance_bias);
  problems.NonNegative("occdist_scale", o.occdist_scale);
  problems.NonNegative("heading_lookahead", o.heading_lookahead);
  problems.NonNegative("oscillation_reset_dist", o.oscillation_reset_dist);
  problems.NonNegative("escape_reset_dist", o.escape_reset_dist);
  problems.NonNegative("escape_reset_theta", o.escape_reset_theta);
  problems.Positive("rotate_to_path_angle", o.rotate_to_path_angle);
  problems.NonNegative("max_centripetal_acc", o.max_centripetal_acc);
  problems.Positive("full_margin_vel", o.full_margin_vel);
  problems.NonNegative("moving_obstacle_scale", o.moving_obstacle_scale);
  problems.Positive("moving_obstacle_horizon", o.moving_obstacle_horizon);
  problems.NonNegative("moving_obstacle_margin", o.moving_obstacle_margin);
  problems.NonNegative("moving_obstacle_deviation", o.moving_obstacle_deviation);
  problems.Positive("personal_distance", o.personal_distance);
  problems.NonNegative("moving_obstacle_wait", o.moving_obstacle_wait);

  // A rollout shorter than one control period would leave the robot
  // unchecked for the rest of the period.
  if (std::isfinite(o.sim_time) && std::isfinite(o.controller_frequency) &&
      o.controller_frequency > 0.0 && o.sim_time > 0.0) {
    require(o.sim_time >= 1.0 / o.controller_frequency,
            "sim_time=" + Num(o.sim_time) +
                " is shorter than one control period 1/controller_frequency=" +
                Num(1.0 / o.controller_frequency));
  }

  problems.ThrowIfAny();
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
