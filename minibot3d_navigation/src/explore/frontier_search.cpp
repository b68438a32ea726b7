#include "minibot3d_navigation/explore/frontier_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <stdexcept>
#include <utility>

#include "minibot3d_common/line_walker.h"
#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = ExploreOptions;

constexpr double kInf = std::numeric_limits<double>::infinity();

// 0 free, 1 unknown, 2 occupied.
int8_t Kind(int value, int free_threshold) {
  return value < 0 ? 1 : (value <= free_threshold ? 0 : 2);
}

// Where the search starts: the robot's cell if it is known free; else the nearest known-free
// cells within `radius`, found by a breadth-first walk through cells that are not occupied (the
// blind patch under a robot whose lasers sit at its ends), each with its walked distance.
std::vector<std::pair<int, double>> StartCells(const std::vector<uint8_t>& kind, int w, int h,
                                               int start, double res, double radius) {
  if (kind[start] == 0) return {{start, 0.0}};
  const int dxs[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  const int dys[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  std::vector<double> dist(kind.size(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[start] = 0.0;
  open.push({0.0, start});
  std::vector<std::pair<int, double>> found;
  double nearest = std::numeric_limits<double>::infinity();
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > dist[i] || d > nearest + 1e-9) continue;
    if (kind[i] == 0) {
      nearest = d;
      found.emplace_back(i, d);
      continue;
    }
    const int x = i % w, y = i / w;
    for (int k = 0; k < 8; ++k) {
      const int xx = x + dxs[k], yy = y + dys[k];
      if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
      const int j = yy * w + xx;
      if (kind[j] == 2) continue;
      const double nd = d + (k < 4 ? res : res * std::sqrt(2.0));
      if (nd <= radius + 1e-9 && nd < dist[j]) {
        dist[j] = nd;
        open.push({nd, j});
      }
    }
  }
  if (found.empty()) found.emplace_back(start, 0.0);  // nothing free near: as before
  return found;
}

void CheckGrid(const OccupancyGrid& grid) {
  const int w = grid.width, h = grid.height;
  if (w <= 0 || h <= 0 || !(grid.resolution > 0.0) ||
      grid.data.size() != static_cast<size_t>(w) * h) {
    throw std::invalid_argument("frontier search: malformed map (" + std::to_string(w) + "x" +
                                std::to_string(h) + ", " + std::to_string(grid.data.size()) +
                                " cells, resolution " + Num(grid.resolution) + ")");
  }
}

std::vector<uint8_t> Kinds(const OccupancyGrid& grid, int free_threshold) {
  std::vector<uint8_t> kind(grid.data.size());
  for (size_t i = 0; i < kind.size(); ++i) kind[i] = Kind(grid.data[i], free_threshold);
  return kind;
}

// Free cells with an unknown 4-neighbour.
std::vector<uint8_t> FrontierCells(const std::vector<uint8_t>& kind, int w, int h) {
  static const int dxs[4] = {1, -1, 0, 0};
  static const int dys[4] = {0, 0, 1, -1};
  std::vector<uint8_t> is_frontier(kind.size(), 0);
  for (int i = 0; i < w * h; ++i) {
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
  return is_frontier;
}

// True when every cell strictly between cells a and b (Bresenham) is free.
bool LineOfSight(int a, int b, int w, const std::vector<uint8_t>& kind) {
  minibot3d_common::LineWalker walk(a % w, a / w, b % w, b / w);
  if (walk.done()) return true;
  while (true) {
    walk.Next();
    if (walk.done()) return true;
    if (kind[walk.y() * w + walk.x()] != 0) return false;
  }
}

// How near each cell is to an occupied cell, in one pass: 2 within `inner`,
// 1 within `outer` (>= inner) only, 0 farther.
std::vector<uint8_t> NearOccupied(const std::vector<uint8_t>& kind, int w, int h, double inner,
                                  double outer, double res) {
  const int r = static_cast<int>(std::ceil(outer / res));
  struct Offset {
    int dx, dy;
    uint8_t level;
  };
  std::vector<Offset> disc;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const double d2 = (dx * dx + dy * dy) * res * res;
      if (d2 <= outer * outer + 1e-12) {
        disc.push_back({dx, dy, static_cast<uint8_t>(d2 <= inner * inner + 1e-12 ? 2 : 1)});
      }
    }
  }
  std::vector<uint8_t> near(kind.size(), 0);
  for (int i = 0; i < w * h; ++i) {
    if (kind[i] != 2) continue;
    const int x = i % w, y = i / w;
    for (const Offset& d : disc) {
      const int xx = x + d.dx, yy = y + d.dy;
      if (xx >= 0 && yy >= 0 && xx < w && yy < h) {
        uint8_t& n = near[yy * w + xx];
        n = std::max(n, d.level);
      }
    }
  }
  return near;
}

// Non-zero for the cells within `radius` of an unknown cell that borders a known-free one:
// NearOccupied with those unknown cells standing for the occupied ones.
std::vector<uint8_t> NearUnknown(const std::vector<uint8_t>& kind, int w, int h, double radius,
                                 double res) {
  static const int dxs[4] = {1, -1, 0, 0};
  static const int dys[4] = {0, 0, 1, -1};
  std::vector<uint8_t> border(kind.size(), 0);
  for (int i = 0; i < w * h; ++i) {
    if (kind[i] != 1) continue;
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int xx = x + dxs[k], yy = y + dys[k];
      if (xx >= 0 && yy >= 0 && xx < w && yy < h && kind[yy * w + xx] == 0) {
        border[i] = 2;
        break;
      }
    }
  }
  return NearOccupied(border, w, h, radius, radius, res);
}

// True when cell v has a line of sight to an unknown 4-neighbour of frontier
// cell i: a ray from v reaches the unknown side.
bool SeesUnknownSide(int v, int i, int w, int h, const std::vector<uint8_t>& kind) {
  static const int dxs[4] = {1, -1, 0, 0};
  static const int dys[4] = {0, 0, 1, -1};
  const int x = i % w, y = i / w;
  for (int k = 0; k < 4; ++k) {
    const int ux = x + dxs[k], uy = y + dys[k];
    if (ux < 0 || uy < 0 || ux >= w || uy >= h || kind[uy * w + ux] != 1) continue;
    if (LineOfSight(v, uy * w + ux, w, kind)) return true;
  }
  return false;
}

// Shortest 8-connected path lengths (m) from `starts` (cell, length there), a step from cell i to
// its neighbour j allowed when enter(i, j); paths longer than `limit` are not followed.
template <typename Enter>
std::vector<double> PathLengths(const std::vector<std::pair<int, double>>& starts,
                                const Enter& enter, int w, int h, double res,
                                double limit = kInf) {
  std::vector<double> dist(w * h, kInf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  for (const auto& [cell, d0] : starts) {
    dist[cell] = d0;
    open.push({d0, cell});
  }
  const int dxs[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  const int dys[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > dist[i]) continue;
    const int x = i % w, y = i / w;
    for (int k = 0; k < 8; ++k) {
      const int xx = x + dxs[k], yy = y + dys[k];
      if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
      const int j = yy * w + xx;
      if (!enter(i, j)) continue;
      const double nd = d + (k < 4 ? res : res * std::sqrt(2.0));
      if (nd < dist[j] && nd <= limit + 1e-9) {
        dist[j] = nd;
        open.push({nd, j});
      }
    }
  }
  return dist;
}

// Free cells joined to the reachable ones (dist < inf) through free cells farther than `gap`
// from any occupied cell (8-connected): pockets off the robot's space, but not free cells seen
// through a chink in a wall (outside the building).
std::vector<uint8_t> JoinedToReachable(const std::vector<uint8_t>& kind,
                                       const std::vector<double>& dist, int w, int h,
                                       double gap, double res) {
  const std::vector<uint8_t> near = NearOccupied(kind, w, h, gap, gap, res);
  std::vector<uint8_t> joined(kind.size(), 0);
  std::vector<int> stack;
  for (int i = 0; i < w * h; ++i) {
    if (dist[i] < kInf) {
      joined[i] = 1;
      stack.push_back(i);
    }
  }
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        const int j = yy * w + xx;
        if (joined[j] || kind[j] != 0 || near[j] >= 2) continue;
        joined[j] = 1;
        stack.push_back(j);
      }
    }
  }
  return joined;
}

// Calls visit(c, j) for each cell j that has an unknown 4-neighbour of frontier cell cells[c] in
// its line of sight within `range` cells (possibly more than once): rays walked out from every
// such unknown cell through known-free cells, one per cell of the circle of radius `range`, so
// that no cell within range is skipped.
template <typename Visit>
void WalkVisibility(const std::vector<int>& cells, const std::vector<uint8_t>& kind, int w, int h,
                    int range, const Visit& visit) {
  static const int dxs[4] = {1, -1, 0, 0};
  static const int dys[4] = {0, 0, 1, -1};
  // The ends of the rays: the cells of a circle of radius `range` (midpoint circle walk).
  std::vector<std::pair<int, int>> ends;
  for (int x = range, y = 0, err = 1 - range; x >= y; ++y) {
    const int pts[8][2] = {{x, y}, {y, x}, {-y, x}, {-x, y}, {-x, -y}, {-y, -x}, {y, -x}, {x, -y}};
    for (const auto& p : pts) ends.emplace_back(p[0], p[1]);
    if (err < 0) {
      err += 2 * y + 3;
    } else {
      err += 2 * (y - x) + 5;
      --x;
    }
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  for (size_t c = 0; c < cells.size(); ++c) {
    const int i = cells[c];
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int ux = x + dxs[k], uy = y + dys[k];
      if (ux < 0 || uy < 0 || ux >= w || uy >= h || kind[uy * w + ux] != 1) continue;
      for (const auto& [ex, ey] : ends) {
        minibot3d_common::LineWalker walk(ux, uy, ux + ex, uy + ey);
        while (!walk.done()) {
          walk.Next();
          const int xx = walk.x(), yy = walk.y();
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) break;
          const int j = yy * w + xx;
          if (kind[j] != 0) break;
          visit(c, j);
        }
      }
    }
  }
}

// For each cell, how many of the frontier cells `cells` it sees (WalkVisibility).  `touched`
// lists the cells with a count.
std::vector<int> VisibilityCounts(const std::vector<int>& cells, const std::vector<uint8_t>& kind,
                                  int w, int h, int range, std::vector<int>* touched) {
  std::vector<int> count(kind.size(), 0);
  std::vector<int> stamp(kind.size(), -1);  // the last frontier cell counted at each cell
  touched->clear();
  WalkVisibility(cells, kind, w, h, range, [&](size_t c, int j) {
    if (stamp[j] == static_cast<int>(c)) return;
    stamp[j] = static_cast<int>(c);
    if (count[j]++ == 0) touched->push_back(j);
  });
  return count;
}

// A viewpoint from off for a frontier without a near one.  Each reachable cell `roomy` accepts
// that is not excluded is scored by the frontier cells (those joined to the robot's space) seen
// from every free cell within `tolerance` of it (VisibilityCounts within view_range, the least
// over that disc): move_base stops anywhere within its goal tolerance, and a pocket seen from
// the goal may be hidden from a stop beside it.  The goal is the cell with the shortest path
// from the robot among those scoring at least 3/4 of the best (the cells' own counts when no
// cell scores).  Sets `in_view` to the frontier cells it sees and *view_radius to the distance
// (m) to the farthest of them; returns -1 when no cell sees any.
template <typename Roomy>
int FarViewpointImpl(const std::vector<int>& cluster, const std::vector<uint8_t>& kind,
                     const std::vector<double>& dist, const std::vector<uint8_t>& is_excluded,
                     const std::vector<uint8_t>& joined, int w, int h, double res,
                     double view_range, double tolerance, const Roomy& roomy,
                     double* view_radius, std::vector<int>* in_view) {
  std::vector<int> cells;
  for (int i : cluster) {
    if (joined[i]) cells.push_back(i);
  }
  if (cells.empty()) return -1;
  const int range = static_cast<int>(std::floor(view_range / res));
  std::vector<int> touched;
  const std::vector<int> count = VisibilityCounts(cells, kind, w, h, range, &touched);
  const int tr = static_cast<int>(std::floor(tolerance / res + 1e-9));
  std::vector<std::pair<int, int>> disc;
  for (int dy = -tr; dy <= tr; ++dy) {
    for (int dx = -tr; dx <= tr; ++dx) {
      if (dx * dx + dy * dy <= tr * tr) disc.emplace_back(dx, dy);
    }
  }
  std::vector<std::pair<int, int>> scored;  // (cell, least count within tolerance)
  for (int j : touched) {
    if (!(dist[j] < kInf) || (is_excluded[j] & 2) || !roomy(j)) continue;
    int least = count[j];
    const int jx = j % w, jy = j / w;
    for (const auto& [dx, dy] : disc) {
      const int xx = jx + dx, yy = jy + dy;
      if (xx < 0 || yy < 0 || xx >= w || yy >= h || kind[yy * w + xx] != 0) continue;
      least = std::min(least, count[yy * w + xx]);
    }
    scored.emplace_back(j, least);
  }
  int most = 0;
  for (const auto& [j, least] : scored) most = std::max(most, least);
  const bool robust = most > 0;
  if (!robust) {
    for (const auto& [j, least] : scored) most = std::max(most, count[j]);
  }
  if (most == 0) return -1;
  int best = -1;
  for (const auto& [j, least] : scored) {
    if (4 * (robust ? least : count[j]) < 3 * most) continue;
    if (best < 0 || dist[j] < dist[best] || (dist[j] == dist[best] && j < best)) best = j;
  }
  std::vector<uint8_t> seen(cells.size(), 0);
  WalkVisibility(cells, kind, w, h, range, [&](size_t c, int j) {
    if (j == best) seen[c] = 1;
  });
  double farthest = 0.0;
  const int bx = best % w, by = best / w;
  in_view->clear();
  for (size_t c = 0; c < cells.size(); ++c) {
    if (!seen[c]) continue;
    in_view->push_back(cells[c]);
    farthest = std::max(farthest, std::hypot(cells[c] % w - bx, cells[c] / w - by) * res);
  }
  *view_radius = farthest + res;
  return best;
}

}  // namespace

void ValidateExploreOptions(const ExploreOptions& o) {
  options::Problems p("explore");
  p.Require(std::isfinite(o.min_frontier_size) && o.min_frontier_size >= 0.0,
            "min_frontier_size=" + Num(o.min_frontier_size) + " must be >= 0");
  p.Require(std::isfinite(o.clearance) && o.clearance >= 0.0,
            "clearance=" + Num(o.clearance) + " must be >= 0");
  p.Require(std::isfinite(o.goal_clearance) && o.goal_clearance >= o.clearance,
            "goal_clearance=" + Num(o.goal_clearance) + " must be >= clearance=" +
                Num(o.clearance));
  p.Require(o.free_threshold >= 0 && o.free_threshold < 100,
            "free_threshold=" + std::to_string(o.free_threshold) + " must be in [0, 100)");
  p.Require(std::isfinite(o.blacklist_radius) && o.blacklist_radius >= 0.0,
            "blacklist_radius=" + Num(o.blacklist_radius) + " must be >= 0");
  p.Require(std::isfinite(o.goal_search_radius) && o.goal_search_radius >= 0.0,
            "goal_search_radius=" + Num(o.goal_search_radius) + " must be >= 0");
  p.Require(std::isfinite(o.look_radius) && o.look_radius >= o.goal_search_radius,
            "look_radius=" + Num(o.look_radius) + " must be >= goal_search_radius=" +
                Num(o.goal_search_radius) + " (else a reached goal could be chosen again)");
  p.Require(std::isfinite(o.retry_window) && o.retry_window > 0.0 && o.retry_window <= 10.0,
            "retry_window=" + Num(o.retry_window) + " must be in (0, 10] m");
  p.Require(std::isfinite(o.retry_map_change) && o.retry_map_change > 0.0,
            "retry_map_change=" + Num(o.retry_map_change) + " must be > 0");
  p.Require(std::isfinite(o.start_search_radius) && o.start_search_radius >= 0.0,
            "start_search_radius=" + Num(o.start_search_radius) + " must be >= 0");
  p.Require(std::isfinite(o.view_range) &&
                (o.view_range == 0.0 || o.view_range >= o.goal_search_radius),
            "view_range=" + Num(o.view_range) + " must be 0 (off) or >= goal_search_radius=" +
                Num(o.goal_search_radius));
  p.Require(std::isfinite(o.goal_tolerance) && o.goal_tolerance >= 0.0,
            "goal_tolerance=" + Num(o.goal_tolerance) + " must be >= 0");
  p.Require(std::isfinite(o.creep_depth) && o.creep_depth >= 0.0,
            "creep_depth=" + Num(o.creep_depth) + " must be >= 0");
  p.Require(o.max_goal_attempts >= 1,
            "max_goal_attempts=" + std::to_string(o.max_goal_attempts) + " must be >= 1");
  p.ThrowIfAny();
}

const options::OptionTable<ExploreOptions>& ExploreOptionTable() {
  static const options::OptionTable<O> table(
      "explore",
      {Field("min_frontier_size", &O::min_frontier_size,
             "Shortest frontier (m, cells x resolution) that counts; shorter ones are noise "
             "(explore_lite)."),
       Field("clearance", &O::clearance,
             "Distance (m) from occupied cells that the cells of a path to a goal must keep."),
       Field("goal_clearance", &O::goal_clearance,
             "Distance (m) from occupied cells a goal must keep, so that the robot can turn there; "
             "at least clearance."),
       Field("free_threshold", &O::free_threshold,
             "Map values 0..this are free; higher ones occupied, -1 unknown."),
       Field("blacklist_radius", &O::blacklist_radius,
             "Radius (m) round a reached goal (for good) or an unreachable one (until the map "
             "there changes) within which no new goal is chosen."),
       Field("goal_search_radius", &O::goal_search_radius,
             "Distance (m) from a frontier cell within which its goal (a cell that sees past "
             "it) is looked for."),
       Field("look_radius", &O::look_radius,
             "Distance (m) from a reached goal within which frontier cells it saw that stay "
             "unknown stop counting as frontier; at least goal_search_radius."),
       Field("retry_window", &O::retry_window,
             "Half the side (m) of the square watched round an unreachable goal."),
       Field("retry_map_change", &O::retry_map_change,
             "Area (m^2) of that square that must change (free, occupied, unknown) before the "
             "goal may be tried again."),
       Field("max_goal_attempts", &O::max_goal_attempts,
             "Goals sent near one place before it is given up for good."),
       Field("start_search_radius", &O::start_search_radius,
             "When the robot's own cell is not known free (lasers at its ends do not see under "
             "it), the search starts from the nearest known-free cell within this distance (m), "
             "reached through cells that are not occupied."),
       Field("view_range", &O::view_range,
             "A frontier with no goal within goal_search_radius (the far end of a gap too "
             "narrow to stand in, seen only at a slant) is looked into from a roomy cell within "
             "this distance (m) that has most of it in sight; reaching it, what stays unknown in "
             "sight there is not chased again. Keep it within the lidar's reliable range; 0: "
             "such a frontier is dropped."),
       Field("goal_tolerance", &O::goal_tolerance,
             "How far from a goal move_base may stop (its xy_goal_tolerance, m): a goal that "
             "looks at a frontier from off must have it in sight from anywhere within this "
             "distance."),
       Field("creep_depth", &O::creep_depth,
             "A frontier no roomy cell within view_range sees (down a gap between furniture and "
             "a wall) is looked into from a cell only clearance from walls (room to turn on the "
             "spot, no margin: the local planner creeps) at most this far (m, by path) from a "
             "roomy cell; 0: such a frontier is dropped.")});
  return table;
}

void SetExploreOption(const std::string& name, const std::string& text, ExploreOptions* o) {
  ExploreOptionTable().Set(name, text, o);
}
bool IsExploreOptionName(const std::string& name) { return ExploreOptionTable().Has(name); }
std::vector<std::string> ExploreOptionNames() { return ExploreOptionTable().Names(); }

FrontierSearch::FrontierSearch(const ExploreOptions& options) : options_(options) {
  ValidateExploreOptions(options_);
}

FrontierSearchResult FrontierSearch::Find(const OccupancyGrid& grid, const Pose2& robot,
                                          const std::vector<Point2>& excluded,
                                          const std::vector<Point2>& looked_at,
                                          const std::vector<Point2>& unreachable) const {
  CheckGrid(grid);
  const int w = grid.width, h = grid.height;
  const double res = grid.resolution;
  const int n = w * h;
  auto to_world = [&](int i) {
    return Point2{grid.origin_x + (i % w + 0.5) * res, grid.origin_y + (i / w + 0.5) * res};
  };
  const int rx = static_cast<int>(std::floor((robot.x - grid.origin_x) / res));
  const int ry = static_cast<int>(std::floor((robot.y - grid.origin_y) / res));
  if (rx < 0 || ry < 0 || rx >= w || ry >= h) {
    throw std::invalid_argument("frontier search: robot (" + Num(robot.x) + ", " + Num(robot.y) +
                                ") is off the map");
  }

  FrontierSearchResult result;
  const std::vector<uint8_t> kind = Kinds(grid, options_.free_threshold);
  for (int i = 0; i < n; ++i) {
    if (kind[i] == 0) result.known_free_area += res * res;
  }

  // Traversable: free and no occupied cell within the clearance disc.  Cramped:
  // an occupied cell within goal_clearance (paths may pass, goals may not).
  const std::vector<uint8_t> near =
      NearOccupied(kind, w, h, options_.clearance, options_.goal_clearance, res);
  auto traversable = [&](int i) { return kind[i] == 0 && near[i] < 2; };
  // Goals keep goal_clearance from unknown space as from walls: the unseen face of a shelf may
  // be there, and a gap that only looked roomy would be a pocket the robot cannot turn in.
  const std::vector<uint8_t> near_unknown = NearUnknown(kind, w, h, options_.goal_clearance, res);
  auto cramped = [&](int i) { return near[i] >= 1 || near_unknown[i]; };

  // Dijkstra from the robot; non-traversable free cells only while escaping
  // from a start that is itself not traversable.
  const std::vector<double> dist = PathLengths(
      StartCells(kind, w, h, ry * w + rx, res, options_.start_search_radius),
      [&](int i, int j) { return traversable(j) || (!traversable(i) && kind[j] == 0); }, w, h,
      res);
  const int dxs[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  const int dys[8] = {0, 0, 1, -1, 1, -1, 1, -1};

  // Frontier cells, but for those looked at from a viewpoint, clustered 8-connected.
  std::vector<uint8_t> is_frontier = FrontierCells(kind, w, h);
  for (const Point2& p : looked_at) {
    const int x = static_cast<int>(std::floor((p.x - grid.origin_x) / res));
    const int y = static_cast<int>(std::floor((p.y - grid.origin_y) / res));
    if (x >= 0 && y >= 0 && x < w && y < h) is_frontier[y * w + x] = 0;
  }
  const int sr = static_cast<int>(std::ceil(options_.goal_search_radius / res));
  const double search_r2 = options_.goal_search_radius * options_.goal_search_radius + 1e-12;
  // Cells within `radius` of one of `points`, marked `mark`.
  auto mark_within = [&](const std::vector<Point2>& points, double radius, uint8_t mark,
                         std::vector<uint8_t>* marked) {
    const int er = static_cast<int>(std::ceil(radius / res));
    for (const Point2& e : points) {
      const int ex = static_cast<int>(std::floor((e.x - grid.origin_x) / res));
      const int ey = static_cast<int>(std::floor((e.y - grid.origin_y) / res));
      for (int y = std::max(0, ey - er); y <= std::min(h - 1, ey + er); ++y) {
        for (int x = std::max(0, ex - er); x <= std::min(w - 1, ex + er); ++x) {
          const Point2 p = to_world(y * w + x);
          if (std::hypot(e.x - p.x, e.y - p.y) < radius) (*marked)[y * w + x] |= mark;
        }
      }
    }
  };
  // 1: within blacklist_radius of an excluded viewpoint (no near viewpoint there).  2: no far
  // viewpoint there: within goal_tolerance of an excluded one (the same stop), or within
  // blacklist_radius of an unreachable goal.  A far viewpoint may be near one reached before:
  // it is chosen for what is in sight from it now, and what stays unknown in sight there once
  // it is reached no longer counts.
  std::vector<uint8_t> is_excluded(n, 0);
  mark_within(excluded, options_.blacklist_radius, 1, &is_excluded);
  mark_within(excluded, options_.goal_tolerance, 2, &is_excluded);
  mark_within(unreachable, options_.blacklist_radius, 2, &is_excluded);
  std::unordered_map<int, bool> candidate_los;  // this frontier's cells seen from a candidate
  std::vector<uint8_t> joined;  // JoinedToReachable, made when a frontier first needs it
  std::vector<uint8_t> creep;   // within creep_depth of a roomy cell, made when first needed
  std::vector<int> in_view;
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
    for (int i : cluster) {
      const Point2 p = to_world(i);
      cx += p.x;
      cy += p.y;
    }
    f.centroid = {cx / cluster.size(), cy / cluster.size()};
    // The viewpoint: the nearest reachable cell, roomy enough to turn in, that sees the
    // unknown side of a frontier cell and is not excluded.
    int best = -1;
    bool any_reachable = false;
    candidate_los.clear();
    for (int i : cluster) {
      const int x = i % w, y = i / w;
      for (int dy = -sr; dy <= sr; ++dy) {
        for (int dx = -sr; dx <= sr; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          if ((dx * dx + dy * dy) * res * res > search_r2) continue;
          const int j = yy * w + xx;
          if (!traversable(j) || !(dist[j] < kInf) || cramped(j)) continue;
          any_reachable = true;
          if (best >= 0 && dist[j] >= dist[best]) continue;
          if (is_excluded[j] & 1) continue;
          auto it = candidate_los.find(j);
          if (it == candidate_los.end() || !it->second) {
            const bool los = SeesUnknownSide(j, i, w, h, kind);
            candidate_los[j] = los;
            if (!los) continue;
          }
          best = j;
        }
      }
    }
    if (best < 0 && options_.view_range > 0.0) {
      if (joined.empty()) {
        joined = JoinedToReachable(kind, dist, w, h, options_.clearance / 2.0, res);
      }
      best = FarViewpointImpl(cluster, kind, dist, is_excluded, joined, w, h, res,
                              options_.view_range, options_.goal_tolerance,
                              [&](int j) { return traversable(j) && !cramped(j); },
                              &f.view_radius, &in_view);
      if (best < 0 && options_.creep_depth > 0.0) {
        // No roomy cell sees it: a cell a path may use (clearance from walls: room to turn on
        // the spot but no margin) at most creep_depth from roomy space, so that the robot
        // edges into a gap's mouth rather than down a gap it could only back out of.
        if (creep.empty()) {
          std::vector<std::pair<int, double>> roomy;
          for (int j = 0; j < n; ++j) {
            if (traversable(j) && !cramped(j) && dist[j] < kInf) roomy.emplace_back(j, 0.0);
          }
          const std::vector<double> depth = PathLengths(
              roomy, [&](int, int j) { return traversable(j); }, w, h, res, options_.creep_depth);
          creep.resize(n);
          for (int j = 0; j < n; ++j) creep[j] = depth[j] < kInf;
        }
        best = FarViewpointImpl(cluster, kind, dist, is_excluded, joined, w, h, res,
                                options_.view_range, options_.goal_tolerance,
                                [&](int j) { return creep[j] != 0; }, &f.view_radius, &in_view);
        f.creeping = best >= 0;
      }
      for (int i : in_view) f.in_view.push_back(to_world(i));
    }
    if (best < 0) {
      ++(any_reachable ? result.blacklisted : result.unreachable);
      continue;
    }
    f.goal = to_world(best);
    f.distance = dist[best];
    result.frontiers.push_back(f);
  }
  std::sort(result.frontiers.begin(), result.frontiers.end(),
            [](const Frontier& a, const Frontier& b) { return a.distance < b.distance; });
  return result;
}

std::vector<Point2> FrontierSearch::InSight(const OccupancyGrid& grid, const Point2& viewpoint,
                                             double radius) const {
  CheckGrid(grid);
  const int w = grid.width, h = grid.height;
  const double res = grid.resolution;
  std::vector<Point2> cells;
  const int vx = static_cast<int>(std::floor((viewpoint.x - grid.origin_x) / res));
  const int vy = static_cast<int>(std::floor((viewpoint.y - grid.origin_y) / res));
  if (vx < 0 || vy < 0 || vx >= w || vy >= h) return cells;
  const std::vector<uint8_t> kind = Kinds(grid, options_.free_threshold);
  const std::vector<uint8_t> is_frontier = FrontierCells(kind, w, h);
  const double look = std::max(options_.look_radius, radius);
  const int r = static_cast<int>(std::ceil(look / res));
  const double r2 = look * look + 1e-12;
  const int v = vy * w + vx;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const int x = vx + dx, y = vy + dy;
      if (x < 0 || y < 0 || x >= w || y >= h || (dx * dx + dy * dy) * res * res > r2) continue;
      if (is_frontier[y * w + x] && SeesUnknownSide(v, y * w + x, w, h, kind)) {
        cells.push_back({grid.origin_x + (x + 0.5) * res, grid.origin_y + (y + 0.5) * res});
      }
    }
  }
  return cells;
}

ExplorationMemory::ExplorationMemory(const ExploreOptions& options) : options_(options) {
  ValidateExploreOptions(options_);
}

void ExplorationMemory::Reached(const Point2& viewpoint) { visited_.push_back(viewpoint); }

void ExplorationMemory::LookedAt(const std::vector<Point2>& in_sight) {
  looked_at_.insert(looked_at_.end(), in_sight.begin(), in_sight.end());
}

std::vector<int8_t> ExplorationMemory::Window(const Point2& centre, double step,
                                              const OccupancyGrid& map) const {
  const int half = static_cast<int>(std::ceil(options_.retry_window / step));
  const bool well_formed = map.resolution > 0.0 && map.width > 0 && map.height > 0 &&
                          map.data.size() == static_cast<size_t>(map.width) * map.height;
  std::vector<int8_t> window;
  window.reserve((2 * half + 1) * (2 * half + 1));
  for (int dy = -half; dy <= half; ++dy) {
    for (int dx = -half; dx <= half; ++dx) {
      // A malformed map reads as unknown (FrontierSearch::Find reports it).
      int8_t kind = 1;
      if (well_formed) {
        const double gx = std::floor((centre.x + dx * step - map.origin_x) / map.resolution);
        const double gy = std::floor((centre.y + dy * step - map.origin_y) / map.resolution);
        if (gx >= 0 && gy >= 0 && gx < map.width && gy < map.height) {
          const int i = static_cast<int>(gy) * map.width + static_cast<int>(gx);
          kind = Kind(map.data[i], options_.free_threshold);
        }
      }
      window.push_back(kind);
    }
  }
  return window;
}

int ExplorationMemory::Failed(const Point2& goal, const OccupancyGrid& map) {
  Failure* f = nullptr;
  for (Failure& g : failures_) {
    if (std::hypot(g.goal.x - goal.x, g.goal.y - goal.y) < options_.blacklist_radius) f = &g;
  }
  if (f == nullptr) {
    failures_.push_back(Failure{});
    f = &failures_.back();
    f->goal = goal;
  }
  ++f->attempts;
  f->excluded = true;
  f->step = map.resolution > 0.0 ? map.resolution : 0.05;
  f->window = Window(f->goal, f->step, map);
  return f->attempts;
}

std::vector<Point2> ExplorationMemory::Refresh(const OccupancyGrid& map) {
  std::vector<Point2> released;
  for (Failure& f : failures_) {
    if (!f.excluded || f.attempts >= options_.max_goal_attempts) continue;
    const std::vector<int8_t> now = Window(f.goal, f.step, map);
    int changed = 0;
    for (size_t k = 0; k < now.size(); ++k) changed += now[k] != f.window[k];
    if (changed * f.step * f.step >= options_.retry_map_change) {
      f.excluded = false;
      released.push_back(f.goal);
    }
  }
  return released;
}

std::vector<Point2> ExplorationMemory::Excluded() const {
  std::vector<Point2> out = visited_;
  for (const Failure& f : failures_) {
    if (f.excluded) out.push_back(f.goal);
  }
  return out;
}

std::vector<Point2> ExplorationMemory::Unreachable() const {
  std::vector<Point2> out;
  for (const Failure& f : failures_) {
    if (f.excluded) out.push_back(f.goal);
  }
  return out;
}

}  // namespace nav
}  // namespace minibot3d_navigation
