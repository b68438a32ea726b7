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

const options::OptionTable<O>& Table() {
  static const options::OptionTable<O> table(
      kOwner,
      {Field("acc_lim_x", &O::acc_lim_x),
       Field("acc_lim_y", &O::acc_lim_y),
       Field("acc_lim_theta", &O::acc_lim_theta),
       Field("max_vel_x", &O::max_vel_x),
       Field("min_vel_x", &O::min_vel_x),
       Field("max_vel_theta", &O::max_vel_theta),
       Field("min_vel_theta", &O::min_vel_theta),
       Field("min_in_place_vel_theta", &O::min_in_place_vel_theta),
       Field("escape_vel", &O::escape_vel),
       Field("holonomic_robot", &O::holonomic_robot),
       Field("yaw_goal_tolerance", &O::yaw_goal_tolerance),
       Field("xy_goal_tolerance", &O::xy_goal_tolerance),
       Field("latch_xy_goal_tolerance", &O::latch_xy_goal_tolerance),
       Field("trans_stopped_vel", &O::trans_stopped_vel),
       Field("rot_stopped_vel", &O::rot_stopped_vel),
       Field("sim_time", &O::sim_time),
       Field("sim_granularity", &O::sim_granularity),
       Field("angular_sim_granularity", &O::angular_sim_granularity),
       Field("vx_samples", &O::vx_samples),
       Field("vtheta_samples", &O::vtheta_samples),
       Field("controller_frequency", &O::controller_frequency),
       Field("path_distance_bias", &O::path_distance_bias),
       Field("goal_distance_bias", &O::goal_distance_bias),
       Field("occdist_scale", &O::occdist_scale),
       Field("heading_lookahead", &O::heading_lookahead),
       Field("dwa", &O::dwa),
       Field("meter_scoring", &O::meter_scoring),
       Field("oscillation_reset_dist", &O::oscillation_reset_dist),
       Field("escape_reset_dist", &O::escape_reset_dist),
       Field("escape_reset_theta", &O::escape_reset_theta),
       Field("prune_plan", &O::prune_plan),
       Field("rotate_to_path_angle", &O::rotate_to_path_angle),
       Field("max_centripetal_acc", &O::max_centripetal_acc),
       Field("full_margin_vel", &O::full_margin_vel)});
  return table;
}

// Other spellings of the same fields: older TrajectoryPlannerROS names and
// DWAPlannerROS names that mean the same for a differential drive.
const options::OptionTable<O>& Aliases() {
  static const options::OptionTable<O> table(
      kOwner,
      {Field("acc_lim_th", &O::acc_lim_theta),
       Field("min_in_place_rotational_vel", &O::min_in_place_vel_theta),
       Field("min_rot_vel", &O::min_in_place_vel_theta),
       Field("backup_vel", &O::escape_vel),
       Field("theta_stopped_vel", &O::rot_stopped_vel),
       Field("vth_samples", &O::vtheta_samples),
       Field("pdist_scale", &O::path_distance_bias),
       Field("gdist_scale", &O::goal_distance_bias),
       Field("use_dwa", &O::dwa)});
  return table;
}

// Symmetric rotational limit (DWAPlannerROS max_rot_vel, TrajectoryPlannerROS
// max_rotational_vel): sets max_vel_theta = v, min_vel_theta = -v.
const char* const kSymmetricThetaNames[] = {"max_rot_vel",
                                            "max_rotational_vel"};

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

bool IsSymmetricThetaName(const std::string& name) {
  for (const char* n : kSymmetricThetaNames) {
    if (name == n) return true;
  }
  return false;
}

}  // namespace

double EffectiveAngularSimGranularity(const DwaOptions& o) {
  return o.angular_sim_granularity < 0.0 ? o.sim_granularity
                                         : o.angular_sim_granularity;
}

void SetDwaOption(const std::string& name, const std::string& text,
                  DwaOptions* options) {
  if (IsSymmetricThetaName(name)) {
    const double v = options::ParseDouble(kOwner, name, text);
    options->max_vel_theta = v;
    options->min_vel_theta = -v;
  } else if (Aliases().Has(name)) {
    Aliases().Set(name, text, options);
  } else if (!IsIgnoredDwaOptionName(name)) {
    Table().Set(name, text, options);  // throws for an unknown name
  }
}

bool IsIgnoredDwaOptionName(const std::string& name) {
  for (const char* n : kIgnoredNames) {
    if (name == n) return true;
  }
  return false;
}

bool IsDwaOptionName(const std::string& name) {
  return Table().Has(name) || Aliases().Has(name) ||
         IsSymmetricThetaName(name) || IsIgnoredDwaOptionName(name);
}

std::vector<std::string> DwaOptionNames() { return Table().Names(); }

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
