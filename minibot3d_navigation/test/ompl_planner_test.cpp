// Tests of the OMPL global planner on tiny inline maps: corridor and U-turn
// solved by each algorithm with every pose valid, unreachable goal reported
// as kNoPath at once, start/goal errors shared with A*, reproducible plans
// with ompl_seed, and the footprint check for a non-circular robot.
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/planner/ompl_planner.h"
#include "minibot3d_navigation/planner/path_smoothing.h"
#include "minibot3d_navigation/planner/planner_factory.h"
#include "planner_test_maps.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

using Code = PlanningError::Code;
using testing::Cell;
using testing::kRes;
using testing::MapFromAscii;

const std::vector<std::string> kCorridor = {
    "################",
    "#..............#",
    "#..............#",
    "#..............#",
    "################",
};

const std::vector<std::string> kUTurn = {
    "################",
    "#......i#......#",
    "#......i#......#",
    "#......i#......#",
    "#......i#......#",
    "#......i#......#",
    "#..............#",
    "#..............#",
    "################",
};

GlobalPlannerOptions Options(const std::string& algorithm, double time = 0.2) {
  GlobalPlannerOptions o;
  o.base_global_planner = "ompl";
  o.ompl_planner = algorithm;
  o.ompl_planning_time = time;
  o.ompl_interpolation_resolution = kRes;
  o.ompl_seed = 17;
  return o;
}

void ExpectValidPath(const OmplPlanner& planner, const Costmap2D& map,
                     const Path& path, const Pose2& start, const Pose2& goal) {
  ASSERT_GE(path.size(), 2u);
  EXPECT_DOUBLE_EQ(path.front().x, start.x);
  EXPECT_DOUBLE_EQ(path.front().y, start.y);
  EXPECT_DOUBLE_EQ(path.back().x, goal.x);
  EXPECT_DOUBLE_EQ(path.back().y, goal.y);
  EXPECT_DOUBLE_EQ(path.back().yaw, goal.yaw);
  for (size_t i = 0; i < path.size(); ++i) {
    EXPECT_TRUE(planner.IsValid(map, path[i]))
        << "pose " << i << " (" << path[i].x << ", " << path[i].y << ", "
        << path[i].yaw << ")";
    if (i > 0) {
      EXPECT_LE(std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y),
                kRes + 1e-9);
    }
  }
}

class OmplAlgorithmTest : public ::testing::TestWithParam<std::string> {};

TEST_P(OmplAlgorithmTest, SolvesCorridor) {
  const Costmap2D map = MapFromAscii(kCorridor);
  OmplPlanner planner(Options(GetParam()), MakeCircleFootprint(0.1));
  const Pose2 start = Cell(1, 2, 0.3), goal = Cell(14, 2, -1.0);
  const Path path = planner.MakePlan(map, start, goal);
  ExpectValidPath(planner, map, path, start, goal);
  EXPECT_LT(PathLength(path), 1.3 * 1.3);
}

TEST_P(OmplAlgorithmTest, SolvesUTurn) {
  const Costmap2D map = MapFromAscii(kUTurn);
  OmplPlanner planner(Options(GetParam(), 0.3), MakeCircleFootprint(0.1));
  const Pose2 start = Cell(3, 6), goal = Cell(12, 6, 1.57);
  const Path path = planner.MakePlan(map, start, goal);
  ExpectValidPath(planner, map, path, start, goal);
  double min_y = 1e9;
  for (const Pose2& p : path) min_y = std::min(min_y, p.y);
  EXPECT_LT(min_y, 0.3) << "must pass below the wall";
  // Forward orientation: each yaw points at the next pose.
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const double heading =
        std::atan2(path[i + 1].y - path[i].y, path[i + 1].x - path[i].x);
    EXPECT_NEAR(AngleDiff(path[i].yaw, heading), 0.0, 1e-9) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Algorithms, OmplAlgorithmTest,
                         ::testing::Values("rrtconnect", "rrtstar", "prmstar"));

TEST(OmplPlannerTest, UnreachableGoalIsNoPathWithoutWaiting) {
  const Costmap2D map = MapFromAscii({
      "############",
      "#....#.....#",
      "#....#.....#",
      "#....#.....#",
      "############",
  });
  OmplPlanner planner(Options("rrtstar", 5.0), {});
  const auto t0 = std::chrono::steady_clock::now();
  try {
    planner.MakePlan(map, Cell(1, 2), Cell(9, 2));
    FAIL() << "expected kNoPath";
  } catch (const PlanningError& e) {
    EXPECT_EQ(e.code(), Code::kNoPath) << e.what();
    EXPECT_NE(std::string(e.what()).find("start (0.150, 0.250)"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("goal (0.950, 0.250)"), std::string::npos);
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
            1.0);
}

TEST(OmplPlannerTest, ReachableButUnsolvedInTimeIsTimeout) {
  const Costmap2D map = MapFromAscii(kUTurn);
  OmplPlanner planner(Options("rrtstar", 1e-6), {});
  try {
    planner.MakePlan(map, Cell(3, 6), Cell(12, 6));
    FAIL() << "expected kTimeout";
  } catch (const PlanningError& e) {
    EXPECT_EQ(e.code(), Code::kTimeout) << e.what();
    EXPECT_NE(std::string(e.what()).find("ompl_planning_time"), std::string::npos)
        << e.what();
  }
}

TEST(OmplPlannerTest, StartGoalErrorsMatchAStar) {
  const Costmap2D map = MapFromAscii(kCorridor);
  OmplPlanner planner(Options("rrtconnect"), {});
  auto code_of = [&](const Pose2& s, const Pose2& g) {
    try {
      planner.MakePlan(map, s, g);
    } catch (const PlanningError& e) {
      return e.code();
    }
    return Code::kInvalidInput;  // not thrown: a distinct, unexpected value
  };
  EXPECT_EQ(code_of({-0.5, 0.2, 0}, Cell(3, 2)), Code::kStartOffMap);
  EXPECT_EQ(code_of(Cell(3, 2), {0.5, 9.0, 0}), Code::kGoalOffMap);
  EXPECT_EQ(code_of(Cell(0, 0), Cell(3, 2)), Code::kStartOccupied);
  EXPECT_EQ(code_of(Cell(3, 2), Cell(15, 2)), Code::kGoalOccupied);
  // Goal in the wall, free cells within the tolerance: ends on one of them.
  GlobalPlannerOptions o = Options("rrtconnect");
  o.default_tolerance = 0.12;
  OmplPlanner tolerant(o, {});
  const Path path = tolerant.MakePlan(map, Cell(3, 2), {1.55, 0.25, 0.7});
  EXPECT_NEAR(path.back().x, Cell(14, 2).x, 1e-12);
  EXPECT_NEAR(path.back().y, Cell(14, 2).y, 1e-12);
  EXPECT_DOUBLE_EQ(path.back().yaw, 0.7);
}

TEST(OmplPlannerTest, SeedMakesRrtConnectReproducible) {
  const Costmap2D map = MapFromAscii(kUTurn);
  OmplPlanner a(Options("rrtconnect"), {});
  OmplPlanner b(Options("rrtconnect"), {});
  const Path pa = a.MakePlan(map, Cell(3, 6), Cell(12, 6));
  const Path pb = b.MakePlan(map, Cell(3, 6), Cell(12, 6));
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    EXPECT_DOUBLE_EQ(pa[i].x, pb[i].x);
    EXPECT_DOUBLE_EQ(pa[i].y, pb[i].y);
  }
}

TEST(OmplPlannerTest, UnknownSpaceFollowsAllowUnknown) {
  const Costmap2D map = MapFromAscii({
      "############",
      "#....u.....#",
      "#....u.....#",
      "#....u.....#",
      "############",
  });
  GlobalPlannerOptions deny = Options("rrtconnect");
  deny.allow_unknown = false;
  OmplPlanner strict(deny, {});
  EXPECT_THROW(strict.MakePlan(map, Cell(1, 2), Cell(9, 2)), PlanningError);
  OmplPlanner permissive(Options("rrtconnect"), {});
  const Path path = permissive.MakePlan(map, Cell(1, 2), Cell(9, 2));
  ExpectValidPath(permissive, map, path, Cell(1, 2), Cell(9, 2));
}

TEST(OmplPlannerTest, RectangularFootprintIsCheckedAtEachPose) {
  // A 0.7 m x 0.2 m robot in a 0.5 m wide corridor fits only lengthwise.
  const Costmap2D map = MapFromAscii({
      "####################",
      "#..................#",
      "#..................#",
      "#..................#",
      "#..................#",
      "#..................#",
      "####################",
  });
  const Footprint rect = {{0.35, 0.1}, {-0.35, 0.1}, {-0.35, -0.1}, {0.35, -0.1}};
  OmplPlanner planner(Options("rrtconnect", 0.5), rect);
  EXPECT_TRUE(planner.IsValid(map, {1.0, 0.35, 0.0}));
  EXPECT_FALSE(planner.IsValid(map, {1.0, 0.35, kPi / 2}));
  const Pose2 start{0.6, 0.35, 0.0}, goal{1.4, 0.35, 0.0};
  const Path path = planner.MakePlan(map, start, goal);
  ExpectValidPath(planner, map, path, start, goal);
}

TEST(OmplPlannerTest, FactoryAndOptionErrors) {
  EXPECT_EQ(MakeGlobalPlanner("ompl", Options("prmstar"), {})->name(), "ompl/prmstar");
  GlobalPlannerOptions bad = Options("rrt");
  EXPECT_THROW(OmplPlanner(bad, {}), std::invalid_argument);
  EXPECT_THROW(OmplPlanner(Options("rrtstar"), {{0, 0}, {1, 1}}), std::invalid_argument);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
