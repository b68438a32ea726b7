// SLAM accuracy from relative displacements: the "relations" metric of R. Kümmerle, B. Steder,
// C. Dornhege, M. Ruhnke, G. Grisetti, C. Stachniss and A. Kleiner, "On measuring the accuracy of
// SLAM algorithms", Autonomous Robots 27(4), 2009. For each relation (i, j) with true relative
// pose δ*_ij, the estimate gives δ_ij = x_j ⊖ x_i, and the error of the relation is
// δ_ij ⊖ δ*_ij. Translational error |(dx, dy)| and rotational error |dθ| are reported separately
// (mean ± standard deviation, absolute and squared), as the paper's tables do, because the two
// live in different units. Unlike an absolute trajectory error, a global offset or a drift that
// happened before both poses of a relation does not count: only the local geometry does.
//
// Files (plain text, whitespace-separated, '#' starts a comment, blank lines ignored):
//   trajectory  "timestamp x y theta"            s, m, m, rad (what slam_offline writes and the
//                                                 simulator's ground truth is logged as)
//   relations   "t1 t2 x y z roll pitch yaw"     the format of the Freiburg/Kümmerle relation
//                                                 files: the true pose of the robot at t2 in its
//                                                 frame at t1 (m, rad). Planar: z, roll and pitch
//                                                 are read and ignored.
//
// No ROS here.
#ifndef MINIBOT3D_SLAM_RELATIONS_H_
#define MINIBOT3D_SLAM_RELATIONS_H_

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

class RelationsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A true relative displacement: the robot's pose at t2 expressed in its frame at t1.
struct Relation {
  double t1 = 0.0;
  double t2 = 0.0;
  Pose2 delta;
};

// Readers throw RelationsError naming the file and, for a bad line, "PATH:LINE: what". A file
// without any pose / relation is an error too. Poses are returned sorted by time (stable).
std::vector<StampedPose> ReadTrajectory(const std::string& path);
std::vector<Relation> ReadRelations(const std::string& path);

// Writers replace the file atomically (temporary file + rename); `comment` lines, if any, go
// first, each prefixed with "# ". Numbers are written so they read back exactly.
void WriteTrajectory(const std::string& path, const std::vector<StampedPose>& poses,
                     const std::string& comment = "");
void WriteRelations(const std::string& path, const std::vector<Relation>& relations,
                    const std::string& comment = "");

// How a relation's timestamps are matched to the estimated trajectory's poses.
struct MatchOptions {
  // A pose within this many seconds of a relation time is an exact match (timestamps written
  // with limited precision by different tools).
  double exact_tolerance = 1e-3;
  // Otherwise the nearest pose is taken if it is within this many seconds (half the period of a
  // 10 Hz scanner); else the relation is unmatched and left out.
  double nearest_tolerance = 0.05;
};

struct ErrorStats {
  double mean = 0.0;
  double stddev = 0.0;  // sample standard deviation (N - 1); 0 for a single value
  double max = 0.0;
};

struct RelationsReport {
  int total = 0;       // relations given
  int used = 0;        // relations whose two poses were both matched
  int unmatched = 0;   // total - used
  int exact_matches = 0;    // pose look-ups (two per used relation) matched within exact_tolerance
  int nearest_matches = 0;  // pose look-ups matched to the nearest pose beyond exact_tolerance
  double max_time_offset = 0.0;  // s, largest |t_pose - t_relation| among the used look-ups
  ErrorStats translation;     // m
  ErrorStats rotation;        // rad
  ErrorStats translation_sq;  // m^2
  ErrorStats rotation_sq;     // rad^2
  std::vector<Pose2> errors;  // δ_ij ⊖ δ*_ij of each used relation, in input order
};

// Evaluates `estimate` (any order; sorted internally) against `relations`.
RelationsReport EvaluateRelations(const std::vector<StampedPose>& estimate,
                                  const std::vector<Relation>& relations,
                                  const MatchOptions& options = MatchOptions());

// The summary line: "relations N translation_m MEAN ± STD rotation_deg MEAN ± STD", then lines
// with the squared errors, maxima and how the timestamps were matched.
std::string FormatReport(const RelationsReport& report);

// Generating relations from a ground-truth trajectory (e.g. the simulator's true pose):
//  - anchors are the first pose and then each first pose at least `every` seconds after the
//    previous anchor (every = 0: every pose);
//  - each anchor is related to the next anchor (the local, short-range accuracy), and
//  - to `random_per_anchor` poses drawn uniformly (seeded, reproducible) among the poses up to
//    `max_span` seconds after it (the larger-scale consistency, e.g. across a loop);
//  - duplicates are dropped; relations come sorted by (t1, t2).
// The relative poses are exact (Between(gt_i, gt_j)), unlike the paper's hand-aligned scans.
struct MakeRelationsOptions {
  double every = 1.0;      // s
  double max_span = 10.0;  // s
  int random_per_anchor = 3;
  std::uint64_t seed = 0;
};

// Throws RelationsError on bad options (every < 0, max_span <= 0, random_per_anchor < 0).
std::vector<Relation> MakeRelations(const std::vector<StampedPose>& ground_truth,
                                    const MakeRelationsOptions& options = MakeRelationsOptions());

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_RELATIONS_H_
