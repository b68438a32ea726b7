// Test and benchmark helper: bigger synthetic worlds than synthetic_world.h's Office — an office
// building of rooms along corridors, two identical rooms — and their occupancy grids.
#ifndef MINIBOT3D_TESTING_SYNTHETIC_BUILDING_H_
#define MINIBOT3D_TESTING_SYNTHETIC_BUILDING_H_

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "minibot3d_testing/synthetic_world.h"

namespace minibot3d_testing {

// Walls are shifted off the cell boundaries of a 5 cm grid, as in Office().
constexpr double kWallShiftX = 0.0137, kWallShiftY = -0.0213;

// Moves every wall by (kWallShiftX, kWallShiftY).
inline void ShiftWalls(World* w) {
  for (Segment& s : w->walls) {
    s.x0 += kWallShiftX;
    s.x1 += kWallShiftX;
    s.y0 += kWallShiftY;
    s.y1 += kWallShiftY;
  }
}

// A trinary grid of `world`: cells a wall passes through are occupied (100), the rest of
// [x0, x1] × [y0, y1] free (0), a `margin` of unknown (-1) around it.
inline GridMap Rasterize(const World& world, double x0, double y0, double x1, double y1,
                         double resolution = 0.05, double margin = 1.0) {
  GridMap map;
  map.resolution = resolution;
  map.origin_x = x0 - margin;
  map.origin_y = y0 - margin;
  map.width = static_cast<int>(std::ceil((x1 - x0 + 2 * margin) / resolution));
  map.height = static_cast<int>(std::ceil((y1 - y0 + 2 * margin) / resolution));
  map.data.assign(static_cast<std::size_t>(map.width) * map.height, -1);
  auto cell = [&](double x, double y) -> std::int8_t* {
    const int cx = static_cast<int>(std::floor((x - map.origin_x) / resolution));
    const int cy = static_cast<int>(std::floor((y - map.origin_y) / resolution));
    if (cx < 0 || cy < 0 || cx >= map.width || cy >= map.height) return nullptr;
    return &map.data[static_cast<std::size_t>(cy) * map.width + cx];
  };
  for (int cy = 0; cy < map.height; ++cy) {
    for (int cx = 0; cx < map.width; ++cx) {
      const double x = map.origin_x + (cx + 0.5) * resolution;
      const double y = map.origin_y + (cy + 0.5) * resolution;
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) map.data[cy * map.width + cx] = 0;
    }
  }
  for (const Segment& s : world.walls) {
    const double len = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
    const int n = std::max(1, static_cast<int>(std::ceil(len / (resolution / 8))));
    for (int k = 0; k <= n; ++k) {
      const double t = static_cast<double>(k) / n;
      if (std::int8_t* c = cell(s.x0 + t * (s.x1 - s.x0), s.y0 + t * (s.y1 - s.y0))) *c = 100;
    }
  }
  return map;
}

// An office floor of width × height metres: three corridors (2 m wide) along x, rooms of random
// widths (3–7 m) between them, each with a 1 m door onto a corridor and, mostly, a piece of
// furniture; seeded, so no two rooms look alike. `room_centres` gets a free spot in each room.
inline World OfficeBuilding(double width, double height, unsigned seed,
                            std::vector<Pose2>* room_centres = nullptr) {
  std::mt19937 rng(seed);
  auto uniform = [&](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  World w;
  w.AddBox(0.0, 0.0, width, height);
  const double corridor = 2.0;
  // Bands of rooms between corridors: [0, c1), (c1 + 2, c2), ... with the corridors evenly spaced.
  std::vector<double> band_edges{0.0};
  const int corridors = 3;
  for (int k = 1; k <= corridors; ++k) {
    const double centre = height * k / (corridors + 1);
    band_edges.push_back(centre - corridor / 2);
    band_edges.push_back(centre + corridor / 2);
  }
  band_edges.push_back(height);
  for (std::size_t b = 0; b + 1 < band_edges.size(); b += 2) {
    const double ya = band_edges[b], yb = band_edges[b + 1];
    const bool corridor_below = b > 0, corridor_above = b + 2 < band_edges.size();
    double x = 0.0;
    while (x < width - 1e-9) {
      double room = uniform(3.0, 7.0);
      if (width - (x + room) < 3.0) room = width - x;
      const double xa = x, xb = x + room;
      if (xb < width - 1e-9) w.walls.push_back({xb, ya, xb, yb});
      // Corridor-side walls, with a door in one of them.
      const bool door_above = corridor_above && (!corridor_below || uniform(0, 1) < 0.5);
      for (int side = 0; side < 2; ++side) {
        const bool above = side == 1;
        if (above ? !corridor_above : !corridor_below) continue;
        const double y = above ? yb : ya;
        if (above == door_above) {
          const double d = uniform(xa + 0.3, xb - 1.3);
          w.walls.push_back({xa, y, d, y});
          w.walls.push_back({d + 1.0, y, xb, y});
        } else {
          w.walls.push_back({xa, y, xb, y});
        }
      }
      // A spot clear of the walls and of the furniture (kept 0.3 m away from it).
      Pose2 spot{xa + 0.25 * room + 0.2, ya + 0.3 * (yb - ya), 0.0};
      if (uniform(0, 1) < 0.8) {
        const double fw = uniform(0.4, 1.2), fh = uniform(0.4, 1.2);
        const double fx = uniform(xa + 0.5, xb - 0.5 - fw), fy = uniform(ya + 0.5, yb - 0.5 - fh);
        w.AddBox(fx, fy, fx + fw, fy + fh);
        if (spot.x > fx - 0.3 && spot.x < fx + fw + 0.3 && spot.y > fy - 0.3 &&
            spot.y < fy + fh + 0.3) {
          spot = Pose2{xa + 0.75 * room - 0.2, ya + 0.75 * (yb - ya), 0.0};
          if (spot.x > fx - 0.3 && spot.x < fx + fw + 0.3 && spot.y > fy - 0.3 &&
              spot.y < fy + fh + 0.3) {
            spot.x = fx - 0.35;
          }
        }
      }
      if (room_centres) room_centres->push_back(spot);
      x = xb;
    }
  }
  ShiftWalls(&w);
  return w;
}

// Two identical closed rooms, 6 m × 4 m, the second `shift` metres along x from the first
// ([0, 6] × [0, 4]); each holds a table and a cupboard so that a room has only one way to look.
inline World TwinRooms(double shift = 10.0) {
  World w;
  for (int k = 0; k < 2; ++k) {
    const double dx = k * shift;
    w.AddBox(dx + 0.0, 0.0, dx + 6.0, 4.0);
    w.AddBox(dx + 1.0, 2.8, dx + 2.2, 3.4);   // cupboard
    w.AddBox(dx + 4.1, 0.7, dx + 4.9, 1.3);   // table
    w.walls.push_back({dx + 6.0, 2.0, dx + 5.0, 2.0});  // wall stub
  }
  ShiftWalls(&w);
  return w;
}

// A full-circle scan of n beams (the last beam one step short of the first).
inline LaserScan FullScan(const World& world, const Pose2& pose, int n = 360,
                          double range_max = 30.0) {
  return world.Scan(pose, n, 2.0 * M_PI * (n - 1) / n, range_max);
}

}  // namespace minibot3d_testing

#endif  // MINIBOT3D_TESTING_SYNTHETIC_BUILDING_H_
