// correlative_search_bench: time of a whole-map, full-rotation CorrelativeSearch (global
// localization) for a 360-beam scan, on map_server maps and on synthetic office floors.
//
//   correlative_search_bench [MAP_YAML ...] [--runs N] [--depth D] [--range M] [--step RAD]
//                            [--blur M] [--no-synthetic] [--verbose]
//
// For every map: build the max-grid stack once (timed), then for N scans taken at random free
// poses (seeded) search from a random initial pose with linear_search_window = kWholeMap and
// angular_search_window = π, and print the median and worst Search and SearchAll (5 candidates)
// times, how many scans were found within a cell and an angular step, and the work done.
// Scans on a YAML map are ray-cast in its grid (an occupied cell ends a beam); on the synthetic
// floors (50 m × 50 m and 54 m × 59 m, OfficeBuilding in minibot3d_testing/synthetic_building.h) in the walls.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "minibot3d_map_io/map_io.h"
#include "minibot3d_scan_matching/correlative_search.h"
#include "minibot3d_testing/synthetic_building.h"

using minibot3d_scan_matching::CorrelativeSearch;
using minibot3d_scan_matching::CorrelativeSearchOptions;
using minibot3d_scan_matching::GridMap;
using minibot3d_common::LaserScan;
using minibot3d_common::Pose2;

namespace {

struct Settings {
  int runs = 11;
  int depth = 7;
  double range = 30.0;
  double step = 0.0;
  double blur = 0.05;
  bool verbose = false;
};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// CPU time of this thread: the machine is shared, and wall time counts the others' work too.
double CpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int Cell(const GridMap& map, double x, double y) {
  const int cx = static_cast<int>(std::floor((x - map.origin_x) / map.resolution));
  const int cy = static_cast<int>(std::floor((y - map.origin_y) / map.resolution));
  if (cx < 0 || cy < 0 || cx >= map.width || cy >= map.height) return -2;
  return map.data[static_cast<std::size_t>(cy) * map.width + cx];
}

// A free cell with nothing but free cells within `clearance` (an axis-aligned check).
bool Clear(const GridMap& map, double x, double y, double clearance) {
  for (double dy = -clearance; dy <= clearance; dy += map.resolution) {
    for (double dx = -clearance; dx <= clearance; dx += map.resolution) {
      if (Cell(map, x + dx, y + dy) != 0) return false;
    }
  }
  return true;
}

// 360 beams cast through the grid (maps with origin_theta = 0): a cell >= 65 ends a beam.
LaserScan GridScan(const GridMap& map, const Pose2& pose, double range_max) {
  LaserScan scan;
  scan.range_min = 0.05;
  scan.range_max = range_max;
  for (int i = 0; i < 360; ++i) {
    const double a = -M_PI + 2.0 * M_PI * i / 360;
    const double c = std::cos(pose.yaw + a), s = std::sin(pose.yaw + a);
    double r = INFINITY;
    for (double t = 0.0; t < range_max; t += map.resolution / 4) {
      const int v = Cell(map, pose.x + t * c, pose.y + t * s);
      if (v == -2) break;
      if (v >= 65) {
        r = t;
        break;
      }
    }
    scan.angles.push_back(a);
    scan.ranges.push_back(r);
  }
  return scan;
}

void Run(const std::string& name, const GridMap& map,
         const std::function<LaserScan(const Pose2&)>& scan_at, const Settings& settings) {
  CorrelativeSearchOptions options;
  options.linear_search_window = CorrelativeSearchOptions::kWholeMap;
  options.angular_search_window = M_PI;
  options.branch_and_bound_depth = settings.depth;
  options.angular_step = settings.step;
  options.blur_sigma = settings.blur;
  const auto t0 = std::chrono::steady_clock::now();
  const CorrelativeSearch search(map, options);
  const double build = Seconds(t0);

  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(map.origin_x,
                                            map.origin_x + map.width * map.resolution);
  std::uniform_real_distribution<double> uy(map.origin_y,
                                            map.origin_y + map.height * map.resolution);
  std::uniform_real_distribution<double> ua(-M_PI, M_PI);
  std::vector<double> times, cpu, times_all, cpu_all, scores, second;
  int found = 0, right_place = 0;
  CorrelativeSearch::Stats stats_sum;
  for (int run = 0; run < settings.runs; ++run) {
    // A free pose that sees more than 2 m (not inside a piece of furniture).
    Pose2 truth;
    std::vector<Eigen::Vector2d> points;
    double d = 0.0;
    do {
      truth = Pose2{ux(rng), uy(rng), ua(rng)};
      if (!Clear(map, truth.x, truth.y, 0.3)) continue;
      points = minibot3d_scan_matching::ScanToPoints(scan_at(truth));
      d = 0.0;
      for (const auto& p : points) d = std::max(d, p.norm());
    } while (d < 2.0);
    const Pose2 initial{ux(rng), uy(rng), ua(rng)};
    const double step = settings.step > 0.0 ? settings.step
                                            : std::acos(1.0 - map.resolution * map.resolution /
                                                                  (2.0 * d * d));
    auto t = std::chrono::steady_clock::now();
    double c = CpuSeconds();
    const auto best = search.Search(points, initial, options);
    times.push_back(Seconds(t));
    cpu.push_back(CpuSeconds() - c);
    const auto stats = CorrelativeSearch::LastStats();
    stats_sum.angles += stats.angles;
    stats_sum.top_nodes += stats.top_nodes;
    stats_sum.nodes_scored += stats.nodes_scored;
    stats_sum.leaves += stats.leaves;
    stats_sum.lookups += stats.lookups;
    stats_sum.top_lookups += stats.top_lookups;
    t = std::chrono::steady_clock::now();
    c = CpuSeconds();
    const auto all = search.SearchAll(points, initial, options);
    times_all.push_back(Seconds(t));
    cpu_all.push_back(CpuSeconds() - c);
    if (best) {
      scores.push_back(best->score);
      if (std::hypot(best->pose.x - truth.x, best->pose.y - truth.y) <= 0.3 &&
          std::fabs(minibot3d_common::NormalizeAngle(best->pose.yaw - truth.yaw)) <= 0.05) {
        ++right_place;
      }
      if (std::fabs(best->pose.x - truth.x) <= map.resolution &&
          std::fabs(best->pose.y - truth.y) <= map.resolution &&
          std::fabs(minibot3d_common::NormalizeAngle(best->pose.yaw - truth.yaw)) <= step) {
        ++found;
      } else if (settings.verbose) {
        CorrelativeSearchOptions local = options;
        local.linear_search_window = 0.1;
        local.angular_search_window = 0.01;
        local.min_score = 0.0;
        const auto near = search.Search(points, truth, local);
        std::printf("  missed: truth (%.3f, %.3f, %.3f) score %.3f, best near it %.3f; found "
                    "(%.3f, %.3f, %.3f) score %.3f; step %.4f\n",
                    truth.x, truth.y, truth.yaw, search.Score(points, truth), near->score,
                    best->pose.x, best->pose.y, best->pose.yaw, best->score, step);
      }
    }
    second.push_back(all.size() > 1 ? all[1].score : 0.0);
  }
  const double n = settings.runs;
  std::printf("%s: %d x %d cells (%.0f m2) at %.3f m, depth %d, blur %.3f m; grids built in "
              "%.3f s\n",
              name.c_str(), map.width, map.height,
              map.width * map.height * map.resolution * map.resolution, map.resolution,
              settings.depth, settings.blur, build);
  std::printf("  Search    median %.3f s CPU (wall %.3f s), max %.3f s CPU over %d scans; found "
              "within a cell and a step %d/%d, at the right place (0.3 m, 0.05 rad) %d/%d; median "
              "score %.3f\n",
              Median(cpu), Median(times), *std::max_element(cpu.begin(), cpu.end()), settings.runs,
              found, settings.runs, right_place, settings.runs,
              scores.empty() ? 0.0 : Median(scores));
  std::printf("  SearchAll median %.3f s CPU (wall %.3f s), max %.3f s CPU (5 candidates; median "
              "runner-up score %.3f)\n",
              Median(cpu_all), Median(times_all), *std::max_element(cpu_all.begin(), cpu_all.end()),
              Median(second));
  std::printf("  per search: %.0f angles, %.0f top nodes, %.0f nodes scored, %.0f leaves, %.1fM "
              "endpoint lookups (%.1fM for the top nodes)\n",
              stats_sum.angles / n, stats_sum.top_nodes / n, stats_sum.nodes_scored / n,
              stats_sum.leaves / n, stats_sum.lookups / n / 1e6, stats_sum.top_lookups / n / 1e6);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  std::vector<std::string> yamls;
  bool synthetic = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> double {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "correlative_search_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return std::atof(argv[++i]);
    };
    if (a == "--runs") settings.runs = std::max(1, static_cast<int>(value()));
    else if (a == "--depth") settings.depth = static_cast<int>(value());
    else if (a == "--range") settings.range = value();
    else if (a == "--step") settings.step = value();
    else if (a == "--blur") settings.blur = value();
    else if (a == "--no-synthetic") synthetic = false;
    else if (a == "--verbose") settings.verbose = true;
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "correlative_search_bench: unknown option %s\n", a.c_str());
      return 2;
    } else {
      yamls.push_back(a);
    }
  }
  try {
    for (const std::string& yaml : yamls) {
      const GridMap map = minibot3d_map_io::LoadMap(yaml);
      Run(yaml, map, [&](const Pose2& p) { return GridScan(map, p, settings.range); }, settings);
    }
    if (synthetic) {
      for (const auto& size : {std::pair<double, double>{50.0, 50.0}, {54.0, 59.0}}) {
        const auto world =
            minibot3d_testing::OfficeBuilding(size.first, size.second, 1);
        const GridMap map =
            minibot3d_testing::Rasterize(world, 0.0, 0.0, size.first, size.second);
        Run("office " + std::to_string(static_cast<int>(size.first)) + " m x " +
                std::to_string(static_cast<int>(size.second)) + " m",
            map,
            [&](const Pose2& p) {
              return minibot3d_testing::FullScan(world, p, 360, settings.range);
            },
            settings);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "correlative_search_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
