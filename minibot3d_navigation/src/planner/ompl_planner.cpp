#include "minibot3d_navigation/planner/ompl_planner.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "minibot3d_navigation/planner/path_smoothing.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// Sets OMPL's (process-wide) log level for one scope and restores it.
class ScopedOmplLogLevel {
 public:
  explicit ScopedOmplLogLevel(ompl::msg::LogLevel level)
      : saved_(ompl::msg::getLogLevel()) {
    ompl::msg::setLogLevel(level);
  }
  ~ScopedOmplLogLevel() { ompl::msg::setLogLevel(saved_); }

 private:
  ompl::msg::LogLevel saved_;
};

std::string CellText(int mx, int my) {
  return "cell (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
}

// Cells reachable from `start` through traversable cells, 8-connected without
// cutting corners (A*'s moves).  reached[i] != 0 for those.
void FloodReachable(const Costmap2D& costmap, const GlobalPlannerOptions& o,
                    int start, std::vector<uint8_t>* reached) {
  const int w = costmap.size_x(), h = costmap.size_y();
  reached->assign(static_cast<size_t>(w) * h, 0);
  std::vector<int> queue;
  queue.reserve(1024);
  queue.push_back(start);
  (*reached)[start] = 1;
  const uint8_t* data = costmap.data();
  auto free_cell = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h &&
           IsTraversableCost(data[y * w + x], o);
  };
  for (size_t q = 0; q < queue.size(); ++q) {
    const int i = queue[q], x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !free_cell(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 &&
            (!free_cell(x + dx, y) || !free_cell(x, y + dy))) {
          continue;
        }
        const int n = (y + dy) * w + x + dx;
        if ((*reached)[n]) continue;
        (*reached)[n] = 1;
        queue.push_back(n);
      }
    }
  }
}

}  // namespace

OmplPlanner::OmplPlanner(const GlobalPlannerOptions& options,
                         const Footprint& footprint)
    : options_(options), footprint_(footprint) {
  ValidateGlobalPlannerOptions(options_);
  if (!footprint_.empty()) {
    if (footprint_.size() < 3) {
      throw std::invalid_argument(
          "OmplPlanner: footprint needs at least 3 points (or none for a "
          "point robot), got " + std::to_string(footprint_.size()));
    }
    FootprintRadii(footprint_, &inscribed_radius_, &circumscribed_radius_);
  }
}

bool OmplPlanner::UsesFootprintCheck(const Costmap2D& costmap) const {
  return !footprint_.empty() &&
         circumscribed_radius_ - inscribed_radius_ > 0.5 * costmap.resolution();
}

bool OmplPlanner::IsValid(const Costmap2D& costmap, const Pose2& pose) const {
  int mx = 0, my = 0;
  if (!costmap.WorldToMap(pose.x, pose.y, &mx, &my)) return false;
  if (!IsTraversableCost(costmap.cost(mx, my), options_)) return false;
  if (!UsesFootprintCheck(costmap)) return true;
  const int c = FootprintCost(costmap, footprint_, pose);
  return (c >= 0 && c < kLethalObstacle) ||
         (c == kNoInformation && options_.allow_unknown);
}

Path OmplPlanner::MakePlan(const Costmap2D& costmap, const Pose2& start,
                           const Pose2& goal) {
  using Code = PlanningError::Code;
  const PlanEndpoints ep = ResolveEndpoints(costmap, start, goal, options_);
  const int w = costmap.size_x();
  const int start_index = costmap.Index(ep.start_mx, ep.start_my);
  const bool footprint_check = UsesFootprintCheck(costmap);
  if (footprint_check && !IsValid(costmap, start) &&
      IsTraversableCost(costmap.cost(ep.start_mx, ep.start_my), options_)) {
    throw PlanningError(Code::kStartOccupied,
                        "start " + FormatXY(start.x, start.y) +
                            ": the footprint there touches a lethal cell "
                            "(FootprintCost " +
                            std::to_string(FootprintCost(costmap, footprint_, start)) +
                            ")");
  }

  // Reachability on the grid: kNoPath at once, and the goal substitute.
  std::vector<uint8_t> reached;
  FloodReachable(costmap, options_, start_index, &reached);
  int target = -1;
  for (const auto& c : ep.goal_cells) {
    const int idx = costmap.Index(c.first, c.second);
    if (reached[idx]) {
      target = idx;
      break;
    }
  }
  int gx = 0, gy = 0;
  costmap.WorldToMap(goal.x, goal.y, &gx, &gy);
  const std::string what = "from start " + FormatXY(start.x, start.y) + " " +
                           CellText(ep.start_mx, ep.start_my) + " to goal " +
                           FormatXY(goal.x, goal.y) + " " + CellText(gx, gy);
  if (target < 0) {
    throw PlanningError(Code::kNoPath,
                        "no path " + what +
                            (ep.goal_substituted
                                 ? " (nor to any traversable cell within "
                                   "default_tolerance)"
                                 : "") +
                            ": not connected through traversable cells");
  }
  Pose2 end = goal;
  if (ep.goal_substituted) costmap.MapToWorld(target % w, target / w, &end.x, &end.y);
  if (footprint_check && !IsValid(costmap, end)) {
    throw PlanningError(Code::kGoalOccupied,
                        "goal " + FormatXY(end.x, end.y) + " yaw " +
                            std::to_string(end.yaw) +
                            ": the footprint there touches a lethal cell");
  }

  // OMPL logs every solve at INFO; keep warnings and errors only.
  ScopedOmplLogLevel quiet(ompl::msg::LOG_WARN);
  if (options_.ompl_seed > 0) {
    // Reseeds the generator of the per-instance seeds, so the planner and
    // samplers created below draw the same numbers on every call.  OMPL logs
    // an error for every setSeed after its first RNG was made (it cannot
    // reseed RNGs that exist already); ours are all made after this call.
    ScopedOmplLogLevel silent(ompl::msg::LOG_NONE);
    ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(options_.ompl_seed));
  }
  auto space = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, costmap.origin_x());
  bounds.setHigh(0, costmap.origin_x() + costmap.size_x_m());
  bounds.setLow(1, costmap.origin_y());
  bounds.setHigh(1, costmap.origin_y() + costmap.size_y_m());
  space->setBounds(bounds);
  og::SimpleSetup ss(space);
  const Costmap2D* cm = &costmap;
  ss.setStateValidityChecker([this, cm, start_index](const ob::State* s) {
    const auto* se2 = s->as<ob::SE2StateSpace::StateType>();
    const Pose2 p{se2->getX(), se2->getY(), se2->getYaw()};
    int mx = 0, my = 0;
    if (cm->WorldToMap(p.x, p.y, &mx, &my) && cm->Index(mx, my) == start_index &&
        !UsesFootprintCheck(*cm)) {
      return true;  // the robot is there (it may be an unknown cell)
    }
    return IsValid(*cm, p);
  });
  const auto si = ss.getSpaceInformation();
  si->setStateValidityCheckingResolution(0.5 * costmap.resolution() /
                                         space->getMaximumExtent());
  ob::ScopedState<ob::SE2StateSpace> s(space), g(space);
  s->setXY(start.x, start.y);
  s->setYaw(start.yaw);
  g->setXY(end.x, end.y);
  g->setYaw(end.yaw);
  ss.setStartAndGoalStates(s, g);
  if (options_.ompl_planner == "rrtstar") {
    ss.setPlanner(std::make_shared<og::RRTstar>(si));
  } else if (options_.ompl_planner == "prmstar") {
    ss.setPlanner(std::make_shared<og::PRMstar>(si));
  } else {
    ss.setPlanner(std::make_shared<og::RRTConnect>(si));
  }
  const ob::PlannerStatus status = ss.solve(options_.ompl_planning_time);
  if (!ss.haveExactSolutionPath()) {
    std::ostringstream os;
    os << "no path " << what << " within ompl_planning_time "
       << options_.ompl_planning_time << " s (" << options_.ompl_planner
       << ": " << status.asString() << "); the goal is reachable on the grid";
    throw PlanningError(status == ob::PlannerStatus::INVALID_START ||
                                status == ob::PlannerStatus::INVALID_GOAL
                            ? Code::kNoPath
                            : Code::kTimeout,
                        os.str());
  }
  if (options_.ompl_simplify) ss.simplifySolution();
  const og::PathGeometric& solution = ss.getSolutionPath();

  // Vertices, then our own even interpolation along x, y (OMPL's SE2
  // interpolation is linear in x, y too, so the positions are on validated
  // motions).  vertex_yaw / vertex_of let a non-circular robot fall back to
  // the yaw OMPL validated.
  std::vector<Point2> vertices;
  std::vector<double> vertex_yaw;
  for (std::size_t i = 0; i < solution.getStateCount(); ++i) {
    const auto* st = solution.getState(i)->as<ob::SE2StateSpace::StateType>();
    vertices.push_back({st->getX(), st->getY()});
    vertex_yaw.push_back(st->getYaw());
  }
  vertices.front() = {start.x, start.y};
  vertices.back() = {end.x, end.y};
  const std::vector<Point2> points =
      ResamplePolyline(vertices, options_.ompl_interpolation_resolution);
  Path path = MakePathPoses(points, start.yaw, end, options_.orientation_mode);
  if (footprint_check) {
    // points[] holds vertex 0, then for each segment i its interior points and
    // vertex i + 1 (ResamplePolyline's order): recover the segment per point.
    size_t k = 1;
    for (size_t seg = 0; seg + 1 < vertices.size(); ++seg) {
      const Point2& a = vertices[seg];
      const Point2& b = vertices[seg + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      const int pieces = std::max(
          1, static_cast<int>(std::ceil(len / options_.ompl_interpolation_resolution - 1e-9)));
      for (int j = 1; j <= pieces && k + 1 < path.size(); ++j, ++k) {
        if (IsValid(costmap, path[k])) continue;
        const double t = static_cast<double>(j) / pieces;
        path[k].yaw = NormalizeAngle(vertex_yaw[seg] +
                                     t * AngleDiff(vertex_yaw[seg + 1], vertex_yaw[seg]));
      }
    }
    if (!IsValid(costmap, path.front())) path.front().yaw = start.yaw;
  }
  return path;
}

}  // namespace nav
}  // namespace minibot3d_navigation
