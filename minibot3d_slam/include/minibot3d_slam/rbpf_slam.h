// Grid-based Rao-Blackwellized particle filter SLAM after Grisetti, Stachniss & Burgard,
// "Improved techniques for grid mapping with Rao-Blackwellized particle filters" (IEEE T-RO 2007).
// (Algorithm summary: see the implementation's header comment.)
#ifndef MINIBOT3D_SLAM_RBPF_SLAM_H_
#define MINIBOT3D_SLAM_RBPF_SLAM_H_

#include <memory>
#include <vector>

#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

class RbpfSlam {
 public:
  explicit RbpfSlam(const GmappingOptions& options);  // validates options (throws)
  ~RbpfSlam();
  RbpfSlam(const RbpfSlam&) = delete;
  RbpfSlam& operator=(const RbpfSlam&) = delete;

  // Feeds one scan with the odometry pose of the robot's base at the scan's time. Returns true
  // when the scan was processed (moved linearUpdate/angularUpdate, temporalUpdate passed, or the
  // first scan); false when it was only used to advance the motion model.
  bool AddScan(const LaserScan& scan, const Pose2& odom);

  // The best particle's pose of the base in the map frame at the last scan given to AddScan
  // (processed or not: unprocessed scans move the pose by the odometry increment).
  Pose2 BestPose() const;
  // map → odom correction for that pose: Compose(MapToOdom(), odom) == BestPose().
  Pose2 MapToOdom() const;
  // The best particle's map, occupancy probabilities thresholded as gmapping does (100 above
  // occ_thresh, 0 below, -1 never observed); grows as the robot explores.
  GridMap Map() const;
  // The best particle's poses at every processed scan, oldest first.
  std::vector<StampedPose> BestTrajectory() const;
  // The pose of `scan` against the best particle's current map, starting from `guess` (the map is
  // not changed): the heading the filter's hill climber and sub-cell refinement find, and the
  // position the sub-cell refinement (point-to-line) alone finds from the guess's position at that
  // heading (each refinement pass moves it at most a cell, so the guess's position must be about
  // that good: slam_offline places its readings between two processed poses). With subcellMatch
  // 0, the climber's pose as is. Returns `guess` when the climb scores at or below minimumScore or
  // nothing was mapped yet. For the poses of readings the filter did not process, which odometry
  // alone places with its rotation error. Why the position does not come from the climb:
  // point-to-point, it wanders along a bare corridor from one reading to the next, while
  // point-to-line puts no pull along a wall and keeps the guess's position there.
  Pose2 Localize(const LaserScan& scan, const Pose2& guess) const;
  // Entropy of the normalised particle weights (gmapping's ~entropy).
  double Entropy() const;

  int processed_scans() const;
  // Bytes of map cells held by all particles together (tiles shared copy-on-write counted once):
  // it grows with the area the laser has covered and with what the particles changed since they
  // last shared an ancestor, not with the bounding box of the trajectory.
  std::size_t MapMemoryBytes() const;
  // Bytes of the scans the loop closer keeps to re-render the map (0 with loopClosure = 0).
  std::size_t LoopScanBytes() const;
  // Bytes of the trajectory tree: its distinct nodes (pose and time, no scan), shared by the
  // particles. With LoopScanBytes, what the filter keeps per processed scan (rbpf_slam_test
  // bounds it); neither keeps the readings that were not processed.
  std::size_t TrajectoryBytes() const;
  // Pose-graph optimisations applied so far (loopClosure = 1): each one replaced the trajectory and
  // the map by corrected ones, so a node should republish both.
  int loop_closures() const;
  // Optimises the pose graph with every constraint found so far and applies the result (as a
  // closure does), whether or not one is due: for the end of an offline run.
  void FinishLoops();
  // Loop-closure constraints currently in the pose graph.
  int loop_constraints() const;
  int resamples() const;
  const GmappingOptions& options() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_RBPF_SLAM_H_
