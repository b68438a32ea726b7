#include "minibot3d_navigation/explore/frontier_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

#include "minibot3d_navigation/option_table.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = ExploreOptions;

const options::OptionTable<O>& Table() {
  static const options::OptionTable<O> table(
      "explore", {Field("min_frontier_size", &O::min_frontier_size),
                  Field("clearance", &O::clearance),
                  Field("free_threshold", &O::free_threshold),
                  Field("blacklist_radius", &O::blacklist_radius),
                  Field("goal_search_radius", &O::goal_search_radius)});
  return table;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

void ValidateExploreOptions(const ExploreOptions& o) {
  options::Problems p("explore");
  p.Require(std::isfinite(o.min_frontier_size) && o.min_frontier_size >= 0.0,
            "min_frontier_size=" + Num(o.min_frontier_size) + " must be >= 0");
  p.Require(std::isfinite(o.clearance) && o.clearance >= 0.0,
            "clearance=" + Num(o.clearance) + " must be >= 0");
  p.Require(o.free_threshold >= 0 && o.free_threshold < 100,
            "free_threshold=" + std::to_string(o.free_threshold) + " must be in [0, 100)");
  p.Require(std::isfinite(o.blacklist_radius) && o.blacklist_radius >= 0.0,
            "blacklist_radius=" + Num(o.blacklist_radius) + " must be >= 0");
  p.Require(std::isfinite(o.goal_search_radius) && o.goal_search_radius >= 0.0,
            "goal_search_radius=" + Num(o.goal_search_radius) + " must be >= 0");
  p.ThrowIfAny();
}

void SetExploreOption(const std::string& name, const std::string& text, ExploreOptions* o) {
  Table().Set(name, text, o);
}
bool IsExploreOptionName(const std::string& name) { return Table().Has(name); }
std::vector<std::string> ExploreOptionNames() { return Table().Names(); }

FrontierSearch::FrontierSearch(const ExploreOptions& options) : options_(options) {
  ValidateExploreOptions(options_);
}

FrontierSearchResult FrontierSearch::Find(const amcl::OccupancyGrid& grid, const Pose2D& robot,
                                          const std::vector<Point2D>& blacklist) const {
  const int w = grid.width, h = grid.height;
  if (w <= 0 || h <= 0 || !(grid.resolution > 0.0) ||
      grid.data.size() != static_cast<size_t>(w) * h) {
    throw std::invalid_argument("frontier search: malformed map (" + std::to_string(w) + "x" +
                                std::to_string(h) + ", " + std::to_string(grid.data.size()) +
                                " cells, resolution " + Num(grid.resolution) + ")");
  }
  const double res = grid.resolution;
  const int n = w * h;
  auto to_world = [&](int i) {
    return Point2D{grid.origin_x + (i % w + 0.5) * res, grid.origin_y + (i / w + 0.5) * res};
  };
  const int rx = static_cast<int>(std::floor((robot.x - grid.origin_x) / res));
  const int ry = static_cast<int>(std::floor((robot.y - grid.origin_y) / res));
  if (rx < 0 || ry < 0 || rx >= w || ry >= h) {
    throw std::invalid_argument("frontier search: robot (" + Num(robot.x) + ", " + Num(robot.y) +
                                ") is off the map");
  }

  FrontierSearchResult result;
  std::vector<uint8_t> kind(n);  // 0 free, 1 unknown, 2 occupied
  for (int i = 0; i < n; ++i) {
    const int v = grid.data[i];
    kind[i] = v < 0 ? 1 : (v <= options_.free_threshold ? 0 : 2);
    if (kind[i] == 0) result.known_free_area += res * res;
  }

  // Traversable: free and no occupied cell within the clearance disc.
  const int r = static_cast<int>(std::ceil(options_.clearance / res));
  std::vector<uint8_t> blocked(n, 0);
  std::vector<std::pair<int, int>> disc;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if ((dx * dx + dy * dy) * res * res <= options_.clearance * options_.clearance + 1e-12) {
        disc.emplace_back(dx, dy);
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    if (kind[i] != 2) continue;
    const int x = i % w, y = i / w;
    for (const auto& d : disc) {
      const int xx = x + d.first, yy = y + d.second;
      if (xx >= 0 && yy >= 0 && xx < w && yy < h) blocked[yy * w + xx] = 1;
    }
  }
  auto traversable = [&](int i) { return kind[i] == 0 && !blocked[i]; };

  // Dijkstra from the robot; non-traversable free cells only while escaping
  // from a start that is itself not traversable.
  std::vector<double> dist(n, kInf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  const int start = ry * w + rx;
  dist[start] = 0.0;
  open.push({0.0, start});
  const int dxs[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  const int dys[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > dist[i]) continue;
    const bool escaping = !traversable(i);
    const int x = i % w, y = i / w;
    for (int k = 0; k < 8; ++k) {
      const int xx = x + dxs[k], yy = y + dys[k];
      if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
      const int j = yy * w + xx;
      if (!(traversable(j) || (escaping && kind[j] == 0))) continue;
      const double nd = d + (k < 4 ? res : res * std::sqrt(2.0));
      if (nd < dist[j]) {
        dist[j] = nd;
        open.push({nd, j});
      }
    }
  }

  // Frontier cells, clustered 8-connected.
  std::vector<uint8_t> is_frontier(n, 0);
  for (int i = 0; i < n; ++i) {
    if (kind[i] != 0) continue;
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int xx = x + dxs[k], yy = y + dys[k];
      if (xx >= 0 && yy >= 0 && xx < w && yy < h && kind[yy * w + xx] == 1) {
        is_frontier[i] = 1;
        break;
      }
    }
  }
  const int sr = static_cast<int>(std::ceil(options_.goal_search_radius / res));
  std::vector<uint8_t> seen(n, 0);
  std::vector<int> stack, cluster;
  for (int s = 0; s < n; ++s) {
    if (!is_frontier[s] || seen[s]) continue;
    cluster.clear();
    stack.assign(1, s);
    seen[s] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      cluster.push_back(i);
      const int x = i % w, y = i / w;
      for (int k = 0; k < 8; ++k) {
        const int xx = x + dxs[k], yy = y + dys[k];
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        const int j = yy * w + xx;
        if (is_frontier[j] && !seen[j]) {
          seen[j] = 1;
          stack.push_back(j);
        }
      }
    }
    if (cluster.size() * res < options_.min_frontier_size) continue;
    Frontier f;
    f.cells = static_cast<int>(cluster.size());
    f.size = cluster.size() * res;
    double cx = 0.0, cy = 0.0;
    int best = -1;
    for (int i : cluster) {
      const Point2D p = to_world(i);
      cx += p.x;
      cy += p.y;
      const int x = i % w, y = i / w;
      for (int dy = -sr; dy <= sr; ++dy) {
        for (int dx = -sr; dx <= sr; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const int j = yy * w + xx;
          if (traversable(j) && dist[j] < kInf && (best < 0 || dist[j] < dist[best])) best = j;
        }
      }
    }
    f.centroid = {cx / cluster.size(), cy / cluster.size()};
    if (best < 0) {
      ++result.unreachable;
      continue;
    }
    f.goal = to_world(best);
    f.distance = dist[best];
    bool banned = false;
    for (const Point2D& b : blacklist) {
      banned |= std::hypot(b.x - f.goal.x, b.y - f.goal.y) < options_.blacklist_radius;
    }
    if (banned) {
      ++result.blacklisted;
      continue;
    }
    result.frontiers.push_back(f);
  }
  std::sort(result.frontiers.begin(), result.frontiers.end(),
            [](const Frontier& a, const Frontier& b) { return a.distance < b.distance; });
  return result;
}

}  // namespace nav
}  // namespace minibot3d_navigation
