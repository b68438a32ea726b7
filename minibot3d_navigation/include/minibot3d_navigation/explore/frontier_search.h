// Frontier-based exploration (Yamauchi, "A frontier-based approach for
// autonomous exploration", CIRA 1997), the search half, ROS-free.
//
// A frontier cell is a known-free cell with an unknown 4-neighbour; 8-connected
// frontier cells form a frontier, kept if it is at least min_frontier_size
// metres long.  The robot should drive to where it can see past the frontier,
// so each frontier gets a goal (its viewpoint): the cell, among traversable
// cells within goal_search_radius of a frontier cell and with a line of sight
// through known-free cells to that cell's unknown side, with the shortest path
// from the robot (a cell beside a frontier but behind a shelf's end sees
// nothing of it).  A goal must be goal_clearance from occupied cells and from
// unknown cells that border known-free ones (an unseen face of a shelf): a robot
// stopping anywhere within its goal tolerance can still turn there, and it is
// not sent into a pocket it cannot turn round in (paths still pass through
// anything `clearance` wide, such as a 0.40 m door).  Paths are a
// Dijkstra flood (8-connected) over traversable cells: known free and farther
// than `clearance` from any occupied cell; a robot that starts closer than that
// to a wall may leave through free cells first (as the A* planner does). A robot
// whose own cell is not known free (lasers at its ends do not see under it)
// starts from the nearest known-free cell within start_search_radius, reached
// through cells that are not occupied (explore_lite's nearest free cell).
// A frontier with no such goal (the far end of a gap behind a shelf, too narrow
// to stand in, seen only at a slant so far) is looked into from off: among the
// roomy reachable cells within view_range, those from which the most of its
// cells' unknown sides are in line of sight (counted by walking rays out from
// the unknown side through known-free cells: an art-gallery style visibility
// count, as in next-best-view planners, González-Baños & Latombe, IJRR 2002),
// from anywhere within goal_tolerance of them (where move_base may stop), the
// one nearest the robot by path among those seeing at least 3/4 of the best.
// When no roomy cell sees any of it (a gap whose mouth is flanked by furniture),
// the same choice is made among cells only `clearance` from walls and at most
// creep_depth by path from a roomy cell: the robot has room to turn there but no
// margin, the local planner creeps, and it edges into the gap's mouth rather than
// down a gap it could only back out of.
// Frontiers whose goal cannot be reached — behind walls, outside the building —
// are dropped, so "no frontier left" means the reachable space is mapped.
//
// ExplorationMemory is explore's blacklist.  When the robot reaches a
// viewpoint, a frontier cell within look_radius whose unknown side it has in
// its line of sight stays frontier only if the sensor cannot clear it (glass,
// below the lidar plane, a grazing ray): such cells are remembered as looked at
// and no longer count as frontier; a frontier's other cells still do, seen from
// a viewpoint at least blacklist_radius from every one reached (so a pocket the
// lidar sees only a sliver of is not crept into cell by cell).  A goal move_base
// could not reach is shown unreachable and excluded, but only until the map
// around it changes
// (retry_map_change m^2 of cells within retry_window change state: a door
// seen open, a corridor mapped), at most max_goal_attempts times in all.  So
// exploration ends when nothing reachable is left, not when the robot got
// stuck once.
#ifndef MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_
#define MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

struct ExploreOptions {
  double min_frontier_size = 0.5;  // m; shorter frontiers are noise
  double clearance = 0.2;          // m from occupied cells for a goal/path cell
  double goal_clearance = 0.35;    // m from occupied cells for a goal: the circumscribed radius
                                   // (0.18 m) + xy_goal_tolerance (0.15 m) + a margin
  int free_threshold = 25;         // OccupancyGrid values 0..this are free
  double blacklist_radius = 0.5;   // m around a reached viewpoint or an unreachable goal
  double goal_search_radius = 0.6; // m from a frontier cell to look for its goal
  double look_radius = 1.0;        // m from a reached goal within which it looked at frontier
  double retry_window = 1.0;       // m, half-size of the square watched round an unreachable goal
  double retry_map_change = 0.25;  // m^2 of it that must change before the goal is retried
  int max_goal_attempts = 3;       // goals sent near one place before it is given up for good
  double start_search_radius = 1.0;  // m: the nearest free cell within this starts the search
                                     // when the robot's own cell is not known free
  double view_range = 2.5;  // m: a frontier without a near goal is looked into from this far
                            // at most; 0: such a frontier is dropped
  double goal_tolerance = 0.15;  // m: move_base's xy_goal_tolerance; a goal looking from off
                                 // sees its frontier from anywhere within it
  double creep_depth = 0.0;  // m: a frontier no roomy cell sees is looked into from a cell only
                            // clearance from walls this far from roomy space at most; 0: dropped
};

// Throws std::invalid_argument listing every offending value.
void ValidateExploreOptions(const ExploreOptions& options);
// The options by name, each with its documentation; thin wrappers below.
const minibot3d_common::options::OptionTable<ExploreOptions>& ExploreOptionTable();
void SetExploreOption(const std::string& name, const std::string& text, ExploreOptions* options);
bool IsExploreOptionName(const std::string& name);
std::vector<std::string> ExploreOptionNames();

struct Frontier {
  Point2 centroid;        // map frame
  Point2 goal;            // where to drive to see it
  double size = 0.0;       // m (cells x resolution)
  double distance = 0.0;   // path length from the robot to the goal, m
  int cells = 0;
  // > 0 when the goal looks at the frontier from off (no room nearer): the distance (m) to the
  // farthest of its cells in sight from the goal; what stays unknown within it there is judged.
  double view_radius = 0.0;
  // Looking from off: the frontier's cells (centres) in sight from the goal; once it is reached
  // they no longer count (ExplorationMemory::LookedAt), seen or not.
  std::vector<Point2> in_view;
  // Looking from off from a cell closer to walls than goal_clearance (creep_depth).
  bool creeping = false;
};

struct FrontierSearchResult {
  std::vector<Frontier> frontiers;  // reachable, not blacklisted, nearest first
  int unreachable = 0;              // frontiers without a reachable viewpoint
  int blacklisted = 0;              // frontiers whose every reachable viewpoint is excluded
  double known_free_area = 0.0;     // m^2
};

class FrontierSearch {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit FrontierSearch(const ExploreOptions& options);

  // `excluded`: viewpoints not to use (within blacklist_radius; for a far
  // viewpoint, within goal_tolerance); `looked_at`: cells not to count as
  // frontier; `unreachable`: goals move_base could not reach, within
  // blacklist_radius of which no far viewpoint is chosen either (all from
  // ExplorationMemory).  Throws std::invalid_argument for a malformed grid
  // (size mismatch, non-positive resolution) or a robot pose off the grid.
  FrontierSearchResult Find(const OccupancyGrid& grid, const Pose2& robot,
                            const std::vector<Point2>& excluded,
                            const std::vector<Point2>& looked_at = {},
                            const std::vector<Point2>& unreachable = {}) const;

  // The frontier cells (centres) within max(look_radius, radius) of `viewpoint`
  // with an unknown 4-neighbour in its line of sight.  Throws like Find.
  std::vector<Point2> InSight(const OccupancyGrid& grid, const Point2& viewpoint,
                              double radius = 0.0) const;

 private:
  ExploreOptions options_;
};

class ExplorationMemory {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit ExplorationMemory(const ExploreOptions& options);

  // The robot reached `viewpoint`: it is not used again.
  void Reached(const Point2& viewpoint);
  // `in_sight` (FrontierSearch::InSight of a reached viewpoint) stayed
  // frontier: those cells no longer count.
  void LookedAt(const std::vector<Point2>& in_sight);
  // move_base could not reach `goal` on `map`: excluded until the map round it
  // changes.  Returns the number of attempts made near it so far.
  int Failed(const Point2& goal, const OccupancyGrid& map);
  // Releases the unreachable goals whose surroundings changed on `map` and
  // that have attempts left; returns them.
  std::vector<Point2> Refresh(const OccupancyGrid& map);
  std::vector<Point2> Excluded() const;
  // The unreachable goals among Excluded().
  std::vector<Point2> Unreachable() const;
  const std::vector<Point2>& looked_at() const { return looked_at_; }

 private:
  struct Failure {
    Point2 goal;
    std::vector<int8_t> window;  // cell kinds round the goal when it last failed
    double step = 0.0;           // m between the window's samples (that map's resolution)
    int attempts = 0;
    bool excluded = true;
  };
  std::vector<int8_t> Window(const Point2& centre, double step,
                             const OccupancyGrid& map) const;

  ExploreOptions options_;
  std::vector<Point2> visited_;
  std::vector<Point2> looked_at_;
  std::vector<Failure> failures_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_EXPLORE_FRONTIER_SEARCH_H_
