// Google Benchmark for the AMCL core: time per filter update (prediction +
// 60-beam correction + resampling every resample_interval = 2 updates +
// clustering) for 500 / 2,000 / 10,000 particles on a 10 m x 8 m map with
// 5 cm cells; the three sensor models alone; the per-map precomputation; and
// the memory the filter holds per particle (counter "bytes_per_particle");
// global localization's map-wide search (GlobalSearch, minibot3d_scan_matching's
// correlative search) on a synthetic 54 m x 59 m office floor and on the
// shipped office world's map (maps/office.yaml, 2,775 m^2 free; the
// environment variable OFFICE_MAP overrides its path).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_map_io/map_io.h"
#include "minibot3d_navigation/amcl/amcl_filter.h"
#include "minibot3d_navigation/amcl/global_search.h"
#include "minibot3d_testing/synthetic_building.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

// 10 m x 8 m room with a partition, a box and a pillar (grid frame metres).
OccupancyGrid BenchRoom(double width_m = 10.0, double height_m = 8.0,
                        double res = 0.05) {
  OccupancyGrid g;
  g.resolution = res;
  g.width = static_cast<int>(std::lround(width_m / res));
  g.height = static_cast<int>(std::lround(height_m / res));
  g.data.assign(static_cast<size_t>(g.width) * g.height, 0);
  auto box = [&g, res](double x0, double y0, double x1, double y1) {
    for (int j = 0; j < g.height; ++j) {
      for (int i = 0; i < g.width; ++i) {
        const double cx = (i + 0.5) * res, cy = (j + 0.5) * res;
        if (cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1) {
          g.data[static_cast<size_t>(j) * g.width + i] = 100;
        }
      }
    }
  };
  box(0, 0, width_m, res);
  box(0, height_m - res, width_m, height_m);
  box(0, 0, res, height_m);
  box(width_m - res, 0, width_m, height_m);
  box(6.0, 0.0, 6.15, 3.0);
  box(1.5, 5.5, 2.7, 6.3);
  box(4.0, 3.8, 4.3, 4.1);
  return g;
}

// A 360-beam scan (the filter keeps laser_max_beams of it) ray-cast in the
// map from `robot`.
LaserScan BenchScan(const MapModel& map, const Pose2& robot) {
  LaserScan scan;
  scan.range_min = 0.15;
  scan.range_max = 12.0;
  scan.angles = MakeBeamAngles(-kPi, 2 * kPi / 360, 360);
  for (double a : scan.angles) {
    scan.ranges.push_back(static_cast<float>(
        map.CalcRange({robot.x, robot.y, robot.yaw + a}, scan.range_max)));
  }
  return scan;
}

AmclOptions BenchOptions(int particles, const std::string& model) {
  AmclOptions o;
  o.min_particles = o.max_particles = particles;  // fixed set size
  o.laser_max_beams = 60;
  o.laser_model_type = model;
  o.initial_pose_x = 3.0;
  o.initial_pose_y = 2.0;
  o.initial_pose_a = 0.4;
  return o;
}

// One Update() per iteration; odometry alternates between two poses 0.25 m
// apart (> update_min_d), so every call predicts and corrects.
void BM_FilterUpdate(benchmark::State& state, const std::string& model) {
  const int n = static_cast<int>(state.range(0));
  const AmclOptions o = BenchOptions(n, model);
  auto map =
      std::make_shared<MapModel>(BenchRoom(), o.laser_likelihood_max_dist);
  AmclFilter filter(o, map);
  const Pose2 a{3.0, 2.0, 0.4};
  const Pose2 b = Compose(a, {0.25, 0.0, 0.0});
  const LaserScan scan_a = BenchScan(*map, a), scan_b = BenchScan(*map, b);
  filter.Update(a, scan_a);
  bool at_a = true;
  for (auto _ : state) {
    at_a = !at_a;
    const UpdateResult r =
        at_a ? filter.Update(a, scan_a) : filter.Update(b, scan_b);
    benchmark::DoNotOptimize(r);
  }
  state.counters["particles"] = static_cast<double>(filter.particles().size());
  state.counters["bytes_per_particle"] =
      static_cast<double>(filter.ParticleMemoryBytes()) /
      filter.particles().size();
  state.counters["map_kib"] = filter.MapMemoryBytes() / 1024.0;
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK_CAPTURE(BM_FilterUpdate, likelihood_field,
                  std::string("likelihood_field"))
    ->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FilterUpdate, likelihood_field_prob,
                  std::string("likelihood_field_prob"))
    ->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FilterUpdate, beam, std::string("beam"))
    ->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kMillisecond);

// The correction step alone (60 beams).
void BM_SensorModel(benchmark::State& state, const std::string& model) {
  const int n = static_cast<int>(state.range(0));
  const AmclOptions o = BenchOptions(n, model);
  auto map =
      std::make_shared<MapModel>(BenchRoom(), o.laser_likelihood_max_dist);
  auto sensor = CreateSensorModel(o, map);
  const Pose2 truth{3.0, 2.0, 0.4};
  PreparedScan scan;
  std::string error;
  if (!PrepareScan(BenchScan(*map, truth), o, &scan, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<Particle> particles(n);
  for (Particle& p : particles) {
    p.pose = {truth.x + noise(rng), truth.y + noise(rng),
              truth.yaw + noise(rng)};
    p.weight = 1.0 / n;
  }
  std::vector<double> ll;
  for (auto _ : state) {
    sensor->ComputeLogLikelihoods(scan, particles, false, &ll);
    benchmark::DoNotOptimize(ll.data());
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK_CAPTURE(BM_SensorModel, likelihood_field,
                  std::string("likelihood_field"))
    ->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SensorModel, beam, std::string("beam"))
    ->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kMillisecond);

// Per-map precomputation (distance transform, free list) for the bench room
// and a 100 m x 100 m map at 5 cm (4 M cells).
void BM_MapPrecompute(benchmark::State& state) {
  const double side = static_cast<double>(state.range(0));
  const OccupancyGrid grid =
      side <= 10.0 ? BenchRoom() : BenchRoom(side, side, 0.05);
  for (auto _ : state) {
    MapModel map(grid, 2.0);
    benchmark::DoNotOptimize(map.Distance(1, 1));
  }
  state.counters["cells"] = static_cast<double>(grid.data.size());
}
BENCHMARK(BM_MapPrecompute)->Arg(10)->Arg(100)->Unit(benchmark::kMillisecond);

// One map-wide search (global_localization) with the shipped options (6
// candidates, 12 m range, 360 beams) on a 54 m x 59 m office floor (3,186 m^2
// at 0.05 m, 1.27 M cells), the scan taken in one of its rooms (a new room each
// iteration).  Counters: the constructor's predicted seconds and how often the
// best candidate was within 0.3 m of the truth.  The budget is raised so the
// search is built whatever the prediction says.
void BM_GlobalSearchOffice(benchmark::State& state) {
  namespace tw = minibot3d_testing;
  std::vector<Pose2> rooms;
  const tw::World world = tw::OfficeBuilding(54.0, 59.0, 1, &rooms);
  const OccupancyGrid grid = tw::Rasterize(world, 0.0, 0.0, 54.0, 59.0);
  AmclOptions o;
  o.laser_max_range = 12.0;
  o.global_search_budget = 100.0;
  const GlobalSearch search(grid, o);
  size_t k = 0;
  int right = 0, runs = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const Pose2 truth = rooms[(k++ * 7) % rooms.size()];
    const LaserScan s = tw::FullScan(world, truth, 360, 12.0);
    LaserScan scan;
    scan.range_min = s.range_min;
    scan.range_max = s.range_max;
    scan.angles = s.angles;
    scan.ranges.assign(s.ranges.begin(), s.ranges.end());
    scan.sensor_in_base = {s.sensor_in_base.x, s.sensor_in_base.y, s.sensor_in_base.yaw};
    state.ResumeTiming();
    const std::vector<SearchCandidate> c = search.Search(scan);
    ++runs;
    if (!c.empty() && std::hypot(c[0].pose.x - truth.x, c[0].pose.y - truth.y) < 0.3) ++right;
  }
  state.counters["predicted_s"] = search.predicted_seconds();
  state.counters["best_right"] = static_cast<double>(right) / std::max(1, runs);
}
BENCHMARK(BM_GlobalSearchOffice)->Iterations(5)->Unit(benchmark::kMillisecond);

// A 360-beam, 12 m scan cast on `grid` from `pose` (cells >= 65 % occupied stop
// a beam; quarter-cell steps), as the simulator's lidar would see the world
// the map was rendered from.
LaserScan CastScan(const OccupancyGrid& grid, const Pose2& pose) {
  LaserScan scan;
  scan.range_min = 0.15;
  scan.range_max = 12.0;
  const int beams = 360;
  for (int b = 0; b < beams; ++b) {
    const double a = -M_PI + 2.0 * M_PI * b / beams;
    const double c = std::cos(pose.yaw + a), s = std::sin(pose.yaw + a);
    const double step = grid.resolution / 4.0;
    double r = 0.0, hit = std::numeric_limits<double>::infinity();
    for (; r < scan.range_max; r += step) {
      const int i = static_cast<int>(std::floor((pose.x + r * c - grid.origin_x) / grid.resolution));
      const int j = static_cast<int>(std::floor((pose.y + r * s - grid.origin_y) / grid.resolution));
      if (i < 0 || j < 0 || i >= grid.width || j >= grid.height) break;
      if (grid.data[static_cast<size_t>(j) * grid.width + i] >= 65) {
        hit = r;
        break;
      }
    }
    scan.angles.push_back(a);
    scan.ranges.push_back(hit);
  }
  return scan;
}

// One map-wide search with the shipped options on the shipped office world's
// map, the scan cast from a new seeded random pose each iteration (a free cell
// >= 0.3 m from anything occupied or unknown).  Counters: the slowest and the
// median CPU time of a search (the budget is global_search_budget = 1 s), and
// how often the best candidate was within 0.3 m / 10 deg of the truth.  Args:
// global_search_angular_step (in 1e-4 rad; 0 derives it from the farthest
// return) and global_search_max_beams.
void BM_GlobalSearchShippedOffice(benchmark::State& state) {
  const char* env = std::getenv("OFFICE_MAP");
  const std::string path = env != nullptr ? env : MINIBOT3D_OFFICE_MAP;
  OccupancyGrid grid;
  try {
    grid = minibot3d_map_io::LoadMap(path);
  } catch (const std::exception& e) {
    state.SkipWithError(("cannot load the office map (OFFICE_MAP): " + std::string(e.what())).c_str());
    return;
  }
  AmclOptions o;
  o.laser_max_range = 12.0;
  o.global_search_angular_step = state.range(0) * 1e-4;  // arg 0: step in 0.1 mrad
  o.global_search_max_beams = static_cast<int>(state.range(1));
  const GlobalSearch search(grid, o);
  if (!search.available()) {
    state.SkipWithError("the office map is over global_search_budget");
    return;
  }
  // Free poses with clearance: a cell whose 13 x 13 neighbourhood is all free.
  std::vector<std::pair<int, int>> cells;
  const int c = static_cast<int>(std::ceil(0.3 / grid.resolution));
  for (int j = c; j < grid.height - c; j += 3) {
    for (int i = c; i < grid.width - c; i += 3) {
      bool ok = true;
      for (int dj = -c; ok && dj <= c; ++dj)
        for (int di = -c; ok && di <= c; ++di)
          ok = grid.data[static_cast<size_t>(j + dj) * grid.width + i + di] == 0;
      if (ok) cells.emplace_back(i, j);
    }
  }
  std::mt19937 rng(1);
  std::vector<double> cpu;
  int right = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const auto& cell = cells[std::uniform_int_distribution<size_t>(0, cells.size() - 1)(rng)];
    const Pose2 truth{grid.origin_x + (cell.first + 0.5) * grid.resolution,
                       grid.origin_y + (cell.second + 0.5) * grid.resolution,
                       std::uniform_real_distribution<double>(-M_PI, M_PI)(rng)};
    const LaserScan scan = CastScan(grid, truth);
    state.ResumeTiming();
    double wall = 0.0, cpu_s = 0.0;
    const std::vector<SearchCandidate> found = search.Search(scan, &wall, &cpu_s);
    cpu.push_back(cpu_s);
    if (!found.empty() &&
        std::hypot(found[0].pose.x - truth.x, found[0].pose.y - truth.y) < 0.3 &&
        std::abs(std::remainder(found[0].pose.yaw - truth.yaw, 2.0 * M_PI)) < 0.175) {
      ++right;
    }
  }
  std::sort(cpu.begin(), cpu.end());
  state.counters["cells"] = static_cast<double>(grid.data.size());
  state.counters["median_cpu_s"] = cpu.empty() ? 0.0 : cpu[cpu.size() / 2];
  state.counters["max_cpu_s"] = cpu.empty() ? 0.0 : cpu.back();
  state.counters["best_right"] = static_cast<double>(right) / std::max<size_t>(1, cpu.size());
}
BENCHMARK(BM_GlobalSearchShippedOffice)
    ->ArgNames({"step_1e-4rad", "beams"})
    ->Args({0, 180})
    ->Args({85, 180})
    ->Args({85, 120})
    ->Args({120, 180})
    ->Args({120, 120})
    ->Iterations(30)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace amcl
}  // namespace minibot3d_navigation

BENCHMARK_MAIN();
