// Frontier search on small inline maps: frontier detection and clustering, the
// goal on the robot's side, unreachable frontiers dropped, blacklist, and
// "nothing left" once a room is closed.
#include "minibot3d_navigation/explore/frontier_search.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr double kRes = 0.1;

// '.' free, '#' occupied, '?' unknown; row 0 of the text is the top (max y).
amcl::OccupancyGrid Grid(const std::vector<std::string>& rows) {
  amcl::OccupancyGrid g;
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

Pose2D At(int x, int y) { return {(x + 0.5) * kRes, (y + 0.5) * kRes, 0.0}; }

ExploreOptions Options() {
  ExploreOptions o;
  o.clearance = 0.1;
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
  FrontierSearch search(o);
  const auto r = search.Find(grid, At(1, 1), {});
  ASSERT_EQ(r.frontiers.size(), 1u);
}

TEST(FrontierSearch, BadInputIsRejectedSayingWhy) {
  FrontierSearch search(Options());
  amcl::OccupancyGrid g = Grid({"...", "..."});
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
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
