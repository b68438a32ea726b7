// A planar ray-cast lidar modelled on Gazebo's ray sensor.
//
// All beams of a scan are cast at one instant (as Gazebo does) against the world's cross-section at
// the sensor's height (WorldSlice::CastFan: one pass over the nearby primitives per scan), beam i at min_angle + i·(max_angle − min_angle)/(samples − 1) in
// the sensor frame. Each true range gets additive Gaussian noise N(mean, stddev²), is quantised to
// the range resolution, and is reported per REP 117: +inf when nothing is within max_range, −inf
// when the return is closer than min_range. Moving bodies (other robots) are convex polygons cast
// after the slice, each only against the beams its angular extent covers.
#ifndef MINIBOT3D_SIM_LIDAR_H_
#define MINIBOT3D_SIM_LIDAR_H_

#include <random>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;

class Lidar {
 public:
  // `slice` must be cut at the sensor's height and outlive the Lidar.
  Lidar(const LaserSpec& spec, const WorldSlice* slice, unsigned seed);

  // Ranges of one scan with the robot's root frame at `root_pose` (world frame). `bodies`, when
  // given, are convex polygons (world frame, vertices in order) at the sensor's height that the
  // beams also hit: other robots.
  void Scan(const Pose2& root_pose, std::vector<float>* ranges,
            const std::vector<std::vector<Eigen::Vector2d>>* bodies = nullptr);

  double angle_increment() const { return increment_; }
  const LaserSpec& spec() const { return spec_; }
  void Reseed(unsigned seed) { rng_.seed(seed); }
  // Rays cast so far (for benchmarks).
  long rays_cast() const { return rays_cast_; }

 private:
  LaserSpec spec_;
  const WorldSlice* slice_;
  Pose2 sensor_in_root_;
  double increment_ = 0.0;
  std::vector<double> cos_, sin_;  // beam directions in the sensor frame
  std::vector<double> dir_x_, dir_y_, true_ranges_;  // per-scan scratch
  std::mt19937 rng_;
  std::normal_distribution<double> noise_;
  long rays_cast_ = 0;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_LIDAR_H_
