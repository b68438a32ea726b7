// Builds the global planner named by move_base's base_global_planner.
//
// Accepted names: "astar" and, so that existing move_base YAML files keep
// working, its aliases "navfn/NavfnROS" and "global_planner/GlobalPlanner"
// (all three give AStarPlanner, which uses the same cost model and
// parameters); "ompl" gives OmplPlanner with options.ompl_planner.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_PLANNER_FACTORY_H_
#define MINIBOT3D_NAVIGATION_PLANNER_PLANNER_FACTORY_H_

#include <memory>
#include <string>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/planner/global_planner.h"
#include "minibot3d_navigation/planner/planner_options.h"

namespace minibot3d_navigation {
namespace nav {

// Throws std::invalid_argument for an unknown name (listing the accepted
// ones) or invalid options (listing every bad value).  `footprint` is used by
// the OMPL planner only (may be empty: point robot).
std::unique_ptr<GlobalPlanner> MakeGlobalPlanner(
    const std::string& name, const GlobalPlannerOptions& options,
    const Footprint& footprint);

// The same with name = options.base_global_planner.
std::unique_ptr<GlobalPlanner> MakeGlobalPlanner(
    const GlobalPlannerOptions& options, const Footprint& footprint);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_PLANNER_FACTORY_H_
