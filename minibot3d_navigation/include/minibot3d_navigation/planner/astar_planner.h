// A* global planner on the costmap grid (Hart, Nilsson & Raphael, "A Formal
// Basis for the Heuristic Determination of Minimum Cost Paths", 1968), with
// the cost model of ROS navfn / global_planner.
//
// Search: 8-connected cells; moving onto a cell of cost c costs
//   step_length_in_cells * (neutral_cost + cost_factor * c)
// (1 or sqrt(2) cells), so the planner trades path length against clearance
// like navfn.  Cells of cost >= lethal_cost are impassable; unknown cells
// (255) are impassable unless allow_unknown, in which case they cost like a
// cell of cost kUnknownCellCost (127, mid-inflation: with the defaults an
// unknown cell costs 8.6x a free one, so the path cuts through unseen space
// only when that saves a lot; navfn uses ~5x).  A diagonal move is not
// allowed past an impassable orthogonal neighbour (no corner cutting).  The
// heuristic is the octile distance times neutral_cost, a lower bound on the
// cost to go since every cell costs at least neutral_cost per cell length:
// admissible and consistent, so the path is cost-optimal.  Costs are 64-bit
// integers (scaled by 1000, diagonal steps rounded up) and the heuristic is
// the octile distance in those same integer free-cell step costs, so it is
// exact in free space; ties in f are broken last-in-first-out (RadixHeap),
// so the search walks straight down one optimal path instead of flooding the
// parallelogram of equal-cost octile paths (on an empty map it expands about
// one cell per cell of path, not the parallelogram's area).
//
// Speed: all per-cell state lives in one flat member array reused between
// calls; a generation counter per cell (open/closed marks of this search)
// replaces clearing it; the open list is a radix heap (see RadixHeap) with
// lazy deletion: a cell whose g improves is pushed again and the stale entry
// is skipped when popped (the cell is closed by then).
//
// Goal tolerance: when the goal cell is not traversable, the nearest
// traversable cell within default_tolerance is the target; if it cannot be
// reached, the failed search has closed exactly the cells reachable from the
// start, so the nearest reachable candidate is used without searching again.
//
// Not thread-safe (the buffers are members): one planner per thread.
//
// Output: the grid path as cell centres, first replaced by the start's
// position and last by the goal's (or by the substitute cell's centre); with
// smooth_path it is shortcut and resampled (path_smoothing.h), else returned
// as is.  Yaws per orientation_mode; the last pose carries the goal's yaw.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_ASTAR_PLANNER_H_
#define MINIBOT3D_NAVIGATION_PLANNER_ASTAR_PLANNER_H_

#include <cstdint>
#include <string>
#include <vector>

#include "minibot3d_navigation/planner/global_planner.h"
#include "minibot3d_navigation/planner/planner_options.h"

namespace minibot3d_navigation {
namespace nav {

class AStarPlanner : public GlobalPlanner {
 public:
  static constexpr int kUnknownCellCost = 127;

  // Validates `options` (std::invalid_argument listing every bad value).
  explicit AStarPlanner(const GlobalPlannerOptions& options);

  std::string name() const override { return "astar"; }

  // Throws PlanningError (see ResolveEndpoints in planner_options.h, and
  // kNoPath naming start and goal when no path exists).
  Path MakePlan(const Costmap2D& costmap, const Pose2& start,
                const Pose2& goal) override;

  // The grid path of the last successful plan (world points, before
  // smoothing; first/last are the exact start and goal positions, or the
  // substitute goal cell's centre).
  const std::vector<Point2>& last_raw_path() const { return raw_path_; }
  // Cells expanded by the last search (for benchmarks).
  int last_expansions() const { return expansions_; }

  const GlobalPlannerOptions& options() const { return options_; }

 private:
  // Monotone integer priority queue (radix heap: Ahuja, Mehlhorn, Orlin &
  // Tarjan, "Faster algorithms for the shortest path problem", JACM 1990).
  // A* with a consistent heuristic pops non-decreasing f, which is all a
  // radix heap needs: pushes are O(1), a pop moves each entry to a lower
  // bucket at most 64 times in all, and buckets are scanned sequentially
  // (cache friendly, unlike a binary heap of a million entries).  Entries of
  // equal f come out last-in-first-out, so among ties the search continues
  // from the cell it just reached (depth first along the optimal path).
  class RadixHeap {
   public:
    struct Entry {
      uint64_t key;
      int32_t index;
    };
    void Clear();
    bool Empty() const { return size_ == 0; }
    void Push(uint64_t key, int32_t index);
    Entry Pop();  // requires !Empty()

   private:
    static int Bucket(uint64_t a, uint64_t b);
    std::vector<Entry> buckets_[65];
    uint64_t nonempty_ = 0;  // bit b-1 set: bucket b (1..64) non-empty
    uint64_t last_ = 0;      // last popped key
    size_t size_ = 0;
  };

  // Per-cell search state, one struct so a neighbour costs one cache line.
  // mark == open_mark_: g and parent are from this search; == open_mark_ + 1:
  // closed.  Anything else: unvisited (left over from an earlier search).
  struct CellState {
    int64_t g;
    uint32_t mark;
    uint8_t parent;  // direction index into the 8 neighbours
  };

  // Runs A* from the start cell to goal cell `goal_index`; true if found.
  bool Search(const Costmap2D& costmap, int start_index, int goal_index);
  void PrepareBuffers(int num_cells);
  // Cells from the start to `index` following the parent links.
  void TraceBack(const Costmap2D& costmap, int start_index, int index,
                 std::vector<int>* cells) const;

  const GlobalPlannerOptions options_;
  // Integer step costs per cell cost value; -1 = impassable.
  int64_t straight_cost_[256];
  int64_t diagonal_cost_[256];
  // Steps out of the inflated band when the search starts inside it.
  int64_t escape_straight_cost_[256];
  int64_t escape_diagonal_cost_[256];
  int64_t escape_or_normal_straight_[256];
  int64_t escape_or_normal_diagonal_[256];
  int64_t h_straight_ = 0;  // heuristic: h_straight * max(|dx|,|dy|) +
  int64_t h_diagonal_ = 0;  //            h_diagonal * min(|dx|,|dy|)

  std::vector<CellState> state_;
  uint32_t open_mark_ = 0;
  RadixHeap open_;
  int expansions_ = 0;

  std::vector<int> cells_;
  std::vector<Point2> raw_path_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_ASTAR_PLANNER_H_
