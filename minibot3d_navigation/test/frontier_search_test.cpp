// Frontier search on small inline maps: frontier detection and clustering, the
// goal on the robot's side and in sight of its frontier, unreachable frontiers
// dropped, excluded viewpoints, "nothing left" once a room is closed; and the
// exploration memory (reached viewpoints never again, unreachable goals retried
// once the map round them changes, a limit on attempts); the explore node's
// options.
#include "minibot3d_navigation/explore/frontier_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "minibot3d_navigation/explore/explore_node_options.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr double kRes = 0.1;

// '.' free, '#' occupied, '?' unknown; row 0 of the text is the top (max y).
OccupancyGrid Grid(const std::vector<std::string>& rows) {
  OccupancyGrid g;
  g.resolution = kRes;
  g.height = static_cast<int>(rows.size());
  g.width = static_cast<int>(rows[0].size());
  g.data.resize(g.width * g.height);
  for (int r = 0; r < g.height; ++r) {
    for (int x = 0; x < g.width; ++x) {
      const char c = rows[r][x];
      g.data[(g.height - 1 - r) * g.width + x] = c == '#' ? 100 : (c == '?' ? -1 : 0);
    }
  }
  return g;
}

Pose2 At(int x, int y) { return {(x + 0.5) * kRes, (y + 0.5) * kRes, 0.0}; }

ExploreOptions Options() {
  ExploreOptions o;
  o.clearance = 0.1;
  o.goal_clearance = 0.1;
  o.min_frontier_size = 0.2;
  o.goal_search_radius = 0.2;
  return o;
}

TEST(FrontierSearch, FindsTheOpenSideOfARoom) {
  // A room open to unknown space on its right.
  const auto grid = Grid({
      "##########???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "##########???",
  });
  FrontierSearch search(Options());
  const auto r = search.Find(grid, At(2, 2), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_NEAR(f.centroid.x, 9.5 * kRes, 1e-9);
  EXPECT_NEAR(f.size, 0.4, 1e-9);  // four frontier cells
  EXPECT_GT(f.goal.x, 0.6);        // the goal is near the opening
  EXPECT_NEAR(f.distance, std::hypot(f.goal.x - At(2, 2).x, f.goal.y - At(2, 2).y), 0.1);
  EXPECT_NEAR(r.known_free_area, 36 * kRes * kRes, 1e-9);
}

TEST(FrontierSearch, ClosedRoomHasNoFrontier) {
  const auto grid = Grid({
      "#######",
      "#.....#",
      "#.....#",
      "#.....#",
      "#######",
  });
  FrontierSearch search(Options());
  EXPECT_TRUE(search.Find(grid, At(3, 2), {}).frontiers.empty());
}

TEST(FrontierSearch, UnreachableAndSmallFrontiersAreDropped) {
  // Left room: the robot.  Right room behind a wall: a frontier it can't reach.
  // One lone unknown cell in the robot's room: too small.
  const auto grid = Grid({
      "#############",
      "#.....#.....?",
      "#.....#.....?",
      "#.?...#.....?",
      "#.....#.....?",
      "#.....#.....?",
      "#############",
  });
  ExploreOptions o = Options();
  o.min_frontier_size = 0.45;  // the lone unknown cell has 4 frontier cells: 0.4 m
  FrontierSearch search(o);
  const auto r = search.Find(grid, At(4, 3), {});
  EXPECT_TRUE(r.frontiers.empty());
  EXPECT_EQ(r.unreachable, 1);
}

TEST(FrontierSearch, NearestFirstAndBlacklist) {
  const auto grid = Grid({
      "?###############?",
      "?...............?",
      "?...............?",
      "?...............?",
      "?###############?",
  });
  FrontierSearch search(Options());
  auto r = search.Find(grid, At(4, 2), {});
  ASSERT_EQ(r.frontiers.size(), 2u);
  EXPECT_LT(r.frontiers[0].centroid.x, r.frontiers[1].centroid.x);  // left one is nearer
  r = search.Find(grid, At(4, 2), {r.frontiers[0].goal});
  ASSERT_EQ(r.frontiers.size(), 1u);
  EXPECT_EQ(r.blacklisted, 1);
  EXPECT_GT(r.frontiers[0].centroid.x, 1.0);
}

// A room with a thin shelf (column 6) and a gap behind it, open to unknown
// space at the gap's far end (top right).
OccupancyGrid ThinShelfRoom() {
  return Grid({
      "###########",
      "#.....#???#",
      "#.....#...#",
      "#.....#...#",
      "#.....#...#",
      "#.........#",
      "###########",
  });
}

// Goals anywhere free, single-cell frontiers kept.
ExploreOptions ThinShelfOptions(double goal_search_radius) {
  ExploreOptions o = Options();
  o.clearance = 0.0;
  o.goal_clearance = 0.0;
  o.goal_search_radius = goal_search_radius;
  o.min_frontier_size = 0.1;
  return o;
}

TEST(FrontierSearch, TheViewpointSeesItsFrontier) {
  // A gap behind a thin shelf (column 6), open to unknown space at its far end
  // (top right).  The cells just left of the shelf are within reach of the
  // frontier and nearer the robot than the gap's cells, but the shelf hides the
  // frontier from them: the viewpoint must be where the gap is in sight.
  const auto grid = ThinShelfRoom();
  const ExploreOptions o = ThinShelfOptions(0.2);
  FrontierSearch search(o);
  const auto r = search.Find(grid, At(1, 1), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_GT(f.goal.x, 7 * kRes) << "goal (" << f.goal.x << ", " << f.goal.y << ")";
}

TEST(FrontierSearch, ExcludedViewpointsLeaveTheOthers) {
  // A long opening on the right: excluding the viewpoint the robot reached moves
  // the goal along the frontier instead of dropping the frontier.
  const auto grid = Grid({
      "############?",
      "#...........?",
      "#...........?",
      "#...........?",
      "#...........?",
      "#...........?",
      "#...........?",
      "#...........?",
      "#...........?",
      "############?",
  });
  ExploreOptions o = Options();
  o.blacklist_radius = 0.25;
  FrontierSearch search(o);
  auto r = search.Find(grid, At(2, 1), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Point2 first = r.frontiers[0].goal;
  r = search.Find(grid, At(2, 1), {first});
  ASSERT_EQ(r.frontiers.size(), 1u);
  EXPECT_GE(std::hypot(r.frontiers[0].goal.x - first.x, r.frontiers[0].goal.y - first.y), 0.25);
  EXPECT_EQ(r.blacklisted, 0);
  // Excluding the whole opening's side drops the frontier, counted as blacklisted.
  std::vector<Point2> all;
  for (int y = 0; y < 10; ++y) all.push_back({At(11, y).x, At(11, y).y});
  r = search.Find(grid, At(2, 1), all);
  EXPECT_TRUE(r.frontiers.empty());
  EXPECT_EQ(r.blacklisted, 1);
}

TEST(FrontierSearch, CellsLookedAtNoLongerCount) {
  // The thin-shelf room: from the gap's mouth the frontier is in sight; from
  // left of the shelf, at the same distance, it is not.
  const auto grid = ThinShelfRoom();
  const ExploreOptions o = ThinShelfOptions(0.25);
  FrontierSearch search(o);
  EXPECT_TRUE(search.InSight(grid, {At(5, 4).x, At(5, 4).y}).empty());
  const auto cells = search.InSight(grid, {At(8, 3).x, At(8, 3).y});
  EXPECT_EQ(cells.size(), 3u);  // the gap's top row, x 7..9
  ExplorationMemory memory(o);
  memory.Reached({At(8, 3).x, At(8, 3).y});
  memory.LookedAt(cells);
  EXPECT_EQ(memory.Excluded().size(), 1u);  // the viewpoint
  auto r = search.Find(grid, At(1, 1), {}, memory.looked_at());
  EXPECT_TRUE(r.frontiers.empty()) << "the cells stayed frontier with the robot there";
  // Cells that were not looked at still count.
  r = search.Find(grid, At(1, 1), {}, {cells[0]});
  EXPECT_EQ(r.frontiers.size(), 1u);
}

TEST(FrontierSearch, NoGoalInAPocketTooNarrowToTurnIn) {
  // A room with a 0.3 m slot off it (text rows 2-4, columns 8-10), unknown
  // beyond it.  Paths may pass 0.1 m from walls, goals need 0.2 m: the slot's
  // frontier gets no goal inside the slot, so the robot is not sent into a
  // pocket it cannot turn round in; seen from the room it still gets one.
  const auto grid = Grid({
      "###############",
      "#.......#######",
      "#..........????",
      "#..........????",
      "#..........????",
      "#.......#######",
      "#.......#######",
      "###############",
  });
  ExploreOptions o = Options();
  o.goal_clearance = 0.2;
  o.goal_search_radius = 0.5;
  FrontierSearch search(o);
  auto r = search.Find(grid, At(2, 2), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  EXPECT_LT(r.frontiers[0].goal.x, 0.8) << "goal (" << r.frontiers[0].goal.x << ")";
  o.goal_search_radius = 0.2;  // nothing roomy within reach of the frontier
  r = FrontierSearch(o).Find(grid, At(2, 2), {});
  EXPECT_TRUE(r.frontiers.empty());
  EXPECT_EQ(r.unreachable, 1);
}

TEST(ExplorationMemory, ReachedViewpointsAreNotUsedAgain) {
  ExplorationMemory memory(Options());
  memory.Reached({1.0, 2.0});
  EXPECT_TRUE(memory.Refresh(Grid({"....", "...."})).empty());
  ASSERT_EQ(memory.Excluded().size(), 1u);
  EXPECT_EQ(memory.Excluded()[0].x, 1.0);
}

TEST(ExplorationMemory, UnreachableGoalsAreRetriedWhenTheMapRoundThemChanges) {
  ExploreOptions o = Options();
  o.retry_window = 0.5;
  o.retry_map_change = 0.05;  // 5 cells of 0.1 m
  o.max_goal_attempts = 2;
  ExplorationMemory memory(o);
  auto grid = Grid({
      "??????????",
      "??????????",
      "....??????",
      "....??????",
      "??????????",
  });
  const Point2 goal{0.55, 0.25};
  EXPECT_EQ(memory.Failed(goal, grid), 1);
  EXPECT_EQ(memory.Excluded().size(), 1u);
  EXPECT_TRUE(memory.Refresh(grid).empty()) << "nothing changed";
  // Four cells change: below the threshold.
  for (int x = 4; x < 8; ++x) grid.data[1 * grid.width + x] = 0;
  EXPECT_TRUE(memory.Refresh(grid).empty());
  // Two more: six cells (0.06 m^2) changed; the goal is released.
  for (int x = 4; x < 6; ++x) grid.data[2 * grid.width + x] = 0;
  const auto released = memory.Refresh(grid);
  ASSERT_EQ(released.size(), 1u);
  EXPECT_NEAR(released[0].x, goal.x, 1e-12);
  EXPECT_TRUE(memory.Excluded().empty());
  // It fails again nearby: a second attempt, the last one; no change releases it now.
  EXPECT_EQ(memory.Failed({0.6, 0.3}, grid), 2);
  for (int x = 0; x < 10; ++x) grid.data[4 * grid.width + x] = 100;
  EXPECT_TRUE(memory.Refresh(grid).empty());
  EXPECT_EQ(memory.Excluded().size(), 1u);
}

TEST(ExplorationMemory, AMapThatGrowsDoesNotReleaseByItself) {
  // SLAM maps grow (a new origin, more cells): the window is sampled in map
  // coordinates, so the same cells in a bigger grid are no change.
  ExplorationMemory memory(Options());
  const auto small = Grid({"....", "....", "...."});
  memory.Failed({0.15, 0.15}, small);
  auto big = Grid({"??????", "?....?", "?....?", "?....?", "??????"});
  big.origin_x = -0.1;
  big.origin_y = -0.1;
  EXPECT_TRUE(memory.Refresh(big).empty());
}

TEST(FrontierSearch, RobotNextToAWallStillFindsItsWay) {
  const auto grid = Grid({
      "##########",
      "#........?",
      "#........?",
      "#........?",
      "##########",
  });
  ExploreOptions o = Options();
  o.clearance = 0.15;  // the robot's cell (next to the wall) is not traversable
  o.goal_clearance = 0.15;
  FrontierSearch search(o);
  const auto r = search.Find(grid, At(1, 1), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
}

// Lasers at a robot's ends do not see under it: its own cell stays unknown in the map. The search
// starts from the nearest free cell instead (else nothing is reachable and exploration ends at
// once, as it did with the start cell alone).
TEST(FrontierSearch, ARobotStandingOnUnknownCellsStartsFromTheNearestFreeOne) {
  const auto grid = Grid({
      "##########???",
      "#.........???",
      "#.???.....???",
      "#.???.....???",
      "#.???.....???",
      "#.........???",
      "##########???",
  });
  FrontierSearch search(Options());
  const auto r = search.Find(grid, At(3, 3), {});
  ASSERT_GE(r.frontiers.size(), 1u);
  bool open_side = false;
  for (const Frontier& f : r.frontiers) open_side |= f.centroid.x > 9 * kRes;
  EXPECT_TRUE(open_side);
  // Farther than start_search_radius from any free cell: nothing is reachable.
  ExploreOptions o = Options();
  o.start_search_radius = 0.05;
  EXPECT_TRUE(FrontierSearch(o).Find(grid, At(3, 3), {}).frontiers.empty());
}

TEST(FrontierSearch, BadInputIsRejectedSayingWhy) {
  FrontierSearch search(Options());
  OccupancyGrid g = Grid({"...", "..."});
  try {
    search.Find(g, {5.0, 5.0, 0.0}, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("off the map"), std::string::npos);
  }
  g.data.pop_back();
  EXPECT_THROW(search.Find(g, At(0, 0), {}), std::invalid_argument);
  ExploreOptions o;
  o.clearance = -1.0;
  EXPECT_THROW(FrontierSearch{o}, std::invalid_argument);
  EXPECT_THROW(SetExploreOption("clearence", "0.2", &o), std::invalid_argument);
  o = ExploreOptions();
  o.max_goal_attempts = 0;
  try {
    ExplorationMemory{o};
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_goal_attempts=0"), std::string::npos) << e.what();
  }
  o = ExploreOptions();
  o.retry_map_change = -1.0;
  EXPECT_THROW(FrontierSearch{o}, std::invalid_argument);
  o = ExploreOptions();
  o.look_radius = 0.2;  // below goal_search_radius 0.4
  EXPECT_THROW(FrontierSearch{o}, std::invalid_argument);
}

TEST(ExploreNodeOptionsTest, ValidationNamesEveryBadValue) {
  ExploreNodeOptions o;
  EXPECT_NO_THROW(ValidateExploreNodeOptions(o));
  ExploreNodeOptionTable().Set("planner_frequency", "0", &o);
  o.progress_timeout = -1.0;
  o.global_frame = " ";
  try {
    ValidateExploreNodeOptions(o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const char* expected : {"planner_frequency=0 must be > 0",
                                 "progress_timeout=-1 must be > 0", "global_frame"}) {
      EXPECT_NE(msg.find(expected), std::string::npos) << "missing '" << expected << "' in " << msg;
    }
  }
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
