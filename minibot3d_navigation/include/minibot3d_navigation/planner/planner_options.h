// Parameters of the global planners, and the start/goal checks they configure.
//
// Names and defaults follow the ROS 1 global planners (navfn/NavfnROS and
// global_planner/GlobalPlanner: default_tolerance, allow_unknown, neutral_cost,
// cost_factor, lethal_cost, orientation_mode) so existing YAML files load
// parameter by parameter through GlobalPlannerOptionTable(); the OMPL planner's
// own parameters carry an `ompl_` prefix.  `base_global_planner` is
// move_base's parameter choosing the planner (see planner_factory.h).
//
// Cell costs are costmap_2d's (costmap_2d.h).  A cell is traversable when its
// cost is < lethal_cost (253 = inscribed by default, so the robot's centre
// never enters a cell where the footprint would touch an obstacle), or when it
// is unknown (255) and allow_unknown is set.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_PLANNER_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_PLANNER_PLANNER_OPTIONS_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

struct GlobalPlannerOptions {
  // Planner chosen by MakeGlobalPlanner(options, footprint): "astar" (aliases
  // "navfn/NavfnROS", "global_planner/GlobalPlanner") or "ompl".
  std::string base_global_planner = "astar";

  // Metres.  When the goal cell is not traversable, plan to the nearest
  // traversable cell within this distance of the goal (the path then ends at
  // that cell's centre with the goal's yaw); 0 = the goal must be traversable.
  double default_tolerance = 0.0;
  bool allow_unknown = true;  // may the path cross unknown (255) cells?

  // Step cost of moving one cell onto a cell of cost c is
  // step_length_in_cells * (neutral_cost + cost_factor * c).
  int neutral_cost = 50;
  double cost_factor = 3.0;
  int lethal_cost = 253;  // cells with cost >= this (and < 255) are impassable

  bool smooth_path = true;  // A*: shortcut + resample the grid path

  // Yaw of the path poses (the last pose always has the goal's yaw), after
  // global_planner's orientation_mode: 0 None (yaw 0), 1 Forward (along the
  // path; our default, ROS's is 0), 2 Interpolate (start yaw to goal yaw,
  // linearly in path length).
  int orientation_mode = 1;

  // --- OMPL planner ---
  std::string ompl_planner = "rrtstar";  // rrtstar, prmstar, rrtconnect
  double ompl_planning_time = 1.0;       // seconds per MakePlan
  bool ompl_simplify = true;             // OMPL's simplifySolution
  double ompl_interpolation_resolution = 0.05;  // metres between path poses
  // > 0: ompl::RNG::setSeed(ompl_seed) before each plan, so a plan that ends
  // on its first solution (rrtconnect) is reproducible.  0 = OMPL's random
  // seed.  Anytime planners (rrtstar, prmstar) stop on a wall-clock budget,
  // so their result still varies with machine load.
  int ompl_seed = 0;
};

// Throws std::invalid_argument listing every offending parameter with its
// value, e.g. "invalid global planner options: neutral_cost=0 must be in
// [1, 1000000]; ompl_planner='rrt' is not one of rrtstar, prmstar, rrtconnect".
void ValidateGlobalPlannerOptions(const GlobalPlannerOptions& options);

// The options by name, each with its documentation.  Setting does not check
// ranges (call ValidateGlobalPlannerOptions once all are set).
const minibot3d_common::options::OptionTable<GlobalPlannerOptions>& GlobalPlannerOptionTable();

// Thin wrappers of GlobalPlannerOptionTable(): Set throws std::invalid_argument
// for an unknown name or unparsable text ("0.25", "true", "rrtstar").
void SetGlobalPlannerOption(const std::string& name, const std::string& text,
                            GlobalPlannerOptions* options);
bool IsGlobalPlannerOptionName(const std::string& name);
std::vector<std::string> GlobalPlannerOptionNames();  // declaration order

// Accepted values of base_global_planner / MakeGlobalPlanner's name.
std::vector<std::string> GlobalPlannerNames();
bool IsAStarPlannerName(const std::string& name);  // astar and its aliases
std::vector<std::string> OmplPlannerNames();       // rrtstar, prmstar, ...

// --- Start/goal checks shared by the planners ---

// True when a cell of this cost may be on a path (see the file comment).
inline bool IsTraversableCost(uint8_t cost, const GlobalPlannerOptions& o) {
  return cost == kNoInformation ? o.allow_unknown : cost < o.lethal_cost;
}

// "254 (lethal)", "253 (inscribed)", "255 (unknown)", "200".
std::string DescribeCost(uint8_t cost);

// The cells a plan runs between.
struct PlanEndpoints {
  int start_mx = 0, start_my = 0;
  // Traversable goal cells, nearest to the goal first: just the goal's own
  // cell when it is traversable, else every traversable cell whose centre is
  // within default_tolerance of the goal.
  std::vector<std::pair<int, int>> goal_cells;
  bool goal_substituted = false;  // goal cell not traversable, goal_cells[0] used
};

// Checks start and goal against `costmap` and throws PlanningError:
//   kInvalidInput  start or goal not finite;
//   kStartOffMap   start outside the costmap (coordinates named);
//   kStartOccupied start cell cost >= lethal_cost (unknown is allowed: the
//                  robot is there);
//   kGoalOffMap    goal outside the costmap;
//   kGoalOccupied  goal cell not traversable and no traversable cell within
//                  default_tolerance (names the goal, its cell and cost).
PlanEndpoints ResolveEndpoints(const Costmap2D& costmap, const Pose2& start,
                               const Pose2& goal,
                               const GlobalPlannerOptions& options);

// "(x, y)" with 3 decimals, for error messages.
std::string FormatXY(double x, double y);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_PLANNER_OPTIONS_H_
