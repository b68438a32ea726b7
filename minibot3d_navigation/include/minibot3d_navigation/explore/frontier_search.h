// Frontier-based exploration (Yamauchi, "A frontier-based approach for
// autonomous exploration", CIRA 1997), the search half, ROS-free.
//
// A frontier cell is a known-free cell with an unknown 4-neighbour; 8-connected
// frontier cells form a frontier, kept if it is at least min_frontier_size
// metres long.  The robot should drive to where it can see past the frontier,
// so each frontier gets a goal: the cell, among traversable cells within a few
// cells of the frontier, with the shortest path from the robot.  Paths are a
// Dijkstra flood (8-connected) over traversable cells: known free and farther
// than `clearance` from any occupied cell; a robot that starts closer than that
// to a wall may leave through free cells first (as the A* planner does).
// Frontiers whose goal cannot be reached — behind walls, outside the building —
// are dropped, so "no frontier left" means the reachable space is mapped.
#ifndef MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_
#define MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_

#include <string>
#include <vector>

#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

struct ExploreOptions {
  double min_frontier_size = 0.5;  // m; shorter frontiers are noise
  double clearance = 0.2;          // m from occupied cells for a goal/path cell
  int free_threshold = 25;         // OccupancyGrid values 0..this are free
  double blacklist_radius = 0.5;   // m around a failed goal
  double goal_search_radius = 0.4; // m from a frontier cell to look for its goal
};

// Throws std::invalid_argument listing every offending value.
void ValidateExploreOptions(const ExploreOptions& options);
void SetExploreOption(const std::string& name, const std::string& text, ExploreOptions* options);
bool IsExploreOptionName(const std::string& name);
std::vector<std::string> ExploreOptionNames();

struct Frontier {
  Point2D centroid;        // map frame
  Point2D goal;            // where to drive to see it
  double size = 0.0;       // m (cells x resolution)
  double distance = 0.0;   // path length from the robot to the goal, m
  int cells = 0;
};

struct FrontierSearchResult {
  std::vector<Frontier> frontiers;  // reachable, not blacklisted, nearest first
  int unreachable = 0;              // frontiers without a reachable goal
  int blacklisted = 0;
  double known_free_area = 0.0;     // m^2
};

class FrontierSearch {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit FrontierSearch(const ExploreOptions& options);

  // Throws std::invalid_argument for a malformed grid (size mismatch,
  // non-positive resolution) or a robot pose off the grid.
  FrontierSearchResult Find(const amcl::OccupancyGrid& grid, const Pose2D& robot,
                            const std::vector<Point2D>& blacklist) const;

 private:
  ExploreOptions options_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_
