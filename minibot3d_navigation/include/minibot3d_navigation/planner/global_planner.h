// The global-planner extension point (nav_core::BaseGlobalPlanner, with
// nav_core2's explicit inputs and exceptions instead of a bool).
//
// Lifecycle: construct with the planner's options (validated there), then call
// MakePlan as often as needed.  MakePlan is given everything it uses — the
// costmap it plans on and the start and goal in the costmap's frame — and
// returns a path from start to goal (goal orientation on the last pose), or
// throws PlanningError saying which of start/goal failed and why.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_GLOBAL_PLANNER_H_
#define MINIBOT3D_NAVIGATION_PLANNER_GLOBAL_PLANNER_H_

#include <string>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

class GlobalPlanner {
 public:
  virtual ~GlobalPlanner() = default;
  virtual std::string name() const = 0;
  virtual Path MakePlan(const Costmap2D& costmap, const Pose2& start,
                        const Pose2& goal) = 0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_GLOBAL_PLANNER_H_
