// Tests of the A* global planner, its options, the path smoothing and the
// planner factory on tiny standard maps written inline (after
// robot_navigation/global_planner_tests/maps): straight corridor, U-turn,
// unreachable goal, goal in an obstacle within / beyond the tolerance, start
// in inflation, start/goal off the map, unknown space.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/planner/astar_planner.h"
#include "minibot3d_navigation/planner/path_smoothing.h"
#include "minibot3d_navigation/planner/planner_factory.h"
#include "minibot3d_navigation/planner/planner_options.h"
#include "planner_test_maps.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

using Code = PlanningError::Code;
using testing::Cell;
using testing::kRes;
using testing::MapFromAscii;

int CostAt(const Costmap2D& map, double x, double y) {
  int mx = 0, my = 0;
  EXPECT_TRUE(map.WorldToMap(x, y, &mx, &my)) << x << ", " << y;
  return map.cost(mx, my);
}

// Every pose on the map, not lethal / inscribed, consecutive poses within
// `max_step` of each other.
void ExpectPathClear(const Costmap2D& map, const Path& path, double max_step,
                     bool allow_unknown = true) {
  ASSERT_FALSE(path.empty());
  for (size_t i = 0; i < path.size(); ++i) {
    const int c = CostAt(map, path[i].x, path[i].y);
    if (c == kNoInformation) {
      EXPECT_TRUE(allow_unknown) << "pose " << i << " in unknown";
    } else {
      EXPECT_LT(c, kInscribedInflatedObstacle)
          << "pose " << i << " at " << path[i].x << ", " << path[i].y;
    }
    if (i > 0) {
      EXPECT_LE(std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y),
                max_step + 1e-9)
          << "gap before pose " << i;
    }
  }
}

void ExpectPlanError(GlobalPlanner* planner, const Costmap2D& map,
                     const Pose2& start, const Pose2& goal, Code code,
                     const std::vector<std::string>& message_parts) {
  try {
    planner->MakePlan(map, start, goal);
    FAIL() << "expected PlanningError";
  } catch (const PlanningError& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    for (const std::string& part : message_parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "'" << part << "' not in: " << e.what();
    }
  }
}

const std::vector<std::string> kCorridor = {
    "############",
    "#..........#",
    "#..........#",
    "#..........#",
    "############",
};

const std::vector<std::string> kUTurn = {
    "############",
    "#....i#....#",
    "#....i#....#",
    "#....i#....#",
    "#....i#....#",
    "#..........#",
    "#..........#",
    "############",
};

TEST(AStarPlannerTest, StraightCorridor) {
  const Costmap2D map = MapFromAscii(kCorridor);
  AStarPlanner planner({});
  const Pose2 start = Cell(1, 2, 1.0), goal = Cell(10, 2, -0.5);
  const Path path = planner.MakePlan(map, start, goal);
  ExpectPathClear(map, path, kRes);
  EXPECT_NEAR(PathLength(path), 0.9, 1e-9);
  EXPECT_DOUBLE_EQ(path.front().x, start.x);
  EXPECT_DOUBLE_EQ(path.front().y, start.y);
  EXPECT_NEAR(path.front().yaw, 0.0, 1e-12);  // Forward: along the corridor
  EXPECT_DOUBLE_EQ(path.back().x, goal.x);
  EXPECT_DOUBLE_EQ(path.back().y, goal.y);
  EXPECT_DOUBLE_EQ(path.back().yaw, goal.yaw);
  for (const Pose2& p : path) EXPECT_NEAR(p.y, start.y, 1e-12);
}

TEST(AStarPlannerTest, UTurnGoesAroundTheWall) {
  const Costmap2D map = MapFromAscii(kUTurn);
  AStarPlanner planner({});
  const Pose2 start = Cell(2, 5), goal = Cell(9, 5, 1.0);
  const Path path = planner.MakePlan(map, start, goal);
  ExpectPathClear(map, path, kRes);
  double min_y = 1e9;
  for (const Pose2& p : path) min_y = std::min(min_y, p.y);
  EXPECT_LT(min_y, 0.3) << "must pass below the wall (rows 1..2)";
  EXPECT_GT(PathLength(path), 0.9);
  EXPECT_DOUBLE_EQ(path.back().yaw, 1.0);
}

TEST(AStarPlannerTest, UnreachableGoalIsNoPath) {
  const Costmap2D map = MapFromAscii({
      "##########",
      "#...#....#",
      "#...#....#",
      "#...#....#",
      "##########",
  });
  AStarPlanner planner({});
  ExpectPlanError(&planner, map, Cell(1, 2), Cell(7, 2), Code::kNoPath,
                  {"no path", "start (0.150, 0.250)", "goal (0.750, 0.250)",
                   "cell (7, 2)"});
  // The planner is usable again after a failure.
  EXPECT_NO_THROW(planner.MakePlan(map, Cell(1, 1), Cell(3, 3)));
}

TEST(AStarPlannerTest, GoalInObstacleWithinTolerancePlansToNearestFree) {
  const Costmap2D map = MapFromAscii({
      "##########",
      "#........#",
      "#....###.#",
      "#....###.#",
      "#........#",
      "##########",
  });
  GlobalPlannerOptions o;
  o.default_tolerance = 0.15;
  AStarPlanner planner(o);
  // Goal near the left side of the block's cell (5, 2): the free cell (4, 2)
  // is 0.06 m away, (5, 1) 0.108 m.
  const Pose2 goal{0.51, 0.25, 2.0};
  const Path path = planner.MakePlan(map, Cell(1, 1), goal);
  ExpectPathClear(map, path, kRes);
  const Pose2 expected = Cell(4, 2);
  EXPECT_NEAR(path.back().x, expected.x, 1e-12);
  EXPECT_NEAR(path.back().y, expected.y, 1e-12);
  EXPECT_DOUBLE_EQ(path.back().yaw, 2.0);

  // Nothing within 0.05 m.
  GlobalPlannerOptions tight;
  tight.default_tolerance = 0.05;
  AStarPlanner strict(tight);
  ExpectPlanError(&strict, map, Cell(1, 1), goal, Code::kGoalOccupied,
                  {"goal (0.510, 0.250)", "cell (5, 2)", "254 (lethal)",
                   "default_tolerance 0.05"});
}

TEST(AStarPlannerTest, ToleranceFallsBackToAReachableCandidate) {
  // Goal in a wall; the nearest free cell is sealed off, the next nearest is
  // reachable: the failed search's closed set picks it.
  const Costmap2D map = MapFromAscii({
      "##########",
      "#...#.#..#",
      "#...###..#",
      "#........#",
      "##########",
  });
  GlobalPlannerOptions o;
  o.default_tolerance = 0.2;
  AStarPlanner planner(o);
  // (4, 3) is lethal; the free cell (5, 3) (0.09 m away) is sealed off; the
  // free cell (3, 3) (0.11 m away) is reachable.
  const Pose2 wall_goal{0.46, 0.35, 0.3};
  const Path path = planner.MakePlan(map, Cell(1, 1), wall_goal);
  ExpectPathClear(map, path, kRes);
  EXPECT_NEAR(path.back().x, Cell(3, 3).x, 1e-12);
  EXPECT_NEAR(path.back().y, Cell(3, 3).y, 1e-12);
  EXPECT_DOUBLE_EQ(path.back().yaw, 0.3);
}

TEST(AStarPlannerTest, StartInInflationIsAllowed) {
  const Costmap2D map = MapFromAscii({
      "##########",
      "#aa......#",
      "#aa......#",
      "##########",
  });
  AStarPlanner planner({});
  const Path path = planner.MakePlan(map, Cell(1, 1), Cell(8, 2));
  EXPECT_EQ(CostAt(map, path.front().x, path.front().y), 200);
  ExpectPathClear(map, path, kRes);
}

TEST(AStarPlannerTest, StartInInscribedBandStepsOutFirst) {
  // The robot's centre ended up in the inscribed band next to a wall: the
  // path leaves the band by the cheapest non-lethal cells, then never enters
  // it again (the band elsewhere stays impassable).
  const Costmap2D map = MapFromAscii({
      "##########",
      "#iii.....#",
      "#iii..i..#",
      "#iii..i..#",
      "##########",
  });
  AStarPlanner planner({});
  const Path path = planner.MakePlan(map, Cell(1, 2), Cell(8, 2));
  EXPECT_EQ(CostAt(map, path.front().x, path.front().y), kInscribedInflatedObstacle);
  bool left_band = false;
  for (const Pose2& p : path) {
    const int c = CostAt(map, p.x, p.y);
    EXPECT_NE(c, kLethalObstacle);
    if (c < kInscribedInflatedObstacle) left_band = true;
    if (left_band) {
      EXPECT_LT(c, kInscribedInflatedObstacle) << "re-entered the band at " << p.x;
    }
  }
  EXPECT_TRUE(left_band);
  // The inscribed column at x = 6 (not connected to the start's band) is not crossed.
  const Path around = planner.MakePlan(map, Cell(4, 2), Cell(8, 2));
  for (const Pose2& p : around) EXPECT_LT(CostAt(map, p.x, p.y), kInscribedInflatedObstacle);
}

TEST(AStarPlannerTest, StartOrGoalOffMapOrOccupied) {
  const Costmap2D map = MapFromAscii(kCorridor);
  AStarPlanner planner({});
  ExpectPlanError(&planner, map, {-1.0, 0.2, 0}, Cell(5, 2), Code::kStartOffMap,
                  {"start (-1.000, 0.200)", "localized"});
  ExpectPlanError(&planner, map, Cell(5, 2), {0.5, 7.0, 0}, Code::kGoalOffMap,
                  {"goal (0.500, 7.000)"});
  ExpectPlanError(&planner, map, Cell(0, 2), Cell(5, 2), Code::kStartOccupied,
                  {"start (0.050, 0.250)", "cell (0, 2)", "254 (lethal)"});
  ExpectPlanError(&planner, map, Cell(5, 2),
                  {std::numeric_limits<double>::quiet_NaN(), 0.2, 0},
                  Code::kInvalidInput, {"not finite"});
}

TEST(AStarPlannerTest, UnknownSpaceFollowsAllowUnknown) {
  // The direct route crosses an unknown band; the way around is long.
  const Costmap2D map = MapFromAscii({
      "################",
      "#......u.......#",
      "#......u.......#",
      "#......u.......#",
      "#......u.......#",
      "#####..u..######",
      "#......u.......#",
      "################",
  });
  const Pose2 start = Cell(2, 4), goal = Cell(12, 4);
  GlobalPlannerOptions allow;
  allow.allow_unknown = true;
  AStarPlanner permissive(allow);
  const Path through = permissive.MakePlan(map, start, goal);
  ExpectPathClear(map, through, kRes, /*allow_unknown=*/true);

  GlobalPlannerOptions deny;
  deny.allow_unknown = false;
  AStarPlanner strict(deny);
  ExpectPlanError(&strict, map, start, goal, Code::kNoPath, {"no path"});
  // An unknown goal cell is occupied for this planner.
  ExpectPlanError(&strict, map, start, Cell(7, 4), Code::kGoalOccupied,
                  {"255 (unknown)", "allow_unknown is false"});
  // ... but an unknown start is where the robot is: allowed.
  EXPECT_NO_THROW(strict.MakePlan(map, Cell(7, 2), Cell(5, 2)));

  // With an opening in the band the strict planner goes through the gap.
  Costmap2D open = map;
  open.set_cost(7, 1, kFreeSpace);
  const Path around = strict.MakePlan(open, start, goal);
  ExpectPathClear(open, around, kRes, /*allow_unknown=*/false);
  EXPECT_GT(PathLength(around), PathLength(through));
}

TEST(AStarPlannerTest, SmoothedPathIsClearNotLongerAndEndsAtGoal) {
  // Walls with an inflation gradient, so the raw path zig-zags through costs.
  const Costmap2D map = MapFromAscii({
      "####################",
      "#cccccccccccccccccc#",
      "#c................c#",
      "#c..iiiii.........c#",
      "#c..i###ibbbbbbb..c#",
      "#c..iiiiiaaaaaab..c#",
      "#c..........iiib..c#",
      "#c..........i#ib..c#",
      "#c..........iiib..c#",
      "#cccccccccccccccccc#",
      "####################",
  });
  GlobalPlannerOptions raw_opts;
  raw_opts.smooth_path = false;
  AStarPlanner raw_planner(raw_opts);
  AStarPlanner smooth_planner({});
  const std::vector<std::pair<Pose2, Pose2>> queries = {
      {Cell(2, 8, 0.3), Cell(17, 1, -2.0)},
      {Cell(2, 1), Cell(17, 8, 1.0)},
      {Cell(3, 2), Cell(15, 9 - 1, 0.0)},
      {{0.234, 0.171, 0.0}, {1.733, 0.812, 3.0}},
  };
  for (const auto& q : queries) {
    const Path raw = raw_planner.MakePlan(map, q.first, q.second);
    const Path smooth = smooth_planner.MakePlan(map, q.first, q.second);
    ExpectPathClear(map, raw, kRes * std::sqrt(2.0));
    ExpectPathClear(map, smooth, kRes);
    EXPECT_LE(PathLength(smooth), PathLength(raw) + 1e-9);
    int raw_max = 0;
    for (const Pose2& p : raw) raw_max = std::max(raw_max, CostAt(map, p.x, p.y));
    for (size_t i = 1; i < smooth.size(); ++i) {
      EXPECT_TRUE(SegmentCostsAtMost(
          map, {smooth[i - 1].x, smooth[i - 1].y}, {smooth[i].x, smooth[i].y},
          raw_max, smooth_planner.options()))
          << "segment " << i << " (" << smooth[i - 1].x << ", " << smooth[i - 1].y
          << ") -> (" << smooth[i].x << ", " << smooth[i].y
          << ") crosses a cell costlier than the raw path's " << raw_max;
    }
    EXPECT_DOUBLE_EQ(smooth.back().x, q.second.x);
    EXPECT_DOUBLE_EQ(smooth.back().y, q.second.y);
    EXPECT_DOUBLE_EQ(smooth.back().yaw, q.second.yaw);
    EXPECT_DOUBLE_EQ(raw.back().yaw, q.second.yaw);
    // Forward orientation: each yaw points at the next pose.
    for (size_t i = 0; i + 1 < smooth.size(); ++i) {
      const double heading = std::atan2(smooth[i + 1].y - smooth[i].y,
                                        smooth[i + 1].x - smooth[i].x);
      EXPECT_NEAR(AngleDiff(smooth[i].yaw, heading), 0.0, 1e-9) << i;
    }
  }
}

TEST(AStarPlannerTest, SmoothingRemovesTheZigZagInOpenSpace) {
  Costmap2D map(60, 60, kRes, 0.0, 0.0);
  AStarPlanner planner({});
  const Pose2 start = Cell(2, 3), goal = Cell(55, 40);
  const Path path = planner.MakePlan(map, start, goal);
  EXPECT_NEAR(PathLength(path), std::hypot(goal.x - start.x, goal.y - start.y),
              1e-9);
  EXPECT_GT(PolylineLength(planner.last_raw_path()), PathLength(path) + 0.1);
}

// Reference Dijkstra with the same step costs (doubles) for the optimality
// check below.
double ReferenceCost(const Costmap2D& map, const GlobalPlannerOptions& o,
                     int sx, int sy, int gx, int gy) {
  const int w = map.size_x(), h = map.size_y();
  std::vector<double> dist(w * h, std::numeric_limits<double>::infinity());
  std::vector<bool> done(w * h, false);
  auto passable = [&](int x, int y) {
    return map.InBounds(x, y) && IsTraversableCost(map.cost(x, y), o);
  };
  dist[sy * w + sx] = 0;
  for (;;) {
    int best = -1;
    for (int i = 0; i < w * h; ++i) {
      if (!done[i] && dist[i] < std::numeric_limits<double>::infinity() &&
          (best < 0 || dist[i] < dist[best])) {
        best = i;
      }
    }
    if (best < 0) return std::numeric_limits<double>::infinity();
    if (best == gy * w + gx) return dist[best];
    done[best] = true;
    const int x = best % w, y = best / w;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((!dx && !dy) || !passable(x + dx, y + dy)) continue;
        if (dx && dy && (!passable(x + dx, y) || !passable(x, y + dy))) continue;
        int c = map.cost(x + dx, y + dy);
        if (c == kNoInformation) c = AStarPlanner::kUnknownCellCost;
        const double step = (dx && dy ? std::sqrt(2.0) : 1.0) *
                            (o.neutral_cost + o.cost_factor * c);
        const int n = (y + dy) * w + x + dx;
        dist[n] = std::min(dist[n], dist[best] + step);
      }
    }
  }
}

double RawPathCost(const Costmap2D& map, const GlobalPlannerOptions& o,
                   const std::vector<Point2>& raw) {
  double cost = 0;
  for (size_t i = 1; i < raw.size(); ++i) {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    map.WorldToMap(raw[i - 1].x, raw[i - 1].y, &x0, &y0);
    map.WorldToMap(raw[i].x, raw[i].y, &x1, &y1);
    int c = map.cost(x1, y1);
    if (c == kNoInformation) c = AStarPlanner::kUnknownCellCost;
    const bool diag = x0 != x1 && y0 != y1;
    cost += (diag ? std::sqrt(2.0) : 1.0) * (o.neutral_cost + o.cost_factor * c);
  }
  return cost;
}

TEST(AStarPlannerTest, PathCostIsOptimalOnRandomMaps) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cost_dist(0, 255);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  GlobalPlannerOptions o;
  AStarPlanner planner(o);  // one planner: buffers reused across sizes
  int solved = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int w = 8 + trial % 13, h = 6 + trial % 7;
    Costmap2D map(w, h, kRes, -0.3, 0.2);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double r = u(rng);
        map.set_cost(x, y, r < 0.2 ? kLethalObstacle
                           : r < 0.3 ? kNoInformation
                           : r < 0.6 ? static_cast<uint8_t>(cost_dist(rng) % 253)
                                     : 0);
      }
    }
    map.set_cost(0, 0, 0);
    map.set_cost(w - 1, h - 1, 0);
    double sx, sy, gx, gy;
    map.MapToWorld(0, 0, &sx, &sy);
    map.MapToWorld(w - 1, h - 1, &gx, &gy);
    const double ref = ReferenceCost(map, o, 0, 0, w - 1, h - 1);
    if (std::isinf(ref)) {
      EXPECT_THROW(planner.MakePlan(map, {sx, sy, 0}, {gx, gy, 0}), PlanningError);
      continue;
    }
    ++solved;
    planner.MakePlan(map, {sx, sy, 0}, {gx, gy, 0});
    EXPECT_NEAR(RawPathCost(map, o, planner.last_raw_path()), ref, 1e-6 * ref)
        << "trial " << trial;
  }
  EXPECT_GT(solved, 10);
}

TEST(AStarPlannerTest, OrientationModes) {
  const Costmap2D map = MapFromAscii(kCorridor);
  const Pose2 start = Cell(1, 2, 0.5), goal = Cell(10, 2, 1.5);
  GlobalPlannerOptions none;
  none.orientation_mode = 0;
  const Path p0 = AStarPlanner(none).MakePlan(map, start, goal);
  for (size_t i = 0; i + 1 < p0.size(); ++i) EXPECT_EQ(p0[i].yaw, 0.0);
  EXPECT_DOUBLE_EQ(p0.back().yaw, 1.5);
  GlobalPlannerOptions interp;
  interp.orientation_mode = 2;
  const Path p2 = AStarPlanner(interp).MakePlan(map, start, goal);
  EXPECT_NEAR(p2.front().yaw, 0.5, 1e-12);
  EXPECT_NEAR(p2[p2.size() / 2].yaw, 1.0, 0.06);
  EXPECT_DOUBLE_EQ(p2.back().yaw, 1.5);
}

TEST(AStarPlannerTest, StartAndGoalInTheSameCell) {
  const Costmap2D map = MapFromAscii(kCorridor);
  AStarPlanner planner({});
  const Path path = planner.MakePlan(map, {0.52, 0.21, 0}, {0.57, 0.27, 1.0});
  ASSERT_EQ(path.size(), 2u);
  EXPECT_DOUBLE_EQ(path.back().x, 0.57);
  EXPECT_DOUBLE_EQ(path.back().yaw, 1.0);
  const Path same = planner.MakePlan(map, {0.52, 0.21, 0}, {0.52, 0.21, 1.0});
  ASSERT_EQ(same.size(), 1u);
  EXPECT_DOUBLE_EQ(same[0].yaw, 1.0);
}

TEST(GlobalPlannerOptionsTest, ValidationListsEveryBadValue) {
  GlobalPlannerOptions o;
  o.base_global_planner = "carrot_planner/CarrotPlanner";
  o.default_tolerance = -1;
  o.neutral_cost = 0;
  o.cost_factor = std::numeric_limits<double>::quiet_NaN();
  o.lethal_cost = 255;
  o.orientation_mode = 5;
  o.ompl_planner = "rrt";
  o.ompl_planning_time = 0;
  o.ompl_interpolation_resolution = -0.1;
  o.ompl_seed = -3;
  try {
    ValidateGlobalPlannerOptions(o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const char* part :
         {"base_global_planner='carrot_planner/CarrotPlanner'",
          "default_tolerance=-1", "neutral_cost=0", "cost_factor=nan",
          "lethal_cost=255", "orientation_mode=5", "ompl_planner='rrt'",
          "ompl_planning_time=0", "ompl_interpolation_resolution=-0.1",
          "ompl_seed=-3"}) {
      EXPECT_NE(msg.find(part), std::string::npos) << part << " in " << msg;
    }
  }
  EXPECT_NO_THROW(ValidateGlobalPlannerOptions(GlobalPlannerOptions()));
  EXPECT_THROW(AStarPlanner{o}, std::invalid_argument);
}

TEST(GlobalPlannerOptionsTest, SetByRosName) {
  GlobalPlannerOptions o;
  SetGlobalPlannerOption("default_tolerance", "0.5", &o);
  SetGlobalPlannerOption("allow_unknown", "false", &o);
  SetGlobalPlannerOption("neutral_cost", " 66 ", &o);
  SetGlobalPlannerOption("ompl_planner", "prmstar", &o);
  SetGlobalPlannerOption("base_global_planner", "navfn/NavfnROS", &o);
  EXPECT_EQ(o.default_tolerance, 0.5);
  EXPECT_FALSE(o.allow_unknown);
  EXPECT_EQ(o.neutral_cost, 66);
  EXPECT_EQ(o.ompl_planner, "prmstar");
  EXPECT_NO_THROW(ValidateGlobalPlannerOptions(o));
  EXPECT_THROW(SetGlobalPlannerOption("neutral_cost", "6.5", &o),
               std::invalid_argument);
  EXPECT_THROW(SetGlobalPlannerOption("visualize_potential", "true", &o),
               std::invalid_argument);
  EXPECT_FALSE(IsGlobalPlannerOptionName("use_dijkstra"));
  EXPECT_TRUE(IsGlobalPlannerOptionName("lethal_cost"));
  EXPECT_EQ(GlobalPlannerOptionNames().front(), "base_global_planner");
}

TEST(PlannerFactoryTest, NamesAndAliases) {
  const Footprint fp = MakeCircleFootprint(0.15);
  for (const char* n : {"astar", "navfn/NavfnROS", "global_planner/GlobalPlanner"}) {
    EXPECT_EQ(MakeGlobalPlanner(n, {}, fp)->name(), "astar") << n;
  }
  EXPECT_EQ(MakeGlobalPlanner("ompl", {}, fp)->name(), "ompl/rrtstar");
  GlobalPlannerOptions o;
  o.base_global_planner = "ompl";
  o.ompl_planner = "rrtconnect";
  EXPECT_EQ(MakeGlobalPlanner(o, fp)->name(), "ompl/rrtconnect");
  try {
    MakeGlobalPlanner("carrot_planner/CarrotPlanner", {}, fp);
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("carrot_planner/CarrotPlanner"), std::string::npos);
    EXPECT_NE(msg.find("astar, navfn/NavfnROS, global_planner/GlobalPlanner, ompl"),
              std::string::npos)
        << msg;
  }
}

TEST(PathSmoothingTest, SegmentCheckTouchesCornerCells) {
  Costmap2D map(4, 4, 1.0, 0.0, 0.0);
  map.set_cost(1, 0, kLethalObstacle);
  GlobalPlannerOptions o;
  // The diagonal (0.5,0.5)->(1.5,1.5) passes exactly through the corner of
  // the lethal cell (1, 0) without entering it; slightly lower it enters.
  EXPECT_TRUE(SegmentCostsAtMost(map, {0.5, 0.5}, {1.5, 1.5}, 0, o));
  EXPECT_FALSE(SegmentCostsAtMost(map, {0.5, 0.5}, {1.5, 1.45}, 0, o));
  EXPECT_TRUE(SegmentCostsAtMost(map, {0.5, 0.5}, {1.5, 1.55}, 0, o));
  // Ending exactly on the border of the lethal cell does not enter it.
  EXPECT_TRUE(SegmentCostsAtMost(map, {0.5, 0.5}, {1.0, 0.5}, 0, o));
  EXPECT_FALSE(SegmentCostsAtMost(map, {0.5, 0.5}, {1.01, 0.5}, 0, o));
  EXPECT_TRUE(SegmentCostsAtMost(map, {0.5, 0.5}, {0.5, 3.5}, 0, o));
  map.set_cost(0, 2, 40);
  EXPECT_FALSE(SegmentCostsAtMost(map, {0.5, 0.5}, {0.5, 3.5}, 39, o));
  EXPECT_TRUE(SegmentCostsAtMost(map, {0.5, 0.5}, {0.5, 3.5}, 40, o));
  EXPECT_FALSE(SegmentCostsAtMost(map, {0.5, 0.5}, {0.5, 4.5}, 255, o));  // off map
}

TEST(PathSmoothingTest, ResampleKeepsCornersAndSpacing) {
  const std::vector<Point2> pts = {{0, 0}, {1, 0}, {1, 0.25}};
  const std::vector<Point2> r = ResamplePolyline(pts, 0.3);
  ASSERT_EQ(r.size(), 1u + 4u + 1u);
  EXPECT_DOUBLE_EQ(r[4].x, 1.0);
  EXPECT_DOUBLE_EQ(r[4].y, 0.0);
  EXPECT_NEAR(PolylineLength(r), 1.25, 1e-12);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
