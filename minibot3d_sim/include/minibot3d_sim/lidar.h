// A planar ray-cast lidar modelled on Gazebo's ray sensor.
//
// All beams of a scan are cast at one instant (as Gazebo does) against the world's cross-section at
// the sensor's height (WorldSlice::CastFan: one pass over the nearby primitives per scan), beam i
// at min_angle + i·(max_angle − min_angle)/(samples − 1) in the sensor frame. Each true range gets
// additive Gaussian noise N(mean, stddev²), is quantised to the range resolution, and is reported
// per REP 117: +inf when nothing is within max_range, −inf when the return is closer than
// min_range. Moving bodies (other robots, actors) are convex polygons cast after the slice, nearest
// first, each only against the beams its angular extent covers and that have not already stopped
// short of it.
#ifndef MINIBOT3D_SIM_LIDAR_H_
#define MINIBOT3D_SIM_LIDAR_H_

#include <random>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;

// A moving body at a sensor's height: a convex outline (vertices in order) in the body's own
// frame, placed in the world at `pose`; the world-frame circle (`centre`, `radius`) bounds it.
struct BodyOutline {
  const std::vector<Eigen::Vector2d>* outline = nullptr;
  Pose2 pose;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;
};

class Lidar {
 public:
  // `slice` must be cut at the sensor's height and outlive the Lidar.
  Lidar(const LaserSpec& spec, const WorldSlice* slice, unsigned seed);

  // Ranges of one scan with the robot's root frame at `root_pose` (world frame). `bodies`, when
  // given, are moving bodies at the sensor's height that the beams also hit: other robots, actors.
  void Scan(const Pose2& root_pose, std::vector<float>* ranges,
            const std::vector<BodyOutline>* bodies = nullptr);

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
  struct NearBody {  // a body within reach: its circle's nearest point and centre's distance
    double closest, dist;
    std::size_t index;
  };
  std::vector<NearBody> near_;
  static constexpr int kBin = 8;  // beams per bin of bin_far_
  std::vector<double> bin_far_;   // per bin of beams, the furthest return off the world
  std::vector<Eigen::Vector2d> placed_;  // the body being cast, in the world frame
  std::vector<double> dir_x_, dir_y_, true_ranges_;  // per-scan scratch
  std::mt19937 rng_;
  std::normal_distribution<double> noise_;
  long rays_cast_ = 0;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_LIDAR_H_
