// Test helper: a 2-D world of wall segments and an ideal laser ray-cast against it, to build
// scans with known ground truth for the SLAM, scan matching and localization tests.
#ifndef MINIBOT3D_TESTING_SYNTHETIC_WORLD_H_
#define MINIBOT3D_TESTING_SYNTHETIC_WORLD_H_

#include <cmath>
#include <limits>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_common/laser_scan.h"
#include "minibot3d_map_io/map_io.h"

namespace minibot3d_testing {

using minibot3d_common::LaserScan;
using minibot3d_common::Pose2;
using GridMap = minibot3d_map_io::OccupancyGrid;

struct Segment {
  double x0, y0, x1, y1;
};

struct World {
  std::vector<Segment> walls;

  void AddBox(double x0, double y0, double x1, double y1) {
    walls.push_back({x0, y0, x1, y0});
    walls.push_back({x1, y0, x1, y1});
    walls.push_back({x1, y1, x0, y1});
    walls.push_back({x0, y1, x0, y0});
  }

  // Distance along the ray from (x, y) in direction a to the nearest wall, or +inf.
  double Cast(double x, double y, double a) const {
    const double dx = std::cos(a), dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : walls) {
      const double ex = s.x1 - s.x0, ey = s.y1 - s.y0;
      const double den = dx * ey - dy * ex;
      if (std::fabs(den) < 1e-12) continue;
      const double wx = s.x0 - x, wy = s.y0 - y;
      const double t = (wx * ey - wy * ex) / den;   // along the ray
      const double u = (wx * dy - wy * dx) / den;   // along the segment
      if (t > 1e-9 && u >= 0.0 && u <= 1.0 && t < best) best = t;
    }
    return best;
  }

  // A scan of n beams over fov (centred ahead) from the sensor at `pose` (sensor at the base).
  LaserScan Scan(const Pose2& pose, int n = 181, double fov = M_PI, double range_max = 30.0,
                 double time = 0.0) const {
    LaserScan scan;
    scan.time = time;
    scan.range_min = 0.05;
    scan.range_max = range_max;
    for (int i = 0; i < n; ++i) {
      const double a = -fov / 2 + fov * i / (n - 1);
      double r = Cast(pose.x, pose.y, pose.yaw + a);
      if (!(r < range_max)) r = std::numeric_limits<double>::infinity();
      scan.angles.push_back(a);
      scan.ranges.push_back(r);
    }
    return scan;
  }
};

// An office-like room, 12 m × 8 m, with an inner block, a pillar and a wall stub so that no two
// places look alike. The walls are shifted off the 5 cm cell boundaries, as real walls are: a wall
// exactly on a boundary puts its hits on both sides of it at random.
inline World Office() {
  World w;
  w.AddBox(-6.0, -4.0, 6.0, 4.0);
  w.AddBox(-2.0, -1.0, 2.0, 1.0);
  w.AddBox(3.5, 2.0, 4.0, 2.6);
  w.walls.push_back({-6.0, 1.5, -4.5, 1.5});
  w.walls.push_back({1.0, -4.0, 1.0, -3.0});
  for (Segment& s : w.walls) {
    s.x0 += 0.0137;
    s.x1 += 0.0137;
    s.y0 -= 0.0213;
    s.y1 -= 0.0213;
  }
  return w;
}

}  // namespace minibot3d_testing

#endif  // MINIBOT3D_TESTING_SYNTHETIC_WORLD_H_
