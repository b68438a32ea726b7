// Map-wide scan-to-map search: branch-and-bound correlative scan matching after Hess, Kohler,
// Rapp & Andor, "Real-Time Loop Closure in 2D LIDAR SLAM" (ICRA 2016), which makes the exhaustive
// correlative search of Olson, "Real-time correlative scan matching" (ICRA 2009) fast enough for
// whole maps. Shared by amcl's global localization (one map, many searches) and SLAM loop closure
// (one search per submap and scan).
//
// Score of a pose: the mean occupancy probability of the map cells that the scan's endpoints fall
// in (nearest-cell lookup; unknown and off-map cells count as `unknown_probability`), in [0, 1],
// after the probabilities are spread by a small Gaussian (blur_sigma, a max-filter, so a wall
// cell stays at its probability) to make the score tolerant of the lattice's sub-cell offsets.
//
// The search is exhaustive over a lattice: angles θ0 + k·δθ (a window around the initial heading,
// or the full circle split evenly) and translations t0 + (i, j)·r with r the map resolution and
// (i, j) integers (a window around the initial position, or every cell of the map). For each angle
// the scan is rotated once and its endpoints reduced to integer cells; a translation then only adds
// (i, j) to them. The default δθ = acos(1 − r² / (2 d²)), d the farthest endpoint, moves that
// endpoint by about one cell.
//
// CorrelativeSearch precomputes, once per map, a stack of max-grids: level h holds for each cell
// (x, y) the largest probability in the 2^h × 2^h block [x, x + 2^h) × [y, y + 2^h) (built from
// level h−1 by taking the max of four shifted copies). A search node at height h stands for the
// 2^h × 2^h translations (i..i+2^h−1, j..j+2^h−1) at one angle; scoring its endpoints on level h
// gives an upper bound of every translation below it. Depth-first branch and bound: score every
// top-height node of every angle, visit them best first, split a node into its four children,
// visit those best first, and drop a node whose bound cannot beat the best leaf so far (or
// min_score). Two departures from Cartographer, both keeping the search exact: every 8th angle
// is searched first, so that the second pass over the others starts with a good best leaf; and a
// node's scoring stops as soon as the endpoints left cannot lift it to that best (endpoints are
// taken in bit-reversed beam order, and those sharing a cell at an angle are merged). The scores
// are kept as integer sums of per-cent probabilities, so the result equals the brute-force
// maximum over the same lattice exactly (correlative_search_test checks it).
//
// SearchAll keeps the best `max_candidates` leaves that are mutually at least min_separation apart
// and score at least min_relative_score × the best (a greedy non-maximum suppression applied as
// leaves are found; the bound is then the K-th best score): one clear winner versus several
// look-alike places is what global localization needs to know. It is exact for K = 1 and for
// well separated peaks; with K > 1 a candidate that was suppressed by a better neighbour that was
// later evicted can be missing.
//
// correlative_search_bench: a whole-map, full-circle Search for a 360-beam scan (30 m range) on a
// 54 m × 59 m office floor takes ~0.4 s of CPU on the 2-core development machine (depth 7; 6 and
// 8 are slower).
#ifndef MINIBOT3D_SCAN_MATCHING_CORRELATIVE_SEARCH_H_
#define MINIBOT3D_SCAN_MATCHING_CORRELATIVE_SEARCH_H_

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_common/laser_scan.h"
#include "minibot3d_map_io/map_io.h"

namespace minibot3d_scan_matching {

using minibot3d_common::NormalizeAngle;
using minibot3d_common::Pose2;
using GridMap = minibot3d_map_io::OccupancyGrid;
using minibot3d_common::LaserScan;

struct CorrelativeSearchOptions {
  // Use as linear_search_window to search every cell of the map.
  static constexpr double kWholeMap = std::numeric_limits<double>::infinity();

  // Half-width (m) of the square of positions around the initial one; kWholeMap for the whole map.
  // Either way only positions on the map are tried (the robot is assumed to be on it).
  double linear_search_window = 7.0;
  // Half-width (rad) of the headings around the initial one; >= π searches the full circle.
  double angular_search_window = M_PI / 6.0;
  // Angular step (rad); 0 derives it from the farthest endpoint d: acos(1 − r² / (2 d²)).
  double angular_step = 0.0;
  // Number of max-grid levels (the coarsest covers 2^(depth−1) cells a side). Used when building
  // the grids; a search may use fewer levels, not more.
  int branch_and_bound_depth = 7;
  // Results score at least this (mean probability, [0, 1]).
  double min_score = 0.5;
  // SearchAll returns at most this many candidates,
  int max_candidates = 5;
  // and only those scoring at least this fraction of the best one (besides min_score): places
  // far behind the best do not make it ambiguous, and a high bound keeps the search quick.
  double min_relative_score = 0.8;
  // SearchAll: two candidates closer than both of these (m, rad) are the same place and only the
  // better one is kept. Use min_separation_angular >= π to count every heading at one place as
  // the same place.
  double min_separation_linear = 1.0;
  double min_separation_angular = M_PI / 4.0;
  // Probability given to unknown cells (-1) and to everything off the map. Used when building.
  double unknown_probability = 0.1;
  // Standard deviation (m) of the Gaussian each cell's probability is spread with onto its
  // neighbours (p(c) = max over cells c' of p(c') · exp(−|c − c'|² / 2σ²)) before the grids are
  // built, 0 for none. A lattice pose is up to half a cell and half an angular step off the true
  // pose, which takes many endpoints off a one-cell-thick wall: on map_server maps unblurred
  // scores drop to ~0.7 near the truth and look-alike places win. Used when building.
  double blur_sigma = 0.05;
};

// Throws std::invalid_argument naming the first parameter out of range, its value and the range.
void CheckCorrelativeSearchOptions(const CorrelativeSearchOptions& options);

struct CorrelativeMatch {
  Pose2 pose;          // of the scan's frame in the map frame
  double score = 0.0;  // mean occupancy probability at the endpoints, [0, 1]
};

// The returns of `scan` within (range_min, min(range_max, max_range)) as points in the robot's
// base frame (the scan's sensor_in_base applied): the input the searches take.
std::vector<Eigen::Vector2d> ScanToPoints(
    const LaserScan& scan, double max_range = std::numeric_limits<double>::infinity());

class CorrelativeSearch {
 public:
  // Builds the max-grid stack for `map` (values 0..100 are per-cent probabilities, -1 unknown;
  // a trinary map from map_server gives 0 / 100 / -1). Checks `options`. O(depth · cells).
  CorrelativeSearch(const GridMap& map, const CorrelativeSearchOptions& options);

  // The best pose on the search lattice around `initial` with a score >= options.min_score, or
  // nullopt. `points` are endpoints in the scan's frame (ScanToPoints); empty gives nullopt.
  // Throws std::invalid_argument for bad options (and if branch_and_bound_depth exceeds the
  // depth the grids were built with).
  std::optional<CorrelativeMatch> Search(const std::vector<Eigen::Vector2d>& points,
                                         const Pose2& initial,
                                         const CorrelativeSearchOptions& options) const;

  // Up to options.max_candidates mutually separated poses scoring >= options.min_score and
  // >= options.min_relative_score × the best, best first. The first equals Search's result.
  std::vector<CorrelativeMatch> SearchAll(const std::vector<Eigen::Vector2d>& points,
                                          const Pose2& initial,
                                          const CorrelativeSearchOptions& options) const;

  // The same maximum found by trying every lattice pose at full resolution: for tests and to
  // measure what branch and bound saves. Ties go to the first pose in (angle, y, x) order.
  std::optional<CorrelativeMatch> BruteForceSearch(const std::vector<Eigen::Vector2d>& points,
                                                   const Pose2& initial,
                                                   const CorrelativeSearchOptions& options) const;

  // The score of one pose (nearest-cell lookup, as the searches do).
  double Score(const std::vector<Eigen::Vector2d>& points, const Pose2& pose) const;

  int depth() const { return static_cast<int>(levels_.size()); }
  const GridMap& map_info() const { return map_; }

  // The work done by the last search on this thread (for benchmarks).
  struct Stats {
    std::int64_t angles = 0, top_nodes = 0, nodes_scored = 0, leaves = 0;
    std::int64_t lookups = 0;  // endpoint cells read
    std::int64_t top_lookups = 0;  // of which in scoring top-height nodes
  };
  static Stats LastStats();

 private:
  struct Level {
    int pad = 0;      // the level covers x in [-pad, width), y in [-pad, height)
    int stride = 0;   // width + pad
    std::vector<std::uint8_t> cells;
  };
  struct Lattice;
  struct Candidate;
  class Searcher;

  std::uint8_t At(const Level& level, int x, int y) const {
    const int gx = x + level.pad, gy = y + level.pad;
    if (static_cast<unsigned>(gx) >= static_cast<unsigned>(level.stride) ||
        static_cast<unsigned>(gy) >= static_cast<unsigned>(map_.height + level.pad)) {
      return unknown_;
    }
    return level.cells[static_cast<std::size_t>(gy) * level.stride + gx];
  }
  Lattice MakeLattice(const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
                      const CorrelativeSearchOptions& options) const;
  std::vector<CorrelativeMatch> SearchKept(const std::vector<Eigen::Vector2d>& points,
                                           const Pose2& initial,
                                           const CorrelativeSearchOptions& options,
                                           int max_kept) const;

  GridMap map_;  // geometry only (data is cleared; level 0 holds the probabilities)
  std::uint8_t unknown_ = 10;
  int max_value_ = 100;  // the largest cell value, unknown_ included
  std::vector<Level> levels_;
};

}  // namespace minibot3d_scan_matching

#endif  // MINIBOT3D_SCAN_MATCHING_CORRELATIVE_SEARCH_H_
