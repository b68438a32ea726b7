// Loop closure for the RBPF: a pose graph of the best particle's trajectory, revisits found by
// scan-to-submap matching, Ceres optimisation, and the map rebuilt from the corrected trajectory.
// The scheme is that of graph SLAM with a sparse back-end — Lu & Milios (1997); Hess, Kohler, Rapp
// & Andor, "Real-Time Loop Closure in 2D LIDAR SLAM" (ICRA 2016) for the submaps and the
// branch-and-bound search — with gmapping's RBPF (Grisetti et al., T-RO 2007) as the front-end.
//
// Nodes are the processed scans (each keeps its scan in compact form: float ranges, and beam
// indices into a table of float directions shared by the scans of one laser geometry). Consecutive nodes are joined by edges equal to the best particle's relative poses
// (scan-matched odometry). Every `loopSubmapScans` consecutive nodes form a submap; a submap is not
// stored as a grid (a building-sized log has hundreds) but rendered on demand from its scans at
// the current poses, with a few recent ones cached. A cached rendering is used only while the
// trajectory still holds the poses it was rendered at: the best particle changes from scan to
// scan, and with it the history (by up to decimetres on the real logs), and a match made on a
// rendering of another history would be a constraint in the wrong frame.
//
// Detection, after each processed scan: the submaps that ended at least `loopMinTravel` metres of
// path ago (older parts of the map — recent ones are the RBPF's own business) and have a node
// within the search window of the current estimate are candidates — the window's half-width is
// `loopSearchWindow`, or `loopDriftRate` × the path driven since the submap ended when that is
// more (the front-end's drift grows with the path: round a building-sized loop of long corridors
// the estimate comes back metres off), at most `loopMaxSearchWindow`; once a constraint has tied
// the trajectory to the map, the path is counted from there (a large window left open after a
// closure only lets a corridor's look-alike places in); the nearest is searched, every
// kSearchEvery-th scan (the searches are most of the loop closer's cost). The current scan is
// searched in each with CorrelativeSearch (the same branch-and-bound search amcl's global
// localization uses) in that window and ±loopSearchAngle around the current estimate; a match must
// reach `loopMinScore` (mean blurred occupancy at the endpoints) and be unambiguous (no other place
// kAmbiguitySeparation away scoring kAmbiguityRatio of it). It is then refined on the submap's grid
// with the RBPF's own scan matcher (hill climber + sub-cell refinement), and checked against the
// submap's free space: at most `loopMaxConflict` of the scan's endpoints may fall in cells the
// submap saw through, with no wall within kConflictCells. The score counts only the endpoints
// that land on walls, so a room or corridor bay that merely looks like the robot's (an office's
// row of rooms, one door apart) scores as well as the right place — but there part of the scan
// ends in the look-alike's open floor. (The negative information of scan-to-map consistency, as
// in map_consistency.h.) A match that passes becomes a constraint between the submap's first node
// and the current node.
//
// Corridors: a scan between two doors of a long corridor matches equally well anywhere along it.
// Such a match is ambiguous, but when every look-alike place lies on one line through the best at
// the same heading it still says where across the corridor the robot is and which way it faces —
// exactly what keeps a corridor driven twice from coming out as two corridors side by side or
// bent. It becomes a corridor constraint: the pose graph edge is weak (kAlongSigma) along the
// line and as tight as any other across it and in heading (the information-matrix view of a
// degenerate match, e.g. Censi, "An accurate closed-form estimate of ICP's covariance", ICRA
// 2007). A large one waits for a full match to vouch for it (below), compared across the corridor
// only; corridor constraints do not reset the search window's drift count, which is about the
// drift along the corridor too. Only with `loopCorridors` 1 (off by default: gmapping_options.h).
//
// Back-end: when new constraints exist and either kOptimizeEvery nodes passed since the last
// optimisation or two new constraints agree that the current estimate is off by more than
// kBigCorrection (a large loop just closed), the graph is optimised. A constraint claiming such a
// large correction waits (kTentativeNodes) for a constraint of another scan against another
// submap to agree before it enters the graph at all — or, on the way back from a long stretch
// nothing anchored (the search window grown past loopSearchWindow), of a scan at least
// kSameSubmapApart further along against the same submap: the first corridor of a return to the
// old track may be the only submap the robot passes before it leaves the track again, and scans
// that far apart see different stretches of it. Right after an anchor one submap stays one
// opinion: with a long-range laser, two wrong matches against one submap can agree.
// Why wait at all: the odometry chain bends to fit any single loop edge, so the graph cannot
// reject a lone false one, and one look-alike place must not move a trajectory by metres
// (pose_graph.h: loop edges under a Huber loss, outliers dropped and the graph re-solved). A
// correction just under kBigCorrection that repeats such a waiting claim from the same submap
// waits with it: otherwise the claim slips in by the next scan that matches a little nearer. The
// corrected trajectory comes back to the RBPF, which applies it only when it moves the newest node
// by kApplyShift / kApplyTurn or more: below that the filter is at least as precise as the
// constraints, and resetting the particles would only trade its precision for theirs.
//
// What the RBPF does with a correction (rbpf_slam.cpp): every particle is reset onto the corrected
// best trajectory and its rebuilt map, with weights reset. Why not move every particle by the same
// rigid transform: the correction is not rigid (a loop bends the whole trajectory), the other
// particles' maps differ from the best one non-rigidly too, and a map that contradicts the
// optimised trajectory is exactly the inconsistency loop closure must remove. The filter loses its
// diversity at that moment, but the motion model re-spreads the particles within a few scans, and
// the graph — not the particle set — now carries the long-loop hypothesis.
#ifndef MINIBOT3D_SLAM_SRC_LOOP_CLOSER_H_
#define MINIBOT3D_SLAM_SRC_LOOP_CLOSER_H_

#include <Eigen/Core>
#include <cstdint>
#include <list>
#include <memory>
#include <vector>

#include "grid.h"
#include "minibot3d_scan_matching/correlative_search.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/types.h"
#include "pose_graph.h"
#include "scan_matcher.h"

namespace minibot3d_slam {

using minibot3d_scan_matching::CheckCorrelativeSearchOptions;
using minibot3d_scan_matching::CorrelativeMatch;
using minibot3d_scan_matching::CorrelativeSearch;
using minibot3d_scan_matching::CorrelativeSearchOptions;

struct LoopConstraint {
  int from = 0, to = 0;  // submap's first node, current node
  Pose2 measurement;     // pose of `to` in the frame of `from`
  double score = 0.0;    // correlative score of the match
  // The rigid map-frame correction (matched pose ⊕ estimate⁻¹) the match implied when it was made:
  // scans after the same drift imply about the same one.
  Pose2 correction;
  bool confirmed = false;
  // A match in a corridor seen along its axis fixes the pose across the corridor and the heading,
  // not where along it: `along_axis` then, with `axis` the corridor's direction in the frame of
  // `from`.
  bool along_axis = false;
  double axis = 0.0;
};

class LoopCloser {
 public:
  static constexpr std::size_t kMaxSearchesPerScan = 1;
  static constexpr int kSearchEvery = 3;  // processed scans (Cartographer samples likewise)
  static constexpr double kAngularStepRange = 10.0;  // m (see the constructor)
  // A match is ambiguous, and dropped, when another place kAmbiguitySeparation away scores at
  // least kAmbiguityRatio of it.
  static constexpr double kAmbiguitySeparation = 0.5, kAmbiguityRatio = 0.95;
  // An ambiguous match is still a corridor constraint (along_axis) when the look-alike places
  // (up to kMaxCandidates) lie on one line through the best, within kAxisOffLine of it, at its
  // heading within kAxisTurn; the constraint's standard deviation along the line is kAlongSigma.
  static constexpr int kMaxCandidates = 3;
  static constexpr double kAxisOffLine = 0.1, kAxisTurn = 0.02;  // m, rad
  static constexpr double kAlongSigma = 10.0;                     // m
  // An endpoint in a submap's free cell conflicts only with no wall within this many cells.
  static constexpr int kConflictCells = 2;
  static constexpr int kOptimizeEvery = 10;        // nodes
  static constexpr int kTentativeNodes = 30;       // how long a large correction waits for a second
  static constexpr double kBigCorrection = 0.3;    // m (or 10× that in rad)
  // Two matches against one submap confirm each other only this far apart in path, and only
  // with the search window grown past loopSearchWindow (see Detect).
  static constexpr double kSameSubmapApart = 6.0;  // m
  // An optimisation is applied to the filter only when it moves the newest node by this much.
  static constexpr double kApplyShift = 0.10, kApplyTurn = 0.0175;  // m, rad (1°)
  // Edge standard deviations: consecutive nodes (scan-matched) and loop closures.
  static constexpr double kSequentialSigmaXy = 0.02, kSequentialSigmaTheta = 0.005;
  static constexpr double kLoopSigmaXy = 0.03, kLoopSigmaTheta = 0.01;

  LoopCloser(const GmappingOptions& options, const ScanMatcher* matcher);

  // Records processed scan number size() (the scans' node indices are consecutive from 0).
  void AddNode(const PreparedScan& scan);
  int size() const { return static_cast<int>(scans_.size()); }

  // Tries to close loops from the newest node, given the best particle's pose of every node
  // (trajectory.size() == size()). Returns true when the graph should be optimised now.
  bool Detect(const std::vector<Pose2>& trajectory);

  // Optimises the pose graph whose node poses start at `trajectory`; returns the corrected poses.
  std::vector<Pose2> Optimize(const std::vector<Pose2>& trajectory);

  // Renders every stored scan at the given poses into `grid`.
  void RenderMap(const std::vector<Pose2>& trajectory, Grid* grid) const;

  const std::vector<LoopConstraint>& constraints() const { return constraints_; }
  int optimizations() const { return optimizations_; }
  int searches() const { return searches_; }
  int outliers() const { return outliers_; }
  int ambiguous() const { return ambiguous_; }
  int conflicting() const { return conflicting_; }  // matches dropped by the free-space check
  std::size_t ScanBytes() const;  // memory of the stored scans
  // Half-width of the search in a submap that ended `path` metres of path ago.
  double SearchWindow(double path) const;

 private:
  // Beam directions of one laser geometry, shared by the scans taken with it (NaN: a beam no
  // scan referring to the table has used yet).
  struct Directions {
    std::vector<float> cos, sin;
  };
  // A scan kept for re-rendering and for matching, in 8 bytes per beam (ranges cut to maxUrange).
  struct StoredScan {
    Pose2 sensor_in_base;
    std::shared_ptr<const Directions> directions;
    std::vector<float> range;
    std::vector<std::uint32_t> beam_hit;  // beam index in `directions` << 1 | end is a hit
    float Cos(std::size_t i) const { return directions->cos[beam_hit[i] >> 1]; }
    float Sin(std::size_t i) const { return directions->sin[beam_hit[i] >> 1]; }
    bool Hit(std::size_t i) const { return (beam_hit[i] & 1u) != 0; }
  };
  struct RenderedSubmap {
    int index = -1;
    std::vector<Pose2> poses;  // of the submap's nodes, as rendered
    Grid grid;
    std::unique_ptr<CorrelativeSearch> search;
    explicit RenderedSubmap(double resolution) : grid(resolution) {}
  };

  // A finished submap near enough to the current estimate to search the newest scan in.
  struct SubmapCandidate {
    double distance;  // from the estimate to the submap's nearest node
    int submap;
    double window;    // half-width of the search
    bool operator<(const SubmapCandidate& o) const { return distance < o.distance; }
  };
  // Whether an earlier constraint t agrees with a new one, and which of the two can vouch for
  // the other.
  struct Agreement {
    bool agree = false, vouches_for_t = false, t_vouches = false;
  };

  void Render(const StoredScan& s, const Pose2& pose, Grid* grid) const;
  RenderedSubmap* Submap(int index, const std::vector<Pose2>& trajectory);
  // The submaps to search the newest node's scan in, nearest first (see Detection above).
  std::vector<SubmapCandidate> Candidates(const std::vector<Pose2>& trajectory) const;
  // The share of the scan's endpoints at `pose`, among those in cells `grid` has seen, that fall
  // in a free cell with no wall within kConflictCells (0 when it has seen none of them).
  static double Conflict(const StoredScan& s, const Pose2& pose, const Grid& grid);
  // A stored scan's beams that end in a hit, as the scan matcher takes them.
  static PreparedScan MatchingBeams(const StoredScan& s);
  // Searches the newest scan in the candidate submap and refines the match there; false when
  // there is no match, it is ambiguous (and not a corridor's), or the refinement wanders off.
  // Otherwise *c is the constraint from the submap's first node to the newest one and
  // *refined_pose the newest node's matched pose.
  bool Match(const SubmapCandidate& cand, const std::vector<Pose2>& trajectory,
             const std::vector<Eigen::Vector2d>& points, const PreparedScan& prepared,
             LoopConstraint* c, Pose2* refined_pose);
  Agreement Agree(const LoopConstraint& c, const Pose2& refined, const LoopConstraint& t,
                  const std::vector<Pose2>& trajectory) const;
  // Whether c corrects the estimate by less than kBigCorrection, and repeats no large claim
  // still waiting for a second opinion.
  bool SmallCorrection(const LoopConstraint& c, const Pose2& refined,
                       const std::vector<Pose2>& trajectory) const;
  // Puts a small correction into the graph; a large one waits in tentative_ until another
  // constraint confirms it (see Back-end above). `window`: the search's half-width.
  void AddConstraint(LoopConstraint c, const Pose2& refined, double window,
                     const std::vector<Pose2>& trajectory);

  GmappingOptions options_;
  const ScanMatcher* matcher_;
  CorrelativeSearchOptions search_options_;
  std::vector<StoredScan> scans_;
  std::shared_ptr<Directions> directions_;  // the newest scan's table
  std::size_t direction_tables_ = 0, direction_bytes_ = 0;
  // The newest node's matching endpoints in the base frame (the search needs no older node's).
  std::vector<Eigen::Vector2f> newest_points_;
  std::vector<double> path_;  // path length at each node (best trajectory at the time it was added)
  // Path length at the newest node a loop constraint in the graph ends at (not a corridor one: it
  // leaves the drift along the corridor open).
  double anchored_path_ = 0.0;
  std::vector<LoopConstraint> constraints_;
  std::list<std::unique_ptr<RenderedSubmap>> cache_;  // most recently used first
  int pending_ = 0;           // constraints added since the last optimisation
  bool big_pending_ = false;  // two of them agree on a large correction of the estimate
  std::vector<LoopConstraint> tentative_;  // large corrections waiting for a second opinion
  int last_optimized_ = 0;    // node count at the last optimisation
  int optimizations_ = 0, searches_ = 0, outliers_ = 0, ambiguous_ = 0, conflicting_ = 0;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_LOOP_CLOSER_H_
