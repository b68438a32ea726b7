// Distance-to-target grid over the local costmap, after base_local_planner's
// MapGrid (the path and goal distance terms of TrajectoryPlanner).
//
// A breadth-first wave, 4-connected, starts from the target cells (the plan's
// cells, or the single local-goal cell) and gives every cell it reaches its
// number of steps from the nearest target.  The wave does not enter lethal,
// inscribed or unknown cells, except cells under the robot's current
// footprint (so a robot standing in the inflated band still has distances);
// such obstacle cells get obstacle_distance(), cells the wave never reaches
// unreachable_distance().  Both are >= size (the "impossible" bound of
// TrajectoryPlanner): a trajectory through such a cell has no way to the
// target.  One pass per cycle, buffers reused across cycles.
#ifndef MINIBOT3D_NAVIGATION_DWA_MAP_GRID_H_
#define MINIBOT3D_NAVIGATION_DWA_MAP_GRID_H_

#include <cmath>
#include <cstdint>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

class MapGrid {
 public:
  // Seeds the wave with the cells of `plan` (densified to one point per
  // cell), from the first pose on the costmap until the plan leaves it again;
  // unknown cells are skipped.  `robot_cells` are cell indices the wave may
  // cross even if they are obstacles.  Returns the number of seed cells (0:
  // no plan pose on the known part of the costmap; all cells unreachable).
  int SetTargetCells(const Costmap2D& costmap, const Path& plan,
                     const std::vector<int>& robot_cells);

  // Seeds the wave with one cell.  Returns false (all cells unreachable) if
  // the cell is off the costmap.
  bool SetTargetCell(const Costmap2D& costmap, int mx, int my,
                     const std::vector<int>& robot_cells);

  // The local goal of `plan` on `costmap` (base_local_planner's
  // MapGrid::setLocalGoal): the last plan point (densified) that is on the
  // known part of the costmap before the plan leaves it, except that once the
  // plan is more than 1 m from its start, the first lethal/inscribed point
  // after a free one ends the search (the goal stays on the free side of an
  // obstacle blocking the plan).  Returns false if no plan point is on the
  // known costmap.  *in_obstacle tells whether the chosen cell is
  // lethal/inscribed.  If `before_block_mx/my` are given, they receive the
  // last free point before the plan first enters a lethal/inscribed cell
  // (-1 if it never does), a fallback when the goal behind the obstacle turns
  // out to be unreachable.
  static bool FindLocalGoal(const Costmap2D& costmap, const Path& plan,
                            int* mx, int* my, bool* in_obstacle,
                            int* before_block_mx = nullptr,
                            int* before_block_my = nullptr);

  int size_x() const { return size_x_; }
  int size_y() const { return size_y_; }
  float distance(int mx, int my) const {
    return dist_[static_cast<size_t>(my) * size_x_ + mx];
  }
  float distance(int index) const { return dist_[index]; }
  // A distance >= this means "no way to the target" (TrajectoryPlanner's
  // impossible_cost = number of cells).
  float impossible_distance() const { return static_cast<float>(cells_); }
  float obstacle_distance() const { return static_cast<float>(cells_); }
  float unreachable_distance() const { return static_cast<float>(cells_ + 1); }
  bool Reachable(int mx, int my) const {
    return distance(mx, my) < impossible_distance();
  }

 private:
  void Resize(const Costmap2D& costmap);
  void Seed(int index);
  void Propagate(const Costmap2D& costmap);

  int size_x_ = 0;
  int size_y_ = 0;
  int cells_ = 0;
  std::vector<float> dist_;
  std::vector<int> queue_;  // BFS queue; each cell enters at most once
  size_t queue_tail_ = 0;
  std::vector<uint8_t> robot_mask_;
};

// Calls `visit(x, y)` for the plan densified so that consecutive points are
// at most `step` apart (base_local_planner's adjustPlanResolution).
template <typename Visit>
void ForEachDensifiedPoint(const Path& plan, double step, Visit visit) {
  if (plan.empty()) return;
  if (!visit(plan[0].x, plan[0].y)) return;
  for (size_t i = 1; i < plan.size(); ++i) {
    const double x0 = plan[i - 1].x, y0 = plan[i - 1].y;
    const double dx = plan[i].x - x0, dy = plan[i].y - y0;
    const double len = std::sqrt(dx * dx + dy * dy);
    const int n = len > step ? static_cast<int>(std::ceil(len / step)) : 1;
    for (int j = 1; j < n; ++j) {
      if (!visit(x0 + dx * j / n, y0 + dy * j / n)) return;
    }
    if (!visit(plan[i].x, plan[i].y)) return;
  }
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_MAP_GRID_H_
