// Frontier search on small inline maps: frontier detection and clustering, the
// goal on the robot's side and in sight of its frontier, unreachable frontiers
// dropped, excluded viewpoints, "nothing left" once a room is closed, goals
// clear of unknown space, pockets too narrow to stand in looked into from off
// (in line with them, seen from wherever the robot stops; from a cramped cell
// when no roomy one sees them); and the
// exploration memory (reached viewpoints never again, unreachable goals retried
// once the map round them changes, a limit on attempts); the explore node's
// options.
#include "minibot3d_navigation/explore/frontier_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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
  ExploreOptions o = Options();
  o.view_range = 0.0;  // a frontier whose near viewpoints are excluded is dropped
  FrontierSearch search(o);
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
  o.view_range = 0.0;  // no looking from off: the last part checks the drop
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
  o.view_range = 0.0;
  r = FrontierSearch(o).Find(grid, At(2, 2), {});
  EXPECT_TRUE(r.frontiers.empty());
  EXPECT_EQ(r.unreachable, 1);
  // Looking from off, the slot is looked into from the room, its whole far end in sight.
  o.view_range = 1.0;
  const FrontierSearch from_off(o);
  r = from_off.Find(grid, At(2, 2), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_GT(f.view_radius, 0.0);
  EXPECT_LT(f.goal.x, 0.8) << "goal (" << f.goal.x << ")";
  EXPECT_EQ(from_off.InSight(grid, f.goal, f.view_radius).size(), 3u)
      << "goal (" << f.goal.x << ", " << f.goal.y << ")";
}

// A room with a gap 0.3 m wide between its top wall and a shelf (text row 4,
// columns 6-19), open to the room on its left; the gap's far part is unknown,
// as after a glance at a slant from below the shelf.
OccupancyGrid ShelfPocketRoom() {
  return Grid({
      "####################",
      "#.........?????????#",
      "#.........?????????#",
      "#.........?????????#",
      "#.....##############",
      "#..................#",
      "#..................#",
      "#..................#",
      "#..................#",
      "#..................#",
      "####################",
  });
}

TEST(FrontierSearch, APocketTooNarrowToStandInIsLookedIntoAlongItsLength) {
  // No cell in the gap is roomy enough for a goal (0.2 m from walls and unknown cells), so the
  // frontier at its mouth has no near viewpoint.  It gets one from off: a roomy cell in line
  // with the gap (text rows 1-3), from which every frontier cell's unknown side is in sight,
  // not one below the shelf, which sees past the mouth at a slant at most.
  const auto grid = ShelfPocketRoom();
  ExploreOptions o = Options();
  o.goal_clearance = 0.2;
  o.view_range = 1.5;
  o.goal_tolerance = 0.0;  // the robot stops on the goal
  FrontierSearch search(o);
  const Pose2 robot = At(15, 3);  // below the shelf, right
  auto r = search.Find(grid, robot, {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_EQ(f.cells, 3);
  EXPECT_GT(f.view_radius, 0.0) << "a near viewpoint in a 0.3 m gap";
  const int row = static_cast<int>(std::floor(f.goal.y / kRes));  // grid row, 0 = bottom
  EXPECT_GE(row, 7) << "goal (" << f.goal.x << ", " << f.goal.y << ") not in line with the gap";
  EXPECT_LE(row, 9) << "goal (" << f.goal.x << ", " << f.goal.y << ")";
  const auto seen = search.InSight(grid, f.goal, f.view_radius);
  EXPECT_EQ(seen.size(), 3u) << "the goal does not see the whole mouth";
  // Looked at from there and still unknown (the sensor could not clear it): the pocket counts
  // as explored, and exploration ends.
  ExplorationMemory memory(o);
  memory.Reached(f.goal);
  memory.LookedAt(seen);
  r = search.Find(grid, robot, memory.Excluded(), memory.looked_at());
  EXPECT_TRUE(r.frontiers.empty());
  // Without looking from off, the frontier is dropped (no viewpoint near it).
  o.view_range = 0.0;
  r = FrontierSearch(o).Find(grid, robot, {});
  EXPECT_TRUE(r.frontiers.empty());
  EXPECT_EQ(r.unreachable, 1);
}

// The fewest frontier cells in sight from any free cell within `tolerance` of `goal`.
size_t LeastInSightWithin(const FrontierSearch& search, const OccupancyGrid& grid,
                          const Frontier& f, double tolerance) {
  size_t least = std::numeric_limits<size_t>::max();
  const int r = static_cast<int>(std::floor(tolerance / kRes + 1e-9));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r * r) continue;
      const Point2 p{f.goal.x + dx * kRes, f.goal.y + dy * kRes};
      const int x = static_cast<int>(std::floor(p.x / kRes));
      const int y = static_cast<int>(std::floor(p.y / kRes));
      if (grid.data[y * grid.width + x] != 0) continue;
      least = std::min(least, search.InSight(grid, p, f.view_radius + 2 * tolerance).size());
    }
  }
  return least;
}

TEST(FrontierSearch, APocketIsLookedIntoFromWhereverTheRobotStopsNearTheGoal) {
  // A 0.3 m gap above a shelf (text row 4), open to the room on its left.  move_base stops
  // anywhere within its goal tolerance: a goal chosen for its own view alone may leave the robot
  // stopping where the shelf hides the gap's mouth; with the tolerance, every stop sees it.
  const auto grid = Grid({
      "##########################",
      "#........?????????????????#",
      "#........?????????????????#",
      "#........?????????????????#",
      "#........##################",
      "#.........................#",
      "#.........................#",
      "#.........................#",
      "#.........................#",
      "#.........................#",
      "#.........................#",
      "#.........................#",
      "##########################",
  });
  ExploreOptions o = Options();
  o.goal_clearance = 0.2;
  o.goal_search_radius = 0.1;  // no roomy cell near the mouth
  o.view_range = 2.0;
  const Pose2 robot = At(20, 3);
  o.goal_tolerance = 0.0;
  const FrontierSearch exact(o);
  auto r = exact.Find(grid, robot, {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  ASSERT_GT(r.frontiers[0].view_radius, 0.0)
      << "goal (" << r.frontiers[0].goal.x << ", " << r.frontiers[0].goal.y << ")";
  const size_t cells = static_cast<size_t>(r.frontiers[0].cells);
  EXPECT_EQ(LeastInSightWithin(exact, grid, r.frontiers[0], 0.2), 0u)
      << "the scene no longer shows the problem: every stop near goal (" << r.frontiers[0].goal.x
      << ", " << r.frontiers[0].goal.y << ") sees some of the mouth";
  o.goal_tolerance = 0.2;
  const FrontierSearch tolerant(o);
  r = tolerant.Find(grid, robot, {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  ASSERT_GT(r.frontiers[0].view_radius, 0.0);
  // Every stop sees the mouth: all of it, but for a stop on its lowest cell, which has the top
  // cell's unknown side only past the gap's corner.
  EXPECT_GE(LeastInSightWithin(tolerant, grid, r.frontiers[0], 0.2), cells - 1)
      << "goal (" << r.frontiers[0].goal.x << ", " << r.frontiers[0].goal.y << ")";
}

TEST(FrontierSearch, AFrontierNoRoomyCellSeesIsLookedIntoFromACrampedOne) {
  // A room (columns 1-5) with a 0.3 m passage off it (text rows 2-4) that bends down (columns
  // 15-17) and ends unknown (rows 7-8).  No cell of the room sees round the bend, and every cell
  // of the passage is closer to a wall than goal_clearance: only a cell the robot can merely
  // turn in (clearance from walls), past the bend, sees the frontier.
  const auto grid = Grid({
      "#####################",
      "#.....###############",
      "#.................###",
      "#.................###",
      "#.................###",
      "#.....#########...###",
      "#.....#########...###",
      "#.....#########???###",
      "#.....#########???###",
      "#####################",
  });
  ExploreOptions o = Options();
  o.goal_clearance = 0.2;
  o.view_range = 1.5;
  o.goal_tolerance = 0.0;
  const Pose2 robot = At(3, 4);
  o.creep_depth = 0.0;
  auto r = FrontierSearch(o).Find(grid, robot, {});
  EXPECT_TRUE(r.frontiers.empty()) << "the scene no longer shows the problem: a roomy cell sees "
                                      "the frontier";
  o.creep_depth = 2.0;
  const FrontierSearch search(o);
  r = search.Find(grid, robot, {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_TRUE(f.creeping);
  EXPECT_GT(f.view_radius, 0.0);
  const int x = static_cast<int>(std::floor(f.goal.x / kRes));
  const int y = static_cast<int>(std::floor(f.goal.y / kRes));
  EXPECT_GE(x, 10) << "goal (" << f.goal.x << ", " << f.goal.y << ") not past the passage's middle";
  EXPECT_GE(y, 3) << "goal (" << f.goal.x << ", " << f.goal.y << ")";
  EXPECT_EQ(search.InSight(grid, f.goal, f.view_radius).size(), 3u)
      << "goal (" << f.goal.x << ", " << f.goal.y << ") does not see the whole frontier";
  // Seen from there and still unknown: exploration ends.
  ExplorationMemory memory(o);
  memory.Reached(f.goal);
  memory.LookedAt(f.in_view);
  r = search.Find(grid, robot, memory.Excluded(), memory.looked_at());
  EXPECT_TRUE(r.frontiers.empty());
  // Such a viewpoint lies at most creep_depth from roomy space: no cell within 0.3 m of the
  // room sees round the bend, so the robot is not sent down the passage.
  o.creep_depth = 0.3;
  r = FrontierSearch(o).Find(grid, robot, {});
  EXPECT_TRUE(r.frontiers.empty()) << "goal (" << r.frontiers[0].goal.x << ", "
                                   << r.frontiers[0].goal.y << ") deep in the passage";
}

TEST(FrontierSearch, GoalsKeepTheirClearanceFromUnknownSpace) {
  // The room open on its right: a goal keeps goal_clearance from the unknown cells as from a
  // wall (an unseen face of a shelf may be there), though the robot, 0.2 m from the unknown
  // cells, already sees the frontier.
  const auto grid = Grid({
      "##########???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "#.........???",
      "##########???",
  });
  ExploreOptions o = Options();
  o.goal_clearance = 0.3;
  o.goal_search_radius = 0.5;
  FrontierSearch search(o);
  const auto r = search.Find(grid, At(8, 4), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
  const Frontier& f = r.frontiers[0];
  EXPECT_EQ(f.view_radius, 0.0);
  EXPECT_LE(f.goal.x, At(6, 0).x + 1e-9) << "goal (" << f.goal.x << ") within 0.3 m of unknown";
  EXPECT_GE(f.goal.x, At(4, 0).x - 1e-9) << "goal (" << f.goal.x << ") beyond goal_search_radius";
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
  o = ExploreOptions();
  o.view_range = 0.3;  // neither 0 (off) nor at least goal_search_radius
  o.goal_tolerance = -0.1;
  SetExploreOption("creep_depth", "-0.2", &o);
  try {
    FrontierSearch{o};
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("view_range=0.3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("goal_tolerance=-0.1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("creep_depth=-0.2"), std::string::npos) << e.what();
  }
  o = ExploreOptions();
  o.view_range = 0.0;
  EXPECT_NO_THROW(FrontierSearch{o});
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
