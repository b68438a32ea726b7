#include "minibot3d_navigation/amcl/global_search.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <sstream>

#include "minibot3d_scan_matching/correlative_search.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

namespace scan_matching = minibot3d_scan_matching;

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

scan_matching::CorrelativeSearchOptions SearchOptions(const AmclOptions& o) {
  scan_matching::CorrelativeSearchOptions s;
  s.linear_search_window = scan_matching::CorrelativeSearchOptions::kWholeMap;
  s.angular_search_window = kPi;  // full circle
  s.angular_step = o.global_search_angular_step;
  s.branch_and_bound_depth = o.global_search_depth;
  s.min_score = o.global_search_min_score;
  s.max_candidates = o.global_search_max_candidates;
  s.min_relative_score = o.global_search_min_relative_score;
  s.min_separation_linear = 1.0;
  s.min_separation_angular = kPi / 4.0;
  return s;
}

}  // namespace

GlobalSearch::GlobalSearch(const OccupancyGrid& grid,
                           const AmclOptions& options)
    : options_(options) {
  if (!options.global_search) {
    fallback_reason_ = "global_search is false";
    return;
  }
  const double cells = static_cast<double>(grid.width) * grid.height;
  predicted_seconds_ = kFixedSeconds + cells / kCellsPerSecond;
  if (predicted_seconds_ > options.global_search_budget) {
    std::ostringstream os;
    os.precision(3);
    os << "map " << grid.width << " x " << grid.height << " cells ("
       << cells * grid.resolution * grid.resolution
       << " m^2 at " << grid.resolution << " m) needs about "
       << predicted_seconds_ << " s per map-wide search, over "
       << "global_search_budget=" << options.global_search_budget
       << " s; raise it to search anyway";
    fallback_reason_ = os.str();
    return;
  }
  search_.reset(new scan_matching::CorrelativeSearch(grid, SearchOptions(options)));
}

GlobalSearch::~GlobalSearch() = default;

std::vector<SearchCandidate> GlobalSearch::Search(const LaserScan& scan,
                                                  double* seconds,
                                                  double* cpu_seconds,
                                                  int max_candidates) const {
  std::vector<SearchCandidate> out;
  if (seconds != nullptr) *seconds = 0.0;
  if (cpu_seconds != nullptr) *cpu_seconds = 0.0;
  if (!search_ || scan.ranges.size() != scan.angles.size()) return out;
  // End points in the base frame, as the filter's sensor model sees them.
  double range_max = scan.range_max;
  if (options_.laser_max_range > 0.0) {
    range_max = std::min(range_max, options_.laser_max_range);
  }
  double range_min = scan.range_min;
  if (options_.laser_min_range > 0.0) {
    range_min = std::max(range_min, options_.laser_min_range);
  }
  const Pose2& l = scan.sensor_in_base;
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan.ranges.size());
  for (size_t k = 0; k < scan.ranges.size(); ++k) {
    const double r = scan.ranges[k];
    if (!std::isfinite(r) || !(r > range_min) || !(r < range_max)) continue;
    const Pose2 end = Compose(l, {r * std::cos(scan.angles[k]),
                                   r * std::sin(scan.angles[k]), 0.0});
    points.emplace_back(end.x, end.y);
  }
  if (points.empty()) return out;
  const size_t max_points = static_cast<size_t>(options_.global_search_max_beams);
  if (points.size() > max_points) {
    std::vector<Eigen::Vector2d> kept;
    kept.reserve(max_points);
    for (size_t k = 0; k < max_points; ++k) {
      kept.push_back(points[k * points.size() / max_points]);
    }
    points.swap(kept);
  }
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  scan_matching::CorrelativeSearchOptions so = SearchOptions(options_);
  if (max_candidates > 0) so.max_candidates = max_candidates;
  const std::vector<scan_matching::CorrelativeMatch> matches =
      search_->SearchAll(points, Pose2{}, so);
  if (seconds != nullptr) {
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                             start)
                   .count();
  }
  if (cpu_seconds != nullptr) *cpu_seconds = ThreadCpuSeconds() - cpu_start;
  for (const scan_matching::CorrelativeMatch& m : matches) {
    out.push_back({{m.pose.x, m.pose.y, NormalizeAngle(m.pose.yaw)},
                   m.score});
  }
  return out;
}

}  // namespace amcl
}  // namespace minibot3d_navigation
