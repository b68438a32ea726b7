// Shared fixture of the global-planner tests: tiny standard maps written as text, after
// robot_navigation/global_planner_tests/maps.
#ifndef MINIBOT3D_NAVIGATION_TEST_PLANNER_TEST_MAPS_H_
#define MINIBOT3D_NAVIGATION_TEST_PLANNER_TEST_MAPS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {
namespace testing {

constexpr double kRes = 0.1;  // m per cell of every text map

// The first row is the top of the map (largest y).  '.' free, '#' lethal,
// 'i' inscribed (253), 'a' inflation 200, 'b' inflation 100, 'c' 30,
// 'u' unknown.
inline Costmap2D MapFromAscii(const std::vector<std::string>& rows) {
  const int h = static_cast<int>(rows.size());
  const int w = static_cast<int>(rows[0].size());
  Costmap2D map(w, h, kRes, 0.0, 0.0);
  for (int r = 0; r < h; ++r) {
    for (int x = 0; x < w; ++x) {
      uint8_t c = 0;
      switch (rows[r][x]) {
        case '#': c = kLethalObstacle; break;
        case 'i': c = kInscribedInflatedObstacle; break;
        case 'a': c = 200; break;
        case 'b': c = 100; break;
        case 'c': c = 30; break;
        case 'u': c = kNoInformation; break;
        default: c = 0;
      }
      map.set_cost(x, h - 1 - r, c);
    }
  }
  return map;
}

// The centre of cell (mx, my) of a text map, heading `yaw`.
inline Pose2 Cell(int mx, int my, double yaw = 0.0) {
  return {(mx + 0.5) * kRes, (my + 0.5) * kRes, yaw};
}

}  // namespace testing
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TEST_PLANNER_TEST_MAPS_H_
