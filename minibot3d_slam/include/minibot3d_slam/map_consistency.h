// How well a trajectory's scans agree with each other where the robot came back: a score of map
// consistency for logs without ground truth.
//
// The idea is the contradiction between what one part of a trajectory saw and the map the rest of
// it makes, used to find mapping errors without ground truth (Chandran-Ramesh & Newman, "Assessing
// map quality using conditional random fields", FSR 2007; Mazuran, Tipaldi, Spinello, Burgard &
// Stachniss, "A statistical measure for map consistency in SLAM", ICRA 2014), reduced here to
// counting free-space/occupied contradictions. When a correct map sees a place on two passes, a
// wall seen on one pass lies where the other pass saw a wall too, never where the other pass's
// beams went through. A doubled or bent wall puts one pass's endpoints in space another pass saw
// as free (the wall moved towards that pass) or lets one pass's beams run through the other's
// wall (it moved away, and then the other pass's endpoints are the ones found in free space).
//
// Algorithm, on a grid of `resolution`:
//   1. Every scan marks, for each beam up to `max_range`, its endpoint cell as hit and the cells
//      along the beam up to `tolerance` before the endpoint as seen free, storing per cell the
//      smallest and largest path length s (metres driven since the first scan) of the scans that
//      hit it and that saw it free.
//   2. The scans to check are picked as gmapping picks the scans it processes: the first, then
//      each one after the robot moved `every_distance` or turned `every_angle`.
//   3. For each of their endpoints at path length s: hits of another pass (path length outside
//      s ± `separation`) within `tolerance` → agreed; otherwise, if another pass saw the
//      endpoint's cell free → a conflict; otherwise the place was not seen again and the
//      endpoint is not counted.
// Reported: conflicts / (agreed + conflicts) over all checked endpoints, and the scans with at
// least `min_scan_endpoints` counted endpoints of which more than `scan_conflict_fraction`
// conflict (a scan placed off the map). People walking and glass make conflicts in a correct map
// too, so the figure is compared between trajectories of the same log (raw odometry, a reference,
// a SLAM estimate), not read as an absolute error.
//
// No ROS here.
#ifndef MINIBOT3D_SLAM_MAP_CONSISTENCY_H_
#define MINIBOT3D_SLAM_MAP_CONSISTENCY_H_

#include <map>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

struct ConsistencyOptions {
  double resolution = 0.05;
  double max_range = 10.0;
  double tolerance = 0.10;
  double separation = 10.0;
  double every_distance = 1.0;
  double every_angle = 0.5;
  int min_scan_endpoints = 20;
  double scan_conflict_fraction = 0.3;
};

// The table of map_consistency's parameters (`--param NAME=VALUE`), and their validation: throws
// std::invalid_argument naming every offending parameter.
const minibot3d_common::options::OptionTable<ConsistencyOptions>& ConsistencyOptionTable();
void ValidateConsistencyOptions(const ConsistencyOptions& o);

// A laser reading placed where a trajectory says the robot was (the robot's base in the map).
struct PlacedScan {
  double time = 0.0;
  Pose2 pose;
  LaserScan scan;  // ranges, angles and sensor_in_base; +inf or NaN for no return
};

struct ScanConsistency {
  double time = 0.0;
  int agreed = 0;
  int conflicts = 0;
};

struct ConsistencyReport {
  int scans = 0;               // scans given
  int scans_checked = 0;       // picked by every_distance / every_angle
  long long endpoints = 0;     // endpoints of the checked scans within max_range
  long long agreed = 0;
  long long conflicts = 0;
  long long not_revisited = 0;
  double conflict_fraction = 0.0;  // conflicts / (agreed + conflicts); 0 when nothing was revisited
  int scans_judged = 0;            // checked scans with >= min_scan_endpoints agreed + conflicts
  // Judged scans over scan_conflict_fraction, worst first.
  std::vector<ScanConsistency> inconsistent;
};

// Throws std::invalid_argument for invalid options or a scan with a non-finite pose or a beam
// count different from its angle count (naming the scan's time).
ConsistencyReport EvaluateConsistency(const std::vector<PlacedScan>& scans,
                                      const ConsistencyOptions& options = ConsistencyOptions());

// The readings of a log that another log of the same run also holds. A trajectory is compared with
// a reference on the same scans: the placed scans make the map the checked ones are judged on, and
// GMapping's corrected logs (.gfs) keep only the scans GMapping processed, a sparser map than all
// of a raw log's scans make. Readings are matched by their ranges rounded to 1 cm (a corrected log
// copies the raw log's readings; no-returns match no-returns), each reference scan once.
class ReferenceScans {
 public:
  explicit ReferenceScans(const std::vector<LaserScan>& reference);
  // True when `scan` has the ranges of a reference scan not yet taken; takes it.
  bool Take(const LaserScan& scan);
  int size() const { return size_; }
  int taken() const { return taken_; }

 private:
  std::map<std::vector<long long>, int> left_;  // ranges in cm (no return: a sentinel) → count
  int size_ = 0;
  int taken_ = 0;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_MAP_CONSISTENCY_H_
