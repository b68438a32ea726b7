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
#include "minibot3d_navigation/dwa/dwa_options.h"

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

// The shipped settings (config/trajectory_planner.yaml, controller_frequency
// of config/move_base_params.yaml), with max_vel_x varied.
inline DwaOptions ShippedOptions(double max_vel_x) {
  DwaOptions o;
  o.controller_frequency = 10.0;
  o.max_vel_x = max_vel_x;
  o.min_vel_x = std::min(0.1, max_vel_x);
  o.max_vel_theta = 2.5;
  o.min_vel_theta = -2.5;
  o.min_in_place_vel_theta = 1.0;
  o.acc_lim_x = 2.5;
  o.acc_lim_theta = 4.0;
  o.max_centripetal_acc = 1.0;
  o.escape_vel = -0.1;
  o.sim_time = 1.5;
  o.sim_granularity = 0.025;
  o.vx_samples = 10;
  o.vtheta_samples = 20;
  o.path_distance_bias = 1.2;
  o.goal_distance_bias = 0.8;
  o.occdist_scale = 0.02;
  o.xy_goal_tolerance = 0.15;
  o.yaw_goal_tolerance = 0.15;
  o.latch_xy_goal_tolerance = true;
  o.meter_scoring = true;
  return o;
}

}  // namespace testing
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TEST_DWA_TEST_SCENES_H_
