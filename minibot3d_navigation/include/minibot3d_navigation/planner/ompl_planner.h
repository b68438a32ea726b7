// Sampling-based global planner through OMPL (Sucan, Moll & Kavraki, "The
// Open Motion Planning Library", IEEE RAM 2012): RRT* and PRM* (Karaman &
// Frazzoli, "Sampling-based algorithms for optimal motion planning", IJRR
// 2011) or RRT-Connect (Kuffner & LaValle, ICRA 2000), per ompl_planner.
//
// The state space is OMPL's plain SE2StateSpace bounded by the costmap's
// extent; the objective is OMPL's default, path length.  A state is valid
// when the cell under the robot's centre is traversable (cost < lethal_cost,
// i.e. not inscribed/lethal with the defaults; unknown only with
// allow_unknown).  With an inflated costmap that check alone is exact for a
// circular robot: 253 marks every centre position whose inscribed circle
// touches an obstacle.  For a non-circular footprint (circumscribed radius
// more than half a cell above the inscribed one) the state must also pass
// FootprintCost(costmap, footprint, state) in [0, 254) (255 allowed with
// allow_unknown): the outline may not cross a lethal cell at the state's yaw.
// An empty footprint means a point robot (centre check only).  Motions are
// checked by OMPL's discrete motion validator every half cell.
//
// MakePlan: checks start/goal like A* (ResolveEndpoints, same goal
// tolerance), then floods the centre-valid cells from the start (8-connected)
// so that an unreachable goal is reported at once as kNoPath instead of after
// the whole time budget; a goal reachable on the grid but not solved within
// ompl_planning_time is kTimeout.  The solution is simplified
// (simplifySolution, if ompl_simplify) and interpolated to
// ompl_interpolation_resolution spacing.  Poses take their yaw per
// orientation_mode (A*'s convention; OMPL's sampled yaws are dropped), the
// last pose is the goal.  For a non-circular footprint any pose whose new yaw
// collides keeps the yaw OMPL validated.
//
// A fresh OMPL problem is built per call (the costmap may change between
// calls); OMPL's RNG is seeded from ompl_seed before each one when it is > 0.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_OMPL_PLANNER_H_
#define MINIBOT3D_NAVIGATION_PLANNER_OMPL_PLANNER_H_

#include <string>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/planner/global_planner.h"
#include "minibot3d_navigation/planner/planner_options.h"

namespace minibot3d_navigation {
namespace nav {

class OmplPlanner : public GlobalPlanner {
 public:
  // Validates `options` (std::invalid_argument listing every bad value).
  OmplPlanner(const GlobalPlannerOptions& options, const Footprint& footprint);

  std::string name() const override { return "ompl/" + options_.ompl_planner; }

  Path MakePlan(const Costmap2D& costmap, const Pose2& start,
                const Pose2& goal) override;

  // Is the robot at `pose` valid under the rules above?
  bool IsValid(const Costmap2D& costmap, const Pose2& pose) const;

  const GlobalPlannerOptions& options() const { return options_; }

 private:
  bool UsesFootprintCheck(const Costmap2D& costmap) const;

  const GlobalPlannerOptions options_;
  const Footprint footprint_;
  double inscribed_radius_ = 0.0;
  double circumscribed_radius_ = 0.0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_OMPL_PLANNER_H_
