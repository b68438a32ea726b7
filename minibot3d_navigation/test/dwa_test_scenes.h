// Shared scene builders of the DWA planner's tests and benchmark: local costmaps made of boxes of
// lethal cells, inflated by brute force with costmap_2d's formula (independently of the
// inflation layer, so the planner is not checked against code it shares).
#ifndef MINIBOT3D_NAVIGATION_TEST_DWA_TEST_SCENES_H_
#define MINIBOT3D_NAVIGATION_TEST_DWA_TEST_SCENES_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/footprint.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace testing {

// The scenes' robot: 0.26 m x 0.25 m, centred on its base.
inline const Footprint kFootprint = {
    {-0.13, -0.125}, {-0.13, 0.125}, {0.13, 0.125}, {0.13, -0.125}};

// Marks lethal every cell whose centre lies in [x0, x1] x [y0, y1].
inline void AddBox(Costmap2D* map, double x0, double y0, double x1, double y1) {
  for (int my = 0; my < map->size_y(); ++my) {
    for (int mx = 0; mx < map->size_x(); ++mx) {
      double wx, wy;
      map->MapToWorld(mx, my, &wx, &wy);
      if (wx >= x0 && wx <= x1 && wy >= y0 && wy <= y1) {
        map->set_cost(mx, my, kLethalObstacle);
      }
    }
  }
}

// costmap_2d's InflationLayer, brute force: every cell that is not lethal gets 253 within
// `inscribed` of a lethal cell, 252 * exp(-k (d - inscribed)) out to `radius`, 0 beyond.
inline void Inflate(Costmap2D* map, double inscribed, double radius, double k) {
  const double res = map->resolution();
  const int r = static_cast<int>(std::ceil(radius / res));
  std::vector<double> dist(map->cells().size(), 1e9);
  for (int my = 0; my < map->size_y(); ++my) {
    for (int mx = 0; mx < map->size_x(); ++mx) {
      if (map->cost(mx, my) != kLethalObstacle) continue;
      for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
          if (!map->InBounds(mx + dx, my + dy)) continue;
          double& d = dist[map->Index(mx + dx, my + dy)];
          d = std::min(d, std::hypot(dx, dy) * res);
        }
      }
    }
  }
  for (int my = 0; my < map->size_y(); ++my) {
    for (int mx = 0; mx < map->size_x(); ++mx) {
      const double d = dist[map->Index(mx, my)];
      if (map->cost(mx, my) == kLethalObstacle) continue;
      uint8_t c = 0;
      if (d <= inscribed) {
        c = kInscribedInflatedObstacle;
      } else if (d <= radius) {
        c = static_cast<uint8_t>(252.0 * std::exp(-k * (d - inscribed)));
      }
      map->set_cost(mx, my, c);
    }
  }
}

}  // namespace testing
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TEST_DWA_TEST_SCENES_H_
