#include "minibot3d_navigation/planner/planner_factory.h"

#include <stdexcept>

#include "minibot3d_navigation/planner/astar_planner.h"
#include "minibot3d_navigation/planner/ompl_planner.h"

namespace minibot3d_navigation {
namespace nav {

std::unique_ptr<GlobalPlanner> MakeGlobalPlanner(
    const std::string& name, const GlobalPlannerOptions& options,
    const Footprint& footprint) {
  if (IsAStarPlannerName(name)) return std::make_unique<AStarPlanner>(options);
  if (name == "ompl") return std::make_unique<OmplPlanner>(options, footprint);
  std::string accepted;
  for (const std::string& n : GlobalPlannerNames()) {
    accepted += (accepted.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument("unknown global planner '" + name +
                              "' (base_global_planner); accepted: " + accepted);
}

std::unique_ptr<GlobalPlanner> MakeGlobalPlanner(
    const GlobalPlannerOptions& options, const Footprint& footprint) {
  return MakeGlobalPlanner(options.base_global_planner, options, footprint);
}

}  // namespace nav
}  // namespace minibot3d_navigation
