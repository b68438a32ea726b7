// Occupancy grid and the per-map precomputation AMCL needs.
//
// The likelihood-field sensor model (Thrun et al., "Probabilistic Robotics",
// sec. 6.4) needs, for every cell, the distance to the nearest occupied cell.
// Computing it per beam would dominate the filter, so MapModel computes the
// whole field once per map with OpenCV's exact Euclidean distance transform
// (cv::distanceTransform, DIST_L2, DIST_MASK_PRECISE) and caps it at
// laser_likelihood_max_dist, exactly the quantity ROS amcl's
// map_update_cspace() produces by brute-force expansion.  It also keeps the
// list of free cells so global localization and augmented-MCL injection can
// draw poses uniformly over free space, and a ray caster for the beam model.
#ifndef MINIBOT3D_NAVIGATION_AMCL_OCCUPANCY_MAP_H_
#define MINIBOT3D_NAVIGATION_AMCL_OCCUPANCY_MAP_H_

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "minibot3d_map_io/map_io.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

// The workspace's occupancy grid (minibot3d_map_io): nav_msgs/OccupancyGrid's
// layout, values -1 unknown, 0 (free) .. 100 (occupied).
using OccupancyGrid = minibot3d_map_io::OccupancyGrid;

// Cell classification.  These are map_server's default thresholds
// (free_thresh 0.196, occupied_thresh 0.65); for trinary maps (0/100/-1, as
// published by map_server and gmapping) the result is identical to ROS amcl,
// which treats exactly 0 as free and exactly 100 as occupied.
constexpr int kMaxFreeValue = 19;      // 0 <= v <= 19 is free
constexpr int kMinOccupiedValue = 66;  // v >= 66 is occupied

class MapModel {
 public:
  // Builds the distance field (capped at max_occ_dist metres) and free list.
  // Throws std::invalid_argument naming the problem for a malformed grid
  // (non-positive size or resolution, data size mismatch, values outside
  // -1..100, non-finite origin) or a map with no free cells.
  MapModel(const OccupancyGrid& grid, double max_occ_dist);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  const Pose2& origin() const { return origin_; }
  double max_occ_dist() const { return max_occ_dist_; }
  const std::vector<int>& free_cells() const { return free_cells_; }

  bool InBounds(int i, int j) const {
    return i >= 0 && j >= 0 && i < width_ && j < height_;
  }
  bool IsFree(int i, int j) const { return state_[Index(i, j)] == kFree; }
  bool IsOccupied(int i, int j) const {
    return state_[Index(i, j)] == kOccupied;
  }
  // Distance in metres from cell (i, j)'s centre to the nearest occupied
  // cell centre, capped at max_occ_dist().  (i, j) must be in bounds.
  double Distance(int i, int j) const { return distance_[Index(i, j)]; }

  // The "grid frame" is the map frame rotated/translated so that the grid is
  // axis-aligned with cell (0, 0)'s corner at the origin: cell (i, j) spans
  // [i*res, (i+1)*res) x [j*res, (j+1)*res).  Hot loops work in it so that
  // origin_theta costs one transform per particle, not one per beam.
  Pose2 WorldToGridFrame(const Pose2& world) const;
  Pose2 GridFrameToWorld(const Pose2& grid) const;

  // Cell containing the world point; false (and *i, *j untouched) off-map.
  bool WorldToCell(double wx, double wy, int* i, int* j) const;
  // World coordinates of the centre of cell (i, j).
  void CellCenterToWorld(int i, int j, double* wx, double* wy) const;

  // Capped distance at a grid-frame point; max_occ_dist() off the map (as
  // amcl, an off-map beam end point counts as "far from any obstacle").
  double DistanceAtGridPoint(double gx, double gy) const {
    const double fi = gx * inv_resolution_, fj = gy * inv_resolution_;
    if (!(fi >= 0.0 && fj >= 0.0 && fi < width_ && fj < height_)) {
      return max_occ_dist_;  // also catches NaN
    }
    return distance_[static_cast<size_t>(fj) * width_ +
                     static_cast<size_t>(fi)];
  }

  // Range along a ray from a grid-frame point until it enters a cell that is
  // not free (occupied, unknown or off-map), as ROS amcl's map_calc_range:
  // exact grid traversal (Amanatides & Woo), returns max_range if nothing is
  // hit before it, 0 if the start cell itself is not free.
  double CalcRangeGrid(double gx, double gy, double angle,
                       double max_range) const;
  // Same, from a world pose (x, y, yaw).
  double CalcRange(const Pose2& world_ray, double max_range) const;

  // A pose uniformly distributed over free space: a uniformly chosen free
  // cell, a uniform position inside it, a uniform yaw in [-pi, pi).
  Pose2 SampleFreePose(std::mt19937_64* rng) const;

  // Heap bytes held (distance field, cell states, free list).
  size_t MemoryBytes() const;

 private:
  enum CellState : int8_t { kFree = 0, kUnknown = 1, kOccupied = 2 };
  size_t Index(int i, int j) const {
    return static_cast<size_t>(j) * width_ + static_cast<size_t>(i);
  }

  int width_;
  int height_;
  double resolution_;
  double inv_resolution_;
  Pose2 origin_;
  double cos_origin_;
  double sin_origin_;
  double max_occ_dist_;
  std::vector<int8_t> state_;
  std::vector<float> distance_;
  std::vector<int> free_cells_;  // linear indices j * width + i
};

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_OCCUPANCY_MAP_H_
