// Shared fixtures for the AMCL core tests: synthetic occupancy grids and a
// laser simulator.  The simulator ray-marches the raw grid itself (fine fixed
// steps), independently of MapModel's ray caster, so sensor-model tests do
// not check the code against itself.
#ifndef MINIBOT3D_NAVIGATION_TEST_AMCL_TEST_UTILS_H_
#define MINIBOT3D_NAVIGATION_TEST_AMCL_TEST_UTILS_H_

#include <cmath>
#include <random>
#include <vector>

#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {
namespace testing {

// An empty grid (all free) of the given size in metres.
inline OccupancyGrid MakeFreeGrid(double width_m, double height_m, double res,
                                  double origin_x = 0.0, double origin_y = 0.0,
                                  double origin_theta = 0.0) {
  OccupancyGrid g;
  g.resolution = res;
  g.origin_x = origin_x;
  g.origin_y = origin_y;
  g.origin_theta = origin_theta;
  g.width = static_cast<int>(std::lround(width_m / res));
  g.height = static_cast<int>(std::lround(height_m / res));
  g.data.assign(static_cast<size_t>(g.width) * g.height, 0);
  return g;
}

// Marks as occupied every cell whose centre lies in the axis-aligned box
// [x0, x1] x [y0, y1] given in grid-frame metres (relative to the origin
// corner; the tests' maps have origin_theta 0 unless stated).
inline void FillBox(OccupancyGrid* g, double x0, double y0, double x1,
                    double y1, int8_t value = 100) {
  for (int j = 0; j < g->height; ++j) {
    for (int i = 0; i < g->width; ++i) {
      const double cx = (i + 0.5) * g->resolution;
      const double cy = (j + 0.5) * g->resolution;
      if (cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1) {
        g->data[static_cast<size_t>(j) * g->width + i] = value;
      }
    }
  }
}

// Closed room with a one-cell outer wall.
inline OccupancyGrid MakeWalledRoom(double width_m, double height_m, double res,
                                    double origin_x = 0.0,
                                    double origin_y = 0.0) {
  OccupancyGrid g = MakeFreeGrid(width_m, height_m, res, origin_x, origin_y);
  const double t = res;  // wall thickness: one cell
  FillBox(&g, 0, 0, width_m, t);
  FillBox(&g, 0, height_m - t, width_m, height_m);
  FillBox(&g, 0, 0, t, height_m);
  FillBox(&g, width_m - t, 0, width_m, height_m);
  return g;
}

// 10 m x 8 m room, 5 cm cells, origin (-2, -1.5): walls plus asymmetric
// furniture (an L-shaped partition, a box, a pillar, a wall notch) so that
// no other pose sees the same scan.
inline OccupancyGrid MakeAsymmetricRoom() {
  OccupancyGrid g = MakeWalledRoom(10.0, 8.0, 0.05, -2.0, -1.5);
  FillBox(&g, 6.0, 0.0, 6.15, 3.0);   // partition from the south wall
  FillBox(&g, 6.0, 2.85, 8.0, 3.0);   // ... turning east (L)
  FillBox(&g, 1.5, 5.5, 2.7, 6.3);    // box in the north-west
  FillBox(&g, 4.0, 3.8, 4.3, 4.1);    // pillar
  FillBox(&g, 0.0, 2.0, 0.6, 2.4);    // notch on the west wall
  FillBox(&g, 8.5, 6.5, 10.0, 8.0);   // filled north-east corner
  return g;
}

// Range from a world pose along its yaw to the first occupied cell, by
// marching in 2 mm steps; range_max if nothing is hit.
inline double MarchRange(const OccupancyGrid& g, const Pose2& ray,
                         double range_max) {
  const double c0 = std::cos(g.origin_theta), s0 = std::sin(g.origin_theta);
  const double step = 0.002;
  for (double r = 0.0; r < range_max; r += step) {
    const double wx = ray.x + r * std::cos(ray.yaw);
    const double wy = ray.y + r * std::sin(ray.yaw);
    const double dx = wx - g.origin_x, dy = wy - g.origin_y;
    const double gx = c0 * dx + s0 * dy, gy = -s0 * dx + c0 * dy;
    const int i = static_cast<int>(std::floor(gx / g.resolution));
    const int j = static_cast<int>(std::floor(gy / g.resolution));
    if (i < 0 || j < 0 || i >= g.width || j >= g.height) return range_max;
    if (g.data[static_cast<size_t>(j) * g.width + i] >= 66) return r;
  }
  return range_max;
}

// A full 360-degree scan of `count` beams taken by a laser mounted at
// laser_pose (base frame) on a robot at `robot` (world), Gaussian range
// noise of `noise_sd` metres.
inline LaserScan SimulateScan(const OccupancyGrid& g, const Pose2& robot,
                              const Pose2& laser_pose, int count,
                              double range_max, double noise_sd,
                              std::mt19937_64* rng) {
  LaserScan scan;
  scan.sensor_in_base = laser_pose;
  scan.range_min = 0.15;
  scan.range_max = range_max;
  scan.angles = MakeBeamAngles(-kPi, 2.0 * kPi / count, count);
  std::normal_distribution<double> noise(0.0, noise_sd);
  const Pose2 laser_world = Compose(robot, laser_pose);
  for (double a : scan.angles) {
    Pose2 ray = laser_world;
    ray.yaw = laser_world.yaw + a;
    double r = MarchRange(g, ray, range_max);
    if (r < range_max && noise_sd > 0.0) r += noise(*rng);
    scan.ranges.push_back(static_cast<float>(r));
  }
  return scan;
}

}  // namespace testing
}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TEST_AMCL_TEST_UTILS_H_
