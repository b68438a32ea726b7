// Google Benchmark for the layered costmap (Lu, Hershberger & Smart, IROS
// 2014; inflation as costmap_2d's InflationLayer):
//   BM_InflateFull/<cm>      the inflation layer alone over a whole
//                            2000 x 2000 office-like map (100 m x 100 m at
//                            5 cm: rooms, 15 cm walls with doors, furniture),
//                            inflation_radius <cm> / 100 m, inscribed 0.2 m;
//                            the copy of the un-inflated map is not timed.
//   BM_GlobalFullRebuild     a full global update of the same map after
//                            clear_costmaps: static copy + obstacle layer +
//                            inflation (what a new map or a reset costs).
//   BM_RollingUpdate         one local-costmap cycle: 6 m x 6 m rolling window
//                            at 5 cm, a 720-beam scan (10 m range) converted,
//                            ray-traced and marked, window moved, inflated;
//                            the robot drives 5 cm per cycle through the map.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_navigation/costmap/layered_costmap.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr int kMapCells = 2000;
constexpr double kRes = 0.05;

// 100 m x 100 m: 5 m x 5 m rooms, 3-cell walls with 1 m doors, and a few
// random boxes (desks, cabinets) per room.
const OccupancyGrid& OfficeMap() {
  static const OccupancyGrid grid = [] {
    OccupancyGrid g;
    g.width = g.height = kMapCells;
    g.resolution = kRes;
    g.data.assign(static_cast<size_t>(kMapCells) * kMapCells, 0);
    auto set = [&g](int i, int j) {
      if (i >= 0 && j >= 0 && i < kMapCells && j < kMapCells) {
        g.data[static_cast<size_t>(j) * kMapCells + i] = 100;
      }
    };
    const int room = 100, wall = 3, door = 20;
    for (int k = 0; k <= kMapCells; k += room) {
      for (int t = 0; t < kMapCells; ++t) {
        const int in_room = t % room;
        if (in_room >= 40 && in_room < 40 + door && k > 0 && k < kMapCells) continue;
        for (int w = 0; w < wall; ++w) {
          set(k - 1 + w, t);  // vertical wall
          set(t, k - 1 + w);  // horizontal wall
        }
      }
    }
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> pos(8, room - 30), size(4, 24);
    for (int ry = 0; ry < kMapCells; ry += room) {
      for (int rx = 0; rx < kMapCells; rx += room) {
        for (int b = 0; b < 3; ++b) {
          const int x0 = rx + pos(rng), y0 = ry + pos(rng), w = size(rng), h = size(rng);
          for (int j = y0; j < y0 + h; ++j) {
            for (int i = x0; i < x0 + w; ++i) set(i, j);
          }
        }
      }
    }
    return g;
  }();
  return grid;
}

CostmapOptions BenchOptions() {
  CostmapOptions o;
  o.robot_radius = 0.2;
  o.footprint_padding = 0.0;
  return o;
}

void BM_InflateFull(benchmark::State& state) {
  const double radius = state.range(0) / 100.0;
  StaticLayer map_layer(BenchOptions());
  map_layer.SetMap(OfficeMap());
  const Costmap2D& source = map_layer.map();
  Costmap2D master = source;
  InflationLayer inflation(radius, 10.0);
  inflation.MatchSize(master);
  inflation.OnFootprintChanged(MakeCircleFootprint(0.2), 0.2, 0.2);
  size_t lethal = 0;
  for (uint8_t v : source.cells()) lethal += v == kLethalObstacle;
  for (auto _ : state) {
    state.PauseTiming();
    std::memcpy(master.mutable_data(), source.data(), source.cells().size());
    state.ResumeTiming();
    inflation.UpdateCosts(CellBounds::Whole(master), &master);
    benchmark::DoNotOptimize(master.mutable_data());
  }
  state.counters["cells"] = static_cast<double>(source.cells().size());
  state.counters["lethal_cells"] = static_cast<double>(lethal);
}
BENCHMARK(BM_InflateFull)->Arg(55)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_GlobalFullRebuild(benchmark::State& state) {
  LayeredCostmap costmap = BuildLayeredCostmap(BenchOptions());
  costmap.SetStaticMap(OfficeMap());
  const Pose2 robot{12.5, 12.5, 0.0};
  costmap.UpdateMap(robot);
  for (auto _ : state) {
    costmap.ResetLayers();
    costmap.UpdateMap(robot);
    benchmark::DoNotOptimize(costmap.costmap().data());
  }
}
BENCHMARK(BM_GlobalFullRebuild)->Unit(benchmark::kMillisecond);

// Range along a ray in the office map until a lethal cell (0.25-cell steps).
double CastRay(const Costmap2D& map, double x, double y, double angle, double max_range) {
  const double step = 0.25 * kRes, c = std::cos(angle), s = std::sin(angle);
  for (double r = 0.0; r < max_range; r += step) {
    int mx, my;
    if (!map.WorldToMap(x + r * c, y + r * s, &mx, &my)) return r;
    if (map.cost(mx, my) == kLethalObstacle) return r;
  }
  return std::numeric_limits<double>::infinity();  // no return within range
}

void BM_RollingUpdate(benchmark::State& state) {
  StaticLayer world(BenchOptions());
  world.SetMap(OfficeMap());
  // A path through three rooms (doors at 2.0..3.0 m of each 5 m wall).
  std::vector<Pose2> poses;
  for (double x = 12.0; x < 26.0; x += 0.05) poses.push_back({x, 12.0 + 0.5, 0.0});
  LaserScan scan_template;
  scan_template.range_min = 0.05;
  scan_template.range_max = 10.0;
  scan_template.angles = MakeBeamAngles(-kPi, 2 * kPi / 720, 720);
  std::vector<LaserScan> scans;
  for (const Pose2& p : poses) {
    LaserScan scan = scan_template;
    for (double a : scan.angles) {
      scan.ranges.push_back(static_cast<float>(CastRay(world.map(), p.x, p.y, p.yaw + a, 10.0)));
    }
    scans.push_back(scan);
  }

  CostmapOptions o = BenchOptions();
  o.rolling_window = true;
  o.static_map = false;
  o.width = 6.0;
  o.height = 6.0;
  o.inf_is_valid = true;
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  size_t k = 0;
  for (auto _ : state) {
    const Pose2& p = poses[k];
    costmap.obstacle_layer()->AddObservation(
        ObservationFromScan(scans[k], p, o.obstacle_range, o.raytrace_range, o.inf_is_valid));
    costmap.UpdateMap(p);
    benchmark::DoNotOptimize(costmap.costmap().data());
    k = (k + 1) % poses.size();
  }
  state.counters["cells"] = static_cast<double>(costmap.costmap().cells().size());
}
BENCHMARK(BM_RollingUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation

BENCHMARK_MAIN();
