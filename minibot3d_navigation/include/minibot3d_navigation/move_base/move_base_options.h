// Parameters of the navigation executive (ROS move_base's own parameters,
// same names and defaults, so existing move_base YAMLs load unchanged).
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_

#include <string>
#include <vector>

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
  // Names of the recovery behaviours, in order (move_base's default list when
  // empty): "conservative_reset", "rotate_recovery", "aggressive_reset".
  std::vector<std::string> recovery_behaviors;
};

// Throws std::invalid_argument listing every offending value.
void ValidateMoveBaseOptions(const MoveBaseOptions& options);
// Sets one option from text; throws std::invalid_argument for an unknown
// name or unparsable text.  recovery_behaviors takes a comma-separated list.
void SetMoveBaseOption(const std::string& name, const std::string& text,
                       MoveBaseOptions* options);
bool IsMoveBaseOptionName(const std::string& name);
std::vector<std::string> MoveBaseOptionNames();

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_MOVE_BASE_OPTIONS_H_
