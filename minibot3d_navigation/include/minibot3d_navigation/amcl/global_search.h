// Map-wide scan search that seeds global localization: the branch-and-bound
// correlative scan matcher of minibot3d_scan_matching (Olson, "Real-time correlative
// scan matching", ICRA 2009; Hess et al., "Real-Time Loop Closure in 2D LIDAR
// SLAM", ICRA 2016 -- see minibot3d_scan_matching/correlative_search.h), shared with
// SLAM loop closure, run over every cell and every heading of the AMCL map.
//
// 5,000 uniform particles cannot cover a building's free space times 360
// degrees finely enough for the likelihood to pick the right place; the
// search can.  It returns up to global_search_max_candidates mutually
// separated poses (>= 1 m or >= 45 deg apart) scoring at least
// global_search_min_score and global_search_min_relative_score of the best;
// the filter spreads its particles round them (weighted by score) and decides
// among them as the robot moves (amcl_filter.h).
//
// The search matches at most global_search_max_beams returns (evenly spaced
// over the scan): its time is nearly proportional to them, and the filter,
// not the search, has the last word.
//
// Budget: a whole-map search costs a fixed part (every heading's top nodes)
// plus a part growing with the map's cell count; the constructor predicts it
// as kFixedSeconds + cells / kCellsPerSecond, constants fitted to
// correlative_search_bench (SearchAll) and amcl_bench (BM_GlobalSearchOffice)
// on a 2-core machine, and, when the prediction exceeds
// global_search_budget, builds nothing and says so in fallback_reason(): the
// filter then keeps the uniform spread.  Every search is timed
// (SearchReport) so a wrong prediction shows in the log.
#ifndef MINIBOT3D_NAVIGATION_AMCL_GLOBAL_SEARCH_H_
#define MINIBOT3D_NAVIGATION_AMCL_GLOBAL_SEARCH_H_

#include <memory>
#include <string>
#include <vector>

#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_scan_matching {
class CorrelativeSearch;
}

namespace minibot3d_navigation {
namespace amcl {

struct SearchCandidate {
  Pose2 pose;          // robot base in the map frame
  double score = 0.0;   // mean occupancy probability at the end points
};

class GlobalSearch {
 public:
  // The cost model above (CPU seconds; see the header comment).
  static constexpr double kFixedSeconds = 0.1;
  static constexpr double kCellsPerSecond = 2.2e6;

  // Builds the multi-resolution grids when options.global_search is on and
  // the predicted search time fits options.global_search_budget; otherwise
  // available() is false and fallback_reason() says why (naming the map size
  // and the parameter).  Options must be valid (ValidateAmclOptions).
  GlobalSearch(const OccupancyGrid& grid, const AmclOptions& options);
  ~GlobalSearch();

  bool available() const { return search_ != nullptr; }
  const std::string& fallback_reason() const { return fallback_reason_; }
  double predicted_seconds() const { return predicted_seconds_; }

  // The best candidate poses of the robot base for `scan`, best first; empty
  // if no pose scores global_search_min_score (or no beam returned).  Sets
  // *seconds / *cpu_seconds (if given) to the wall time and the calling
  // thread's CPU time the search took (a loaded machine stretches the first).
  // max_candidates > 0 overrides global_search_max_candidates.
  std::vector<SearchCandidate> Search(const LaserScan& scan,
                                      double* seconds = nullptr,
                                      double* cpu_seconds = nullptr,
                                      int max_candidates = 0) const;

 private:
  AmclOptions options_;
  double map_range_ = 0.0;  // laser_max_range or the scan's
  std::unique_ptr<minibot3d_scan_matching::CorrelativeSearch> search_;
  std::string fallback_reason_;
  double predicted_seconds_ = 0.0;
};

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_GLOBAL_SEARCH_H_
