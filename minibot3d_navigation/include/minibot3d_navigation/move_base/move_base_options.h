// Parameters of the navigation executive (ROS move_base's own parameters,
// same names and defaults, so existing move_base YAMLs load unchanged).
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"

namespace minibot3d_navigation {
namespace nav {

struct MoveBaseOptions {
  // Which planners (see planner_factory.h and the node for the names).
  std::string base_global_planner = "navfn/NavfnROS";
  std::string base_local_planner = "base_local_planner/TrajectoryPlannerROS";
  // Hz; 0 plans once per goal (and again only when control fails).
  double planner_frequency = 0.0;
  double controller_frequency = 20.0;
  // Seconds without a valid plan / control command before recovering.
  double planner_patience = 5.0;
  double controller_patience = 15.0;
  // Planning attempts before recovering; -1 = only planner_patience counts.
  int max_planning_retries = -1;
  // Seconds without moving oscillation_distance before recovering; 0 = off.
  double oscillation_timeout = 0.0;
  double oscillation_distance = 0.5;
  bool recovery_behavior_enabled = true;
  bool clearing_rotation_allowed = true;
  // Recovery clearing keeps a square of this side centred on the robot.
  double conservative_reset_dist = 3.0;
  bool shutdown_costmaps = false;  // accepted, has no effect (documented)
  // Names of the recovery behaviours, in order: "wait", "back_out",
  // "conservative_reset", "rotate_recovery", "aggressive_reset".  When empty,
  // move_base's default list, preceded by back_out when back_out_distance > 0
  // and, before that, by wait when wait_duration > 0.
  std::vector<std::string> recovery_behaviors;

  // --- Not in ROS move_base: getting out of clutter ---
  // All off by default, so the executive behaves as move_base does;
  // config/move_base_mapless_params.yaml turns them on for mapless navigation
  // (docs/navigation.md, "Backing out and remembering pockets"). Typical
  // values: back_out_distance 0.6, blocked_radius 0.2,
  // recovery_reset_distance 0.5.
  // back_out: metres to reverse along the poses the robot drove through (its
  // trail, in the local frame) when the way ahead is blocked; 0 = no back_out
  // in the default list.  back_out_vel: its speed, m/s.
  double back_out_distance = 0.0;
  double back_out_vel = 0.15;
  // When control fails (controller_patience) or the robot oscillates, the
  // stretch of plan it could not pass — a disc of this radius round the plan
  // point blocked_lookahead metres ahead — is kept out of later plans for this
  // goal, so the global planner goes round it and does not send the robot back
  // into a pocket.  0 = off.  Forgotten if no plan exists without them.
  double blocked_radius = 0.0;
  double blocked_lookahead = 0.15;
  // A recovery sequence starts again from the first behaviour once the robot
  // has driven this far from where the last recovery began (ROS move_base
  // restarts it after any valid command; with 0 the list is never restarted
  // within a goal).
  double recovery_reset_distance = 0.0;
  // wait: when the planner finds no path the robot stands off what shut the
  // way, then stands for up to this many seconds until a path to the goal
  // exists again (someone standing in the only doorway steps out of it), then
  // replans; 0 = neither (no wait in the default list).
  // config/move_base_params.yaml sets 30; mapless navigation and exploration,
  // whose maps are still being made, 0.
  double wait_duration = 0.0;
};

// Throws std::invalid_argument listing every offending value.
void ValidateMoveBaseOptions(const MoveBaseOptions& options);

// The options by move_base name, each with its documentation.
const minibot3d_common::options::OptionTable<MoveBaseOptions>& MoveBaseOptionTable();

// Thin wrappers of MoveBaseOptionTable(): Set throws std::invalid_argument for
// an unknown name or unparsable text.  recovery_behaviors takes a
// comma-separated list.
void SetMoveBaseOption(const std::string& name, const std::string& text,
                       MoveBaseOptions* options);
bool IsMoveBaseOptionName(const std::string& name);
std::vector<std::string> MoveBaseOptionNames();

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_
