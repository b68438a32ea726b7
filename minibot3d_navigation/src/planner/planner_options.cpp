#include "minibot3d_navigation/planner/planner_options.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = GlobalPlannerOptions;

const char* const kAStarNames[] = {"astar", "navfn/NavfnROS",
                                   "global_planner/GlobalPlanner"};
const char* const kOmplPlannerNames[] = {"rrtstar", "prmstar", "rrtconnect"};

template <size_t N>
std::string JoinNames(const char* const (&names)[N]) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += (i ? ", " : "") + std::string(names[i]);
  return s;
}

}  // namespace

const options::OptionTable<GlobalPlannerOptions>& GlobalPlannerOptionTable() {
  static const options::OptionTable<O> table(
      "global planner",
      {Field("base_global_planner", &O::base_global_planner,
             "The planner: astar (also by the names navfn/NavfnROS and "
             "global_planner/GlobalPlanner) or ompl; move_base sets it from its own "
             "base_global_planner."),
       Field("default_tolerance", &O::default_tolerance,
             "When the goal cell cannot be entered, plan to the nearest cell that can within this "
             "distance (m) of the goal; 0: the goal itself must be free (navfn)."),
       Field("allow_unknown", &O::allow_unknown,
             "Paths may cross unknown cells (cost 255)."),
       Field("neutral_cost", &O::neutral_cost,
             "Cost per cell length of a step onto a free cell; onto a cell of cost c it is "
             "neutral_cost + cost_factor x c (global_planner)."),
       Field("cost_factor", &O::cost_factor,
             "Weight of a cell's costmap cost in a step's cost (global_planner)."),
       Field("lethal_cost", &O::lethal_cost,
             "Cells of this cost and above (below 255) cannot be entered; 253: the robot's centre "
             "keeps out of cells where its inscribed circle would touch an obstacle."),
       Field("smooth_path", &O::smooth_path,
             "A*: shorten the grid path by line-of-sight shortcuts through cells no costlier than "
             "those they replace, then resample it at the costmap's resolution; false: the cell "
             "centres."),
       Field("orientation_mode", &O::orientation_mode,
             "Yaw of the path poses before the last (which takes the goal's): 0 zero, 1 along the "
             "path, 2 interpolated from the start's to the goal's (global_planner's None, "
             "Forward, Interpolate; its default is 0)."),
       Field("ompl_planner", &O::ompl_planner,
             "The OMPL algorithm: rrtstar, prmstar or rrtconnect."),
       Field("ompl_planning_time", &O::ompl_planning_time,
             "Time budget (s, wall clock) of one OMPL plan."),
       Field("ompl_simplify", &O::ompl_simplify,
             "Shorten the OMPL solution with OMPL's simplifySolution."),
       Field("ompl_interpolation_resolution", &O::ompl_interpolation_resolution,
             "Spacing (m) of the poses along an OMPL path."),
       Field("ompl_seed", &O::ompl_seed,
             "Seed of OMPL's random generator, set before each plan (a plan that ends on its "
             "first solution, rrtconnect, is then repeatable); 0: OMPL's random seed.")});
  return table;
}

void SetGlobalPlannerOption(const std::string& name, const std::string& text,
                            GlobalPlannerOptions* options) {
  GlobalPlannerOptionTable().Set(name, text, options);
}

bool IsGlobalPlannerOptionName(const std::string& name) {
  return GlobalPlannerOptionTable().Has(name);
}

std::vector<std::string> GlobalPlannerOptionNames() { return GlobalPlannerOptionTable().Names(); }

std::vector<std::string> GlobalPlannerNames() {
  std::vector<std::string> names(std::begin(kAStarNames), std::end(kAStarNames));
  names.emplace_back("ompl");
  return names;
}

bool IsAStarPlannerName(const std::string& name) {
  for (const char* n : kAStarNames) {
    if (name == n) return true;
  }
  return false;
}

std::vector<std::string> OmplPlannerNames() {
  return {std::begin(kOmplPlannerNames), std::end(kOmplPlannerNames)};
}

void ValidateGlobalPlannerOptions(const GlobalPlannerOptions& o) {
  std::vector<std::string> errors;
  auto require = [&errors](bool ok, const std::string& what) {
    if (!ok) errors.push_back(what);
  };
  // Comparisons with NaN are false, so these also reject NaN.
  require(IsAStarPlannerName(o.base_global_planner) ||
              o.base_global_planner == "ompl",
          "base_global_planner='" + o.base_global_planner + "' is not one of " +
              JoinNames(kAStarNames) + ", ompl");
  require(std::isfinite(o.default_tolerance) && o.default_tolerance >= 0.0,
          "default_tolerance=" + Num(o.default_tolerance) + " must be >= 0");
  require(o.neutral_cost >= 1 && o.neutral_cost <= 1000000,
          "neutral_cost=" + std::to_string(o.neutral_cost) +
              " must be in [1, 1000000]");
  require(std::isfinite(o.cost_factor) && o.cost_factor >= 0.0 &&
              o.cost_factor <= 1e6,
          "cost_factor=" + Num(o.cost_factor) + " must be in [0, 1e6]");
  require(o.lethal_cost >= 1 && o.lethal_cost <= 254,
          "lethal_cost=" + std::to_string(o.lethal_cost) +
              " must be in [1, 254] (255 is unknown, see allow_unknown)");
  require(o.orientation_mode >= 0 && o.orientation_mode <= 2,
          "orientation_mode=" + std::to_string(o.orientation_mode) +
              " must be 0 (None), 1 (Forward) or 2 (Interpolate)");
  require(std::find(std::begin(kOmplPlannerNames), std::end(kOmplPlannerNames),
                    o.ompl_planner) != std::end(kOmplPlannerNames),
          "ompl_planner='" + o.ompl_planner + "' is not one of " +
              JoinNames(kOmplPlannerNames));
  require(std::isfinite(o.ompl_planning_time) && o.ompl_planning_time > 0.0,
          "ompl_planning_time=" + Num(o.ompl_planning_time) + " must be > 0");
  require(std::isfinite(o.ompl_interpolation_resolution) &&
              o.ompl_interpolation_resolution > 0.0,
          "ompl_interpolation_resolution=" +
              Num(o.ompl_interpolation_resolution) + " must be > 0");
  require(o.ompl_seed >= 0, "ompl_seed=" + std::to_string(o.ompl_seed) +
                                " must be >= 0 (0 = random)");
  if (!errors.empty()) {
    std::string msg = "invalid global planner options: ";
    for (size_t i = 0; i < errors.size(); ++i) {
      if (i > 0) msg += "; ";
      msg += errors[i];
    }
    throw std::invalid_argument(msg);
  }
}

std::string DescribeCost(uint8_t cost) {
  std::string s = std::to_string(cost);
  if (cost == kLethalObstacle) s += " (lethal)";
  if (cost == kInscribedInflatedObstacle) s += " (inscribed)";
  if (cost == kNoInformation) s += " (unknown)";
  return s;
}

std::string FormatXY(double x, double y) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.3f, %.3f)", x, y);
  return buf;
}

PlanEndpoints ResolveEndpoints(const Costmap2D& costmap, const Pose2& start,
                               const Pose2& goal,
                               const GlobalPlannerOptions& options) {
  using Code = PlanningError::Code;
  if (!minibot3d_common::IsFinite(start) || !minibot3d_common::IsFinite(goal)) {
    throw PlanningError(Code::kInvalidInput,
                        "start " + FormatXY(start.x, start.y) + " yaw " +
                            Num(start.yaw) + " or goal " +
                            FormatXY(goal.x, goal.y) + " yaw " + Num(goal.yaw) +
                            " is not finite");
  }
  auto cell_text = [](int mx, int my) {
    return "cell (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
  };
  const std::string extent =
      " outside the costmap [" + Num(costmap.origin_x()) + ", " +
      Num(costmap.origin_x() + costmap.size_x_m()) + "] x [" +
      Num(costmap.origin_y()) + ", " +
      Num(costmap.origin_y() + costmap.size_y_m()) + "]";
  PlanEndpoints ep;
  if (!costmap.WorldToMap(start.x, start.y, &ep.start_mx, &ep.start_my)) {
    throw PlanningError(Code::kStartOffMap,
                        "start " + FormatXY(start.x, start.y) + " is" + extent +
                            "; has the robot been localized?");
  }
  const uint8_t start_cost = costmap.cost(ep.start_mx, ep.start_my);
  // A start in the inflated band (cost >= lethal_cost but not an obstacle)
  // is allowed: the robot is there, and A* steps out of the band first.
  if (start_cost == kLethalObstacle) {
    throw PlanningError(
        Code::kStartOccupied,
        "start " + FormatXY(start.x, start.y) + " is in " +
            cell_text(ep.start_mx, ep.start_my) + " of cost " +
            DescribeCost(start_cost) + " (an obstacle): is the robot localized?");
  }
  int gx = 0, gy = 0;
  if (!costmap.WorldToMap(goal.x, goal.y, &gx, &gy)) {
    throw PlanningError(Code::kGoalOffMap,
                        "goal " + FormatXY(goal.x, goal.y) + " is" + extent);
  }
  const uint8_t goal_cost = costmap.cost(gx, gy);
  if (IsTraversableCost(goal_cost, options)) {
    ep.goal_cells.emplace_back(gx, gy);
    return ep;
  }
  // Every traversable cell whose centre lies within the tolerance, nearest
  // first (ties broken by cell order, so the choice is deterministic).
  const double res = costmap.resolution();
  const double tol = options.default_tolerance;
  const int r = static_cast<int>(std::ceil(tol / res)) + 1;
  std::vector<std::pair<double, std::pair<int, int>>> candidates;
  for (int y = std::max(0, gy - r); y <= std::min(costmap.size_y() - 1, gy + r);
       ++y) {
    for (int x = std::max(0, gx - r);
         x <= std::min(costmap.size_x() - 1, gx + r); ++x) {
      double cx, cy;
      costmap.MapToWorld(x, y, &cx, &cy);
      const double d = std::hypot(cx - goal.x, cy - goal.y);
      if (d <= tol && IsTraversableCost(costmap.cost(x, y), options)) {
        candidates.push_back({d, {x, y}});
      }
    }
  }
  if (candidates.empty()) {
    throw PlanningError(
        Code::kGoalOccupied,
        "goal " + FormatXY(goal.x, goal.y) + " is in " + cell_text(gx, gy) +
            " of cost " + DescribeCost(goal_cost) +
            (goal_cost == kNoInformation ? " (allow_unknown is false)"
                                         : " >= lethal_cost " +
                                               std::to_string(options.lethal_cost)) +
            " and no traversable cell is within default_tolerance " +
            Num(tol) + " m");
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& c : candidates) ep.goal_cells.push_back(c.second);
  ep.goal_substituted = true;
  return ep;
}

}  // namespace nav
}  // namespace minibot3d_navigation
