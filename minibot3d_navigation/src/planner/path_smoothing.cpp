#include "minibot3d_navigation/planner/path_smoothing.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minibot3d_navigation {
namespace nav {

bool SegmentCostsAtMost(const Costmap2D& costmap, const Point2& a,
                        const Point2& b, int max_cost,
                        const GlobalPlannerOptions& options) {
  auto ok = [&](int x, int y) {
    if (!costmap.InBounds(x, y)) return false;
    const uint8_t c = costmap.cost(x, y);
    return c <= max_cost && IsTraversableCost(c, options);
  };
  const double res = costmap.resolution();
  const double fx = (a.x - costmap.origin_x()) / res;
  const double fy = (a.y - costmap.origin_y()) / res;
  const double dx = (b.x - a.x) / res, dy = (b.y - a.y) / res;
  if (dx == 0.0 && dy == 0.0) {
    return ok(static_cast<int>(std::floor(fx)), static_cast<int>(std::floor(fy)));
  }
  // Amanatides & Woo traversal in the segment parameter t in [0, 1]: tmx /
  // tmy is the t of the next vertical / horizontal grid line crossed.  The
  // cell of each piece between consecutive crossings is found from the
  // piece's midpoint, so a piece of (near) zero length - the segment passing
  // exactly through a cell corner, or starting/ending on a cell border - adds
  // no cell it does not enter.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kMinPiece = 1e-9;
  const double tdx = dx != 0.0 ? 1.0 / std::abs(dx) : kInf;
  const double tdy = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  double tmx = dx > 0 ? (x0 + 1 - fx) / dx : (dx < 0 ? (fx - x0) / -dx : kInf);
  double tmy = dy > 0 ? (y0 + 1 - fy) / dy : (dy < 0 ? (fy - y0) / -dy : kInf);
  double t = 0.0;
  while (t < 1.0) {
    const double t_next = std::min({tmx, tmy, 1.0});
    if (t_next - t > kMinPiece) {
      const double tm = 0.5 * (t + t_next);
      if (!ok(static_cast<int>(std::floor(fx + tm * dx)),
              static_cast<int>(std::floor(fy + tm * dy)))) {
        return false;
      }
    }
    if (tmx <= t_next) tmx += tdx;
    if (tmy <= t_next) tmy += tdy;
    t = t_next;
  }
  return true;
}

std::vector<Point2> ShortcutPath(const Costmap2D& costmap,
                                  const std::vector<Point2>& raw,
                                  const GlobalPlannerOptions& options) {
  const int n = static_cast<int>(raw.size());
  if (n <= 2) return raw;
  std::vector<int> raw_cost(n);
  for (int k = 0; k < n; ++k) {
    int mx = 0, my = 0;
    raw_cost[k] = costmap.WorldToMap(raw[k].x, raw[k].y, &mx, &my)
                      ? costmap.cost(mx, my)
                      : kNoInformation;
  }
  // Prefix maxima would not do (the bound is a range maximum); a sparse
  // table gives the highest raw cost over raw[i..j] in O(1).
  std::vector<std::vector<int>> table{raw_cost};
  for (int span = 1; 2 * span <= n; span *= 2) {
    const std::vector<int>& prev = table.back();
    std::vector<int> next_level(n - 2 * span + 1);
    for (int i = 0; i + 2 * span <= n; ++i) {
      next_level[i] = std::max(prev[i], prev[i + span]);
    }
    table.push_back(std::move(next_level));
  }
  auto range_max = [&table](int i, int j) {  // inclusive
    int level = 0;
    while ((2 << level) <= j - i + 1) ++level;
    return std::max(table[level][i], table[level][j - (1 << level) + 1]);
  };
  auto shortcut_ok = [&](int i, int j) {
    return SegmentCostsAtMost(costmap, raw[i], raw[j], range_max(i, j), options);
  };

  std::vector<int> kept(n);
  for (int k = 0; k < n; ++k) kept[k] = k;
  std::vector<int> next;
  constexpr int kMaxPasses = 4;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const int m = static_cast<int>(kept.size());
    next.clear();
    next.push_back(kept[0]);
    int a = 0;
    while (a < m - 1) {
      // Galloping search for a far reachable point: double the step while
      // the shortcut holds, then bisect between the last success and the
      // first failure.  The test is not monotone in the end point, so this
      // finds a long valid shortcut, not always the longest; the next pass
      // picks up what it missed.  O(L log n) cell checks per shortcut of L.
      int good = a + 1, bad = m;
      for (int step = 1; a + step + 1 < m; step *= 2) {
        const int c = a + step + 1;
        if (shortcut_ok(kept[a], kept[c])) {
          good = c;
        } else {
          bad = c;
          break;
        }
      }
      if (bad == m && good < m - 1) {
        if (shortcut_ok(kept[a], kept[m - 1])) {
          good = m - 1;
        } else {
          bad = m - 1;
        }
      }
      while (bad - good > 1) {
        const int c = good + (bad - good) / 2;
        if (shortcut_ok(kept[a], kept[c])) {
          good = c;
        } else {
          bad = c;
        }
      }
      next.push_back(kept[good]);
      a = good;
    }
    const bool changed = next.size() != kept.size();
    kept.swap(next);
    if (!changed) break;
  }
  std::vector<Point2> out;
  out.reserve(kept.size());
  for (int k : kept) out.push_back(raw[k]);
  return out;
}

std::vector<Point2> ResamplePolyline(const std::vector<Point2>& points,
                                      double spacing) {
  if (points.size() < 2 || !(spacing > 0.0)) return points;
  std::vector<Point2> out;
  out.push_back(points[0]);
  for (size_t i = 1; i < points.size(); ++i) {
    const Point2& a = points[i - 1];
    const Point2& b = points[i];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / spacing - 1e-9)));
    for (int k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
    out.push_back(b);
  }
  return out;
}

double PolylineLength(const std::vector<Point2>& points) {
  double len = 0.0;
  for (size_t i = 1; i < points.size(); ++i) {
    len += std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
  }
  return len;
}

double PathLength(const Path& path) {
  double len = 0.0;
  for (size_t i = 1; i < path.size(); ++i) {
    len += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  }
  return len;
}

Path MakePathPoses(const std::vector<Point2>& points, double start_yaw,
                   const Pose2& goal, int orientation_mode) {
  Path path(points.size());
  const size_t n = points.size();
  if (n == 0) return path;
  const double total = PolylineLength(points);
  const double turn = AngleDiff(goal.yaw, start_yaw);
  double travelled = 0.0;
  // Forward: heading to the next point that differs; a run of coincident
  // points takes the heading after it (or the goal's at the end).
  double heading = goal.yaw;
  std::vector<double> forward(n, goal.yaw);
  for (size_t i = n - 1; i-- > 0;) {
    const double dx = points[i + 1].x - points[i].x;
    const double dy = points[i + 1].y - points[i].y;
    if (dx != 0.0 || dy != 0.0) heading = std::atan2(dy, dx);
    forward[i] = heading;
  }
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) {
      travelled += std::hypot(points[i].x - points[i - 1].x,
                              points[i].y - points[i - 1].y);
    }
    double yaw = 0.0;
    if (orientation_mode == 1) {
      yaw = forward[i];
    } else if (orientation_mode == 2) {
      yaw = NormalizeAngle(start_yaw + (total > 0.0 ? turn * travelled / total : 0.0));
    }
    path[i] = {points[i].x, points[i].y, yaw};
  }
  path.back().yaw = goal.yaw;
  if (points.back().x == goal.x && points.back().y == goal.y) path.back() = goal;
  return path;
}

}  // namespace nav
}  // namespace minibot3d_navigation
