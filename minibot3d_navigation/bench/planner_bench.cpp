// Google Benchmark for the global planners.
//
//  * A* on a synthetic 100 m x 100 m office (2000 x 2000 cells at 5 cm):
//    corridors, rows of rooms with 1 m doors, desks; walls inflated with
//    costmap_2d's formula (254 on the wall, 253 within the 0.15 m inscribed
//    radius, 252 * exp(-10 (d - 0.15)) out to 0.55 m).  One ~75 m query from
//    a room to a room on the far side; smoothed and raw; and an unreachable
//    goal (the whole reachable map is searched).  Nav2's NavFn needs ~146 ms
//    for a comparable plan; the target here is a median <= 50 ms.
//  * A* on the same-size empty map, a 75 m diagonal.
//  * A* vs OMPL (RRT* with a 1 s budget, RRT-Connect, PRM* 1 s) on a
//    10 m x 8 m apartment (200 x 160 cells).
// Counters: path_m (length of the returned path), raw_m (A* grid path),
// expanded (A* cells expanded), mean_cost (mean cell cost under the poses:
// A* trades length for clearance, OMPL minimises length only).  Run:
//   planner_bench --benchmark_counters_tabular=true
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_navigation/planner/astar_planner.h"
#include "minibot3d_navigation/planner/ompl_planner.h"
#include "minibot3d_navigation/planner/path_smoothing.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr double kRes = 0.05;

// Lethal mask -> costmap with costmap_2d's inflation (distances between cell
// centres, brute force over a disc around every wall-boundary cell).
Costmap2D Inflate(const std::vector<uint8_t>& lethal, int w, int h) {
  constexpr double kInscribed = 0.15, kInflation = 0.55, kScaling = 10.0;
  const int r = static_cast<int>(std::ceil(kInflation / kRes));
  std::vector<int> d2(static_cast<size_t>(w) * h, r * r + 1);
  auto is_lethal = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && lethal[y * w + x];
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!lethal[y * w + x]) continue;
      d2[y * w + x] = 0;
      const bool boundary = !is_lethal(x + 1, y) || !is_lethal(x - 1, y) ||
                            !is_lethal(x, y + 1) || !is_lethal(x, y - 1);
      if (!boundary) continue;
      for (int dy = -r; dy <= r; ++dy) {
        const int ny = y + dy;
        if (ny < 0 || ny >= h) continue;
        for (int dx = -r; dx <= r; ++dx) {
          const int nx = x + dx;
          if (nx < 0 || nx >= w) continue;
          int& v = d2[ny * w + nx];
          v = std::min(v, dx * dx + dy * dy);
        }
      }
    }
  }
  Costmap2D map(w, h, kRes, 0.0, 0.0);
  uint8_t* data = map.mutable_data();
  for (size_t i = 0; i < d2.size(); ++i) {
    const double d = std::sqrt(static_cast<double>(d2[i])) * kRes;
    if (d2[i] == 0) {
      data[i] = kLethalObstacle;
    } else if (d <= kInscribed) {
      data[i] = kInscribedInflatedObstacle;
    } else if (d <= kInflation) {
      data[i] = static_cast<uint8_t>(252.0 * std::exp(-kScaling * (d - kInscribed)));
    } else {
      data[i] = 0;
    }
  }
  return map;
}

class MaskBuilder {
 public:
  MaskBuilder(double width_m, double height_m)
      : w_(static_cast<int>(std::lround(width_m / kRes))),
        h_(static_cast<int>(std::lround(height_m / kRes))),
        mask_(static_cast<size_t>(w_) * h_, 0) {}
  // Fills [x0, x1) x [y0, y1) (metres) with `v`.
  void Box(double x0, double y0, double x1, double y1, uint8_t v = 1) {
    const int i0 = std::max(0, static_cast<int>(std::lround(x0 / kRes)));
    const int i1 = std::min(w_, static_cast<int>(std::lround(x1 / kRes)));
    const int j0 = std::max(0, static_cast<int>(std::lround(y0 / kRes)));
    const int j1 = std::min(h_, static_cast<int>(std::lround(y1 / kRes)));
    for (int j = j0; j < j1; ++j) {
      for (int i = i0; i < i1; ++i) mask_[j * w_ + i] = v;
    }
  }
  void Clear(double x0, double y0, double x1, double y1) { Box(x0, y0, x1, y1, 0); }
  Costmap2D Build() const { return Inflate(mask_, w_, h_); }

 private:
  int w_, h_;
  std::vector<uint8_t> mask_;
};

constexpr double kWall = 0.1;

// 100 m x 100 m office: horizontal corridors (2 m) at y = 24, 49, 74 and a
// vertical one at x = 49; between corridors two rows of 8 m rooms, each with
// a 1 m door to its corridor at a random place, some with a door to the next
// room, and two desks.
const Costmap2D& OfficeMap() {
  static const Costmap2D map = [] {
    MaskBuilder b(100.0, 100.0);
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    b.Box(0, 0, 100, kWall);
    b.Box(0, 100 - kWall, 100, 100);
    b.Box(0, 0, kWall, 100);
    b.Box(100 - kWall, 0, 100, 100);
    const double corridor_y[] = {24.0, 49.0, 74.0};
    // Band boundaries: [0,24], [26,49], [51,74], [76,100].
    const double band_lo[] = {0.0, 26.0, 51.0, 76.0};
    const double band_hi[] = {24.0, 49.0, 74.0, 100.0};
    for (double cy : corridor_y) {
      b.Box(0, cy - kWall, 100, cy);           // corridor's lower wall
      b.Box(0, cy + 2.0, 100, cy + 2.0 + kWall);  // upper wall
    }
    for (int band = 0; band < 4; ++band) {
      const double lo = band_lo[band], hi = band_hi[band];
      const double mid = 0.5 * (lo + hi);
      b.Box(0, mid - kWall / 2, 100, mid + kWall / 2);  // between room rows
      for (double x = 0.0; x < 100.0; x += 8.0) {
        // Rooms [x, x + 8) in the lower row [lo, mid) and upper row [mid, hi).
        if (x > 0) b.Box(x - kWall / 2, lo, x + kWall / 2, hi);
        for (int row = 0; row < 2; ++row) {
          const double y0 = row == 0 ? lo : mid, y1 = row == 0 ? mid : hi;
          // Door to the corridor: lower row opens downwards (band > 0),
          // upper row upwards (band < 3); edge rows open to the middle wall.
          const double dx = x + 1.0 + u(rng) * 5.5;
          if (row == 0 && band > 0) b.Clear(dx, lo - kWall, dx + 1.0, lo + kWall);
          if (row == 1 && band < 3) b.Clear(dx, hi - kWall, dx + 1.0, hi + kWall);
          if ((row == 0 && band == 0) || (row == 1 && band == 3)) {
            b.Clear(dx, mid - kWall, dx + 1.0, mid + kWall);
          }
          if (x + 8.0 < 100.0 && u(rng) < 0.3) {  // door to the next room
            const double dy = y0 + 1.0 + u(rng) * (y1 - y0 - 3.0);
            b.Clear(x + 8.0 - kWall, dy, x + 8.0 + kWall, dy + 1.0);
          }
          for (int k = 0; k < 2; ++k) {  // desks 1.6 x 0.8 m
            const double ex = x + 1.0 + u(rng) * 5.0;
            const double ey = y0 + 1.5 + u(rng) * (y1 - y0 - 3.5);
            b.Box(ex, ey, ex + 1.6, ey + 0.8);
          }
        }
      }
    }
    // Vertical corridor x in [49, 51] through everything (walls opened).
    b.Clear(49.0 - kWall, kWall, 51.0 + kWall, 100 - kWall);
    b.Box(49.0 - kWall, kWall, 49.0, 100 - kWall);
    b.Box(51.0, kWall, 51.0 + kWall, 100 - kWall);
    for (double cy : corridor_y) b.Clear(48.9, cy - 0.2, 51.2, cy + 2.2);
    return b.Build();
  }();
  return map;
}

const Costmap2D& EmptyMap() {
  static const Costmap2D map(2000, 2000, kRes, 0.0, 0.0);
  return map;
}

// 10 m x 8 m apartment: hallway, living room, kitchen, two bedrooms, bath.
const Costmap2D& ApartmentMap() {
  static const Costmap2D map = [] {
    MaskBuilder b(10.0, 8.0);
    b.Box(0, 0, 10, kWall);
    b.Box(0, 8 - kWall, 10, 8);
    b.Box(0, 0, kWall, 8);
    b.Box(10 - kWall, 0, 10, 8);
    b.Box(0, 4.0, 10, 4.1);    // hallway lower wall
    b.Box(0, 5.2, 10, 5.3);    // hallway upper wall
    b.Box(4.0, 0, 4.1, 4.0);   // living | kitchen
    b.Box(3.5, 5.3, 3.6, 8);   // bedroom 1 | bedroom 2
    b.Box(7.0, 5.3, 7.1, 8);   // bedroom 2 | bath
    b.Clear(1.5, 3.9, 2.4, 4.2);   // living room door
    b.Clear(6.0, 3.9, 6.9, 4.2);   // kitchen door
    b.Clear(1.0, 5.1, 1.9, 5.4);   // bedroom 1 door
    b.Clear(5.0, 5.1, 5.9, 5.4);   // bedroom 2 door
    b.Clear(8.0, 5.1, 8.9, 5.4);   // bath door
    b.Clear(4.0, 1.0, 4.1, 2.0);   // living <-> kitchen opening
    b.Box(0.5, 0.5, 2.5, 1.4);     // sofa
    b.Box(2.6, 2.2, 3.4, 3.0);     // table
    b.Box(8.5, 0.1, 9.9, 3.0);     // kitchen counter
    b.Box(5.5, 1.5, 6.7, 2.5);     // kitchen table
    b.Box(0.2, 6.2, 1.8, 7.9);     // bed 1
    b.Box(4.5, 6.5, 6.5, 7.9);     // bed 2
    b.Box(9.3, 5.4, 9.9, 6.5);     // bath tub
    return b.Build();
  }();
  return map;
}

// Room to room across the lower corridor: 75.9 m, ~131k cells expanded.
const Pose2 kOfficeStart{20.0, 5.0, 0.0};
const Pose2 kOfficeGoal{75.0, 30.0, 1.57};
// Corner room to a room two corridors up: 113 m with detours through doors,
// ~780k cells expanded (a harder query).
const Pose2 kOfficeFarStart{3.0, 5.0, 0.0};
const Pose2 kOfficeFarGoal{60.0, 40.0, 0.0};
const Pose2 kEmptyStart{5.0, 5.0, 0.0};
const Pose2 kEmptyGoal{65.0, 50.0, 0.0};      // 75 m diagonal
const Pose2 kApartmentStart{0.8, 2.5, 0.0};   // living room
const Pose2 kApartmentGoal{8.2, 6.8, 1.57};   // bathroom

// Mean cell cost under the path's poses: how close to obstacles it runs.
double MeanCost(const Costmap2D& map, const Path& path) {
  double sum = 0.0;
  for (const Pose2& p : path) {
    int mx = 0, my = 0;
    if (map.WorldToMap(p.x, p.y, &mx, &my)) sum += map.cost(mx, my);
  }
  return path.empty() ? 0.0 : sum / path.size();
}

void RunAStar(benchmark::State& state, const Costmap2D& map, const Pose2& start,
              const Pose2& goal, bool smooth) {
  GlobalPlannerOptions o;
  o.smooth_path = smooth;
  AStarPlanner planner(o);
  Path path;
  for (auto _ : state) {
    path = planner.MakePlan(map, start, goal);
    benchmark::DoNotOptimize(path.data());
  }
  state.counters["path_m"] = PathLength(path);
  state.counters["raw_m"] = PolylineLength(planner.last_raw_path());
  state.counters["expanded"] = planner.last_expansions();
  state.counters["mean_cost"] = MeanCost(map, path);
}

void BM_AStarOffice(benchmark::State& state) {
  RunAStar(state, OfficeMap(), kOfficeStart, kOfficeGoal, true);
}
void BM_AStarOfficeFar(benchmark::State& state) {
  RunAStar(state, OfficeMap(), kOfficeFarStart, kOfficeFarGoal, true);
}
void BM_AStarOfficeNoSmoothing(benchmark::State& state) {
  RunAStar(state, OfficeMap(), kOfficeStart, kOfficeGoal, false);
}
void BM_AStarEmpty(benchmark::State& state) {
  RunAStar(state, EmptyMap(), kEmptyStart, kEmptyGoal, true);
}
void BM_AStarApartment(benchmark::State& state) {
  RunAStar(state, ApartmentMap(), kApartmentStart, kApartmentGoal, true);
}

// Goal in a sealed box: the search visits every reachable cell.
void BM_AStarOfficeUnreachable(benchmark::State& state) {
  Costmap2D map = OfficeMap();
  for (int y = 1500; y < 1520; ++y) {
    for (int x = 1500; x < 1520; ++x) {
      const bool edge = x == 1500 || x == 1519 || y == 1500 || y == 1519;
      map.set_cost(x, y, edge ? kLethalObstacle : kFreeSpace);
    }
  }
  AStarPlanner planner({});
  for (auto _ : state) {
    try {
      planner.MakePlan(map, kOfficeStart, {75.5, 75.5, 0.0});
      state.SkipWithError("expected kNoPath");
    } catch (const PlanningError& e) {
      benchmark::DoNotOptimize(e.code());
    }
  }
  state.counters["expanded"] = planner.last_expansions();
}

void RunOmpl(benchmark::State& state, const std::string& algorithm) {
  GlobalPlannerOptions o;
  o.ompl_planner = algorithm;
  o.ompl_planning_time = 1.0;
  OmplPlanner planner(o, MakeCircleFootprint(0.15));
  double length = 0.0, cost = 0.0;
  int solved = 0, runs = 0;
  for (auto _ : state) {
    ++runs;
    try {
      const Path path = planner.MakePlan(ApartmentMap(), kApartmentStart, kApartmentGoal);
      length += PathLength(path);
      cost += MeanCost(ApartmentMap(), path);
      ++solved;
    } catch (const PlanningError&) {
    }
  }
  state.counters["path_m"] = solved ? length / solved : 0.0;
  state.counters["mean_cost"] = solved ? cost / solved : 0.0;
  state.counters["solved"] = static_cast<double>(solved) / std::max(1, runs);
}
void BM_OmplRrtStarApartment(benchmark::State& state) { RunOmpl(state, "rrtstar"); }
void BM_OmplPrmStarApartment(benchmark::State& state) { RunOmpl(state, "prmstar"); }
void BM_OmplRrtConnectApartment(benchmark::State& state) { RunOmpl(state, "rrtconnect"); }

BENCHMARK(BM_AStarOffice)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AStarOfficeFar)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AStarOfficeNoSmoothing)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AStarEmpty)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AStarOfficeUnreachable)->Unit(benchmark::kMillisecond)->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AStarApartment)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_OmplRrtStarApartment)->Unit(benchmark::kMillisecond)->Iterations(3)
    ->Repetitions(3)->ReportAggregatesOnly(true);
BENCHMARK(BM_OmplPrmStarApartment)->Unit(benchmark::kMillisecond)->Iterations(3)
    ->Repetitions(3)->ReportAggregatesOnly(true);
BENCHMARK(BM_OmplRrtConnectApartment)->Unit(benchmark::kMillisecond)->Repetitions(9)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation

BENCHMARK_MAIN();
