// Scan matching and the improved proposal of Grisetti, Stachniss & Burgard, "Improved techniques
// for grid mapping with Rao-Blackwellized particle filters" (IEEE T-RO 2007), as gmapping does it.
//
// Beam model ("closest mean hit" of gmapping): a beam endpoint is compared with the occupied cells
// (occupancy > 0.1) in a (2·kernelSize+1)² window around it that were seen from the beam's side —
// the point √2·δ back along the beam from the cell's mean endpoint lies in a free or unknown cell
// (gmapping tests the cell at the endpoint cell's back-step offset instead, which makes the score
// jump by whole beams for millimetre moves; see ForEachBeam) — and the distance d to the nearest
// such mean endpoint is used:
//   * matching score (hill climbing):  Σ_beams exp(-d² / sigma)  (0 for a beam without match) —
//     gmapping's wide kernel: it still rewards endpoints a few cells off, so the climber sees a
//     slope from further away and takes fewer steps than with the narrow exp(-d² / 2σ²),
//   * log-likelihood (particle weight): Σ_beams -d² / lsigma, or -0.5 / lsigma without match.
// Only every (lskip+1)-th beam with a reading within maxUrange is used.
//
// Optimize is gmapping's hill climber: from the initial pose it tries ±lstep in x and y and ±astep
// in θ, moves to the best improving neighbour, and halves the steps when none improves, stopping
// after `iterations` halvings.
//
// Refine (subcellMatch = 1) continues from the climber's pose with a continuous optimisation, in
// the spirit of Hector SLAM's Gauss-Newton on the map gradient (Kohlbrecher et al., "A flexible and
// scalable SLAM system with full 3D motion estimation", SSRR 2011) but on a distance field instead
// of a bilinear occupancy field. Each beam is associated with the nearest admissible mean endpoint
// found as above; the wall through it runs to the mean of its nearest occupied neighbour cell, and
// the residual is the endpoint's distance to that line (point-to-line; to the mean itself when no
// neighbour is occupied). The mean endpoints are kept to 1/65536 cell, so this field is continuous
// and sub-cell; an interpolated occupancy grid would pull endpoints towards cell centres, and the
// cells just behind a wall (hit by range noise, never passed through) read as fully occupied there.
// Gauss-Newton with re-association and a one-cell Gaussian weight per beam (iteratively reweighted
// least squares, lightly damped for corridors) minimises the weighted squared distances over
// (x, y, θ). Why: the climber ends on a grid of poses lstep/2^iterations apart on a score that is
// flat near its top and jumps as endpoints change cells, so it can stop most of a cell from the
// best pose; the refinement is continuous (scan_matcher_test bounds both errors). Point-to-line
// rather than point-to-point: a beam on a straight wall only says how far the wall is, and puts
// no pull along it. A result more than a cell or astep from the climber's pose is discarded.
//
// SampleAround is the improved proposal of the paper (Sec. IV): around the mode x̂ found by the
// matcher it evaluates the likelihood on a grid of poses (±llsamplerange step llsamplestep in x and
// y, ±lasamplerange step lasamplestep in θ), fits a Gaussian N(μ, Σ) to it — the proposal the new
// pose is drawn from — and returns the log of the mean likelihood over the grid, the approximation
// of η = ∫ p(z | m, x) p(x | x', u) dx that becomes the particle's weight factor.
//
// Both evaluate dozens of nearby poses against one map, so within one call they remember, per beam
// and orientation, which cells are admissible matches (WindowCache in scan_matcher.cpp); the
// results are bit-identical to evaluating every pose on its own, as Score and LogLikelihood do.
#ifndef MINIBOT3D_SLAM_SRC_SCAN_MATCHER_H_
#define MINIBOT3D_SLAM_SRC_SCAN_MATCHER_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "grid.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

// A scan reduced to what matching and mapping need, shared by all particles.
struct PreparedScan {
  Pose2 sensor_in_base;
  // Beams used for matching (reading within maxUrange, every (lskip+1)-th): range and direction in
  // the sensor frame.
  std::vector<double> match_range, match_cos, match_sin;
  // Beams used for the map: range cut to maxUrange, direction, and whether the end is a hit.
  std::vector<double> map_range, map_cos, map_sin;
  std::vector<std::uint8_t> map_hit;
  std::vector<std::uint32_t> map_beam;  // index of each map beam in the LaserScan
};

struct ProposalFit {
  Pose2 mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, θ
  double log_weight = 0.0;  // log of the mean likelihood over the sampled poses
};

class ScanMatcher {
 public:
  explicit ScanMatcher(const GmappingOptions& options);

  // Classifies the beams of `scan` (no-returns dropped; > maxUrange kept for free space only).
  PreparedScan Prepare(const LaserScan& scan) const;

  double Score(const Grid& grid, const PreparedScan& scan, const Pose2& pose) const;
  // Returns the log-likelihood; *matched (optional) gets the number of beams with a match.
  double LogLikelihood(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                       int* matched = nullptr) const;
  // Hill climbing from `initial`; writes the best pose and returns its score.
  double Optimize(const Grid& grid, const PreparedScan& scan, const Pose2& initial,
                  Pose2* best) const;
  // Sub-cell refinement of a matched pose (subcellMatch): Gauss-Newton on the distance field of
  // the map's mean endpoints (see the header comment). Returns `initial` when the problem is
  // degenerate or the result strays more than a cell (or astep) from it.
  Pose2 Refine(const Grid& grid, const PreparedScan& scan, const Pose2& initial) const;
  ProposalFit SampleAround(const Grid& grid, const PreparedScan& scan, const Pose2& mode) const;

  // Integrates the scan at `pose` into the grid (ray-traced free space, hits at endpoints).
  void Register(const PreparedScan& scan, const Pose2& pose, Grid* grid) const;

 private:
  // Which cells of each beam's kernel window passed the admissibility test, remembered across the
  // poses of one Optimize or SampleAround call (see scan_matcher.cpp).
  class WindowCache;

  // Where a beam's endpoint fell and the cell of its closest admissible mean hit.
  struct BeamMatch {
    double px = 0.0, py = 0.0;
    int cx = 0, cy = 0;
  };
  // Squared distance of each match beam's endpoint to its closest admissible mean hit, or -1 when
  // there is none; calls f(d2, match) per beam. `cache` (may be null) must belong to this grid and scan.
  template <class F>
  void ForEachBeam(const Grid& grid, const PreparedScan& scan, const Pose2& pose, WindowCache* cache,
                   F&& f) const;
  double ScoreCached(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                     WindowCache* cache) const;
  double LogLikelihoodCached(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                             WindowCache* cache, int* matched) const;

  static constexpr int kRefineIterations = 10;
  static constexpr int kRefineMinBeams = 10;

  GmappingOptions options_;
  double free_back_;  // how far back along the beam the free cell is looked for (√2·δ)
  // The kernel window as a WindowCache patch bitmask, at the patch's lower-left corner.
  std::uint64_t window_mask_ = 0;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_SCAN_MATCHER_H_
