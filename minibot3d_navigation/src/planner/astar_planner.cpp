#include "minibot3d_navigation/planner/astar_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "minibot3d_navigation/planner/path_smoothing.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

// Integer cost units per (neutral_cost + cost_factor * c) unit: fine enough
// that rounding the diagonal step (sqrt 2) is a 1e-5 relative error.
constexpr double kCostScale = 1000.0;
constexpr double kSqrt2 = 1.41421356237309504880;

// The 8 neighbours: 0..3 straight (+x, -x, +y, -y), 4..7 diagonal.  A
// diagonal's two orthogonal neighbours are kSideA / kSideB.
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
constexpr int kSideA[8] = {-1, -1, -1, -1, 0, 0, 1, 1};
constexpr int kSideB[8] = {-1, -1, -1, -1, 2, 3, 2, 3};

std::string CellText(int mx, int my) {
  return "cell (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
}

}  // namespace

AStarPlanner::AStarPlanner(const GlobalPlannerOptions& options)
    : options_(options) {
  ValidateGlobalPlannerOptions(options_);
  for (int c = 0; c < 256; ++c) {
    int cell_cost = c;
    const bool passable = IsTraversableCost(static_cast<uint8_t>(c), options_);
    if (c == kNoInformation) cell_cost = kUnknownCellCost;
    const double w = options_.neutral_cost + options_.cost_factor * cell_cost;
    straight_cost_[c] = passable ? std::llround(kCostScale * w) : -1;
    diagonal_cost_[c] =
        passable ? static_cast<int64_t>(std::ceil(kCostScale * kSqrt2 * w)) : -1;
    // Escape steps: a robot whose centre is already in the inflated band
    // (localization noise, a recovery turn near a wall) may leave it through
    // non-lethal cells; see Search.
    const bool escapable = !passable && c < kLethalObstacle;
    escape_straight_cost_[c] = escapable ? std::llround(kCostScale * w) : -1;
    escape_diagonal_cost_[c] =
        escapable ? static_cast<int64_t>(std::ceil(kCostScale * kSqrt2 * w)) : -1;
  }
  // The heuristic is the exact integer cost of the octile path over free
  // cells (straight_cost_[0], diagonal_cost_[0]), so it is exact in open
  // space and every step costs at least its drop in h (consistent): w >=
  // neutral_cost for every cell and rounding is monotone.
  for (int c = 0; c < 256; ++c) {
    escape_or_normal_straight_[c] =
        straight_cost_[c] >= 0 ? straight_cost_[c] : escape_straight_cost_[c];
    escape_or_normal_diagonal_[c] =
        diagonal_cost_[c] >= 0 ? diagonal_cost_[c] : escape_diagonal_cost_[c];
  }
  h_straight_ = straight_cost_[0];
  h_diagonal_ = diagonal_cost_[0] - straight_cost_[0];
}

void AStarPlanner::RadixHeap::Clear() {
  for (auto& b : buckets_) b.clear();
  nonempty_ = 0;
  last_ = 0;
  size_ = 0;
}

int AStarPlanner::RadixHeap::Bucket(uint64_t a, uint64_t b) {
  return a == b ? 0 : 64 - __builtin_clzll(a ^ b);
}

void AStarPlanner::RadixHeap::Push(uint64_t key, int32_t index) {
  // Keys below the last popped one cannot occur with a consistent heuristic;
  // clamp rather than corrupt the heap if rounding ever produced one.
  if (key < last_) key = last_;
  const int b = Bucket(key, last_);
  buckets_[b].push_back({key, index});
  if (b > 0) nonempty_ |= uint64_t{1} << (b - 1);
  ++size_;
}

AStarPlanner::RadixHeap::Entry AStarPlanner::RadixHeap::Pop() {
  if (buckets_[0].empty()) {
    // Refill bucket 0 from the lowest non-empty bucket: its minimum becomes
    // last_, and every entry moves to a strictly lower bucket.
    const int b = __builtin_ctzll(nonempty_) + 1;
    std::vector<Entry>& src = buckets_[b];
    uint64_t min_key = src[0].key;
    for (const Entry& e : src) min_key = std::min(min_key, e.key);
    last_ = min_key;
    for (const Entry& e : src) {
      const int nb = Bucket(e.key, last_);
      buckets_[nb].push_back(e);
      if (nb > 0) nonempty_ |= uint64_t{1} << (nb - 1);
    }
    src.clear();
    nonempty_ &= ~(uint64_t{1} << (b - 1));
  }
  const Entry e = buckets_[0].back();
  buckets_[0].pop_back();
  --size_;
  return e;
}

void AStarPlanner::PrepareBuffers(int num_cells) {
  if (static_cast<int>(state_.size()) != num_cells ||
      open_mark_ > std::numeric_limits<uint32_t>::max() - 4) {
    state_.assign(num_cells, CellState{0, 0, 0});
    open_mark_ = 0;
  }
  open_mark_ += 2;  // marks of earlier searches now mean "unvisited"
  open_.Clear();
}

bool AStarPlanner::Search(const Costmap2D& costmap, int start_index,
                          int goal_index) {
  const int w = costmap.size_x(), h = costmap.size_y();
  PrepareBuffers(w * h);
  const uint8_t* data = costmap.data();
  CellState* st = state_.data();
  const uint32_t open = open_mark_, closed = open_mark_ + 1;
  const int goal_x = goal_index % w, goal_y = goal_index / w;
  const int64_t hs = h_straight_, hd = h_diagonal_;
  auto heuristic = [=](int x, int y) {
    const int64_t ax = std::abs(x - goal_x), ay = std::abs(y - goal_y);
    return ax > ay ? hs * ax + hd * ay : hs * ay + hd * ax;
  };
  int offset[8];
  for (int d = 0; d < 8; ++d) offset[d] = kDy[d] * w + kDx[d];

  expansions_ = 0;
  st[start_index].g = 0;
  st[start_index].mark = open;
  open_.Push(heuristic(start_index % w, start_index / w), start_index);
  while (!open_.Empty()) {
    const int i = open_.Pop().index;
    // Lazy deletion: a cell re-pushed with a better g is closed by then.
    if (st[i].mark == closed) continue;
    st[i].mark = closed;
    ++expansions_;
    if (i == goal_index) return true;
    const int64_t g = st[i].g;
    const int x = i % w, y = i / w;
    // From a cell that is itself not traversable (only reachable as the start
    // or by escape steps from it) the search may step onto non-lethal
    // non-traversable cells too, so a start inside the inflated band is not a
    // dead end; once on a traversable cell the normal rule applies again.
    const bool escaping = straight_cost_[data[i]] < 0;
    const int64_t* straight = escaping ? escape_or_normal_straight_ : straight_cost_;
    const int64_t* diagonal = escaping ? escape_or_normal_diagonal_ : diagonal_cost_;
    const bool inside[4] = {x + 1 < w, x > 0, y + 1 < h, y > 0};
    bool passable[4];
    for (int d = 0; d < 8; ++d) {
      int64_t step;
      if (d < 4) {
        passable[d] = false;
        if (!inside[d]) continue;
        step = straight[data[i + offset[d]]];
        if (step < 0) continue;
        passable[d] = true;
      } else {
        if (!passable[kSideA[d]] || !passable[kSideB[d]]) continue;
        step = diagonal[data[i + offset[d]]];
        if (step < 0) continue;
      }
      CellState& n = st[i + offset[d]];
      if (n.mark == closed) continue;
      const int64_t ng = g + step;
      if (n.mark == open && ng >= n.g) continue;
      n.g = ng;
      n.parent = static_cast<uint8_t>(d);
      n.mark = open;
      open_.Push(static_cast<uint64_t>(ng + heuristic(x + kDx[d], y + kDy[d])),
                 i + offset[d]);
    }
  }
  return false;
}

void AStarPlanner::TraceBack(const Costmap2D& costmap, int start_index,
                             int index, std::vector<int>* cells) const {
  const int w = costmap.size_x();
  cells->clear();
  cells->push_back(index);
  while (index != start_index) {
    const int d = state_[index].parent;
    index -= kDy[d] * w + kDx[d];
    cells->push_back(index);
  }
  std::reverse(cells->begin(), cells->end());
}

Path AStarPlanner::MakePlan(const Costmap2D& costmap, const Pose2& start,
                            const Pose2& goal) {
  const PlanEndpoints ep = ResolveEndpoints(costmap, start, goal, options_);
  const int w = costmap.size_x();
  const int start_index = costmap.Index(ep.start_mx, ep.start_my);
  int target = costmap.Index(ep.goal_cells[0].first, ep.goal_cells[0].second);
  bool found = Search(costmap, start_index, target);
  if (!found && ep.goal_substituted) {
    // The failed search closed every cell reachable from the start.
    for (const auto& c : ep.goal_cells) {
      const int idx = costmap.Index(c.first, c.second);
      if (state_[idx].mark == open_mark_ + 1) {
        target = idx;
        found = true;
        break;
      }
    }
  }
  if (!found) {
    int gx = 0, gy = 0;
    costmap.WorldToMap(goal.x, goal.y, &gx, &gy);
    throw PlanningError(
        PlanningError::Code::kNoPath,
        "no path from start " + FormatXY(start.x, start.y) + " " +
            CellText(ep.start_mx, ep.start_my) + " to goal " +
            FormatXY(goal.x, goal.y) + " " + CellText(gx, gy) +
            (ep.goal_substituted
                 ? " (nor to any traversable cell within default_tolerance)"
                 : "") +
            ": the " + std::to_string(expansions_) +
            " cells reachable from the start do not include it");
  }
  TraceBack(costmap, start_index, target, &cells_);

  Pose2 end = goal;
  if (ep.goal_substituted) {
    costmap.MapToWorld(target % w, target / w, &end.x, &end.y);
  }
  raw_path_.clear();
  raw_path_.reserve(cells_.size() + 1);
  for (int idx : cells_) {
    Point2 p;
    costmap.MapToWorld(idx % w, idx / w, &p.x, &p.y);
    raw_path_.push_back(p);
  }
  raw_path_.front() = {start.x, start.y};
  if (raw_path_.size() == 1) {
    if (start.x != end.x || start.y != end.y) raw_path_.push_back({end.x, end.y});
  } else {
    raw_path_.back() = {end.x, end.y};
  }

  if (!options_.smooth_path) {
    return MakePathPoses(raw_path_, start.yaw, end, options_.orientation_mode);
  }
  const std::vector<Point2> smooth = ResamplePolyline(
      ShortcutPath(costmap, raw_path_, options_), costmap.resolution());
  return MakePathPoses(smooth, start.yaw, end, options_.orientation_mode);
}

}  // namespace nav
}  // namespace minibot3d_navigation
