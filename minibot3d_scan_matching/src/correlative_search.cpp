#include "minibot3d_scan_matching/correlative_search.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace minibot3d_scan_matching {

namespace {

thread_local CorrelativeSearch::Stats last_stats;

[[noreturn]] void Fail(const std::string& name, double value, const std::string& range) {
  std::ostringstream out;
  out << "correlative search: " << name << " = " << value << " is out of range: " << range;
  throw std::invalid_argument(out.str());
}

int CeilDiv(double window, double step) {
  return static_cast<int>(std::ceil(window / step - 1e-9));
}

}  // namespace

void CheckCorrelativeSearchOptions(const CorrelativeSearchOptions& o) {
  // NaN fails every comparison below, so each check is written as "not (valid)".
  if (!(o.linear_search_window > 0.0)) {
    Fail("linear_search_window", o.linear_search_window,
         "must be > 0 m, or CorrelativeSearchOptions::kWholeMap (infinity) for the whole map");
  }
  if (!(o.angular_search_window >= 0.0) || std::isinf(o.angular_search_window)) {
    Fail("angular_search_window", o.angular_search_window,
         "must be >= 0 rad and finite (>= pi searches the full circle)");
  }
  if (!(o.angular_step >= 0.0 && o.angular_step <= M_PI)) {
    Fail("angular_step", o.angular_step,
         "must be in [0, pi] rad (0 derives it from the scan's farthest endpoint)");
  }
  if (!(o.branch_and_bound_depth >= 1 && o.branch_and_bound_depth <= 16)) {
    Fail("branch_and_bound_depth", o.branch_and_bound_depth, "must be in [1, 16]");
  }
  if (!(o.min_score >= 0.0 && o.min_score <= 1.0)) {
    Fail("min_score", o.min_score, "must be in [0, 1] (a mean occupancy probability)");
  }
  if (!(o.max_candidates >= 1)) Fail("max_candidates", o.max_candidates, "must be >= 1");
  if (!(o.min_separation_linear >= 0.0) || std::isinf(o.min_separation_linear)) {
    Fail("min_separation_linear", o.min_separation_linear, "must be >= 0 m and finite");
  }
  if (!(o.min_separation_angular >= 0.0) || std::isinf(o.min_separation_angular)) {
    Fail("min_separation_angular", o.min_separation_angular,
         "must be >= 0 rad and finite (>= pi: any heading at one place is the same place)");
  }
  if (!(o.min_relative_score >= 0.0 && o.min_relative_score <= 1.0)) {
    Fail("min_relative_score", o.min_relative_score, "must be in [0, 1] (a fraction of the best)");
  }
  if (!(o.blur_sigma >= 0.0 && o.blur_sigma <= 1.0)) {
    Fail("blur_sigma", o.blur_sigma, "must be in [0, 1] m (0 scores the cells as they are)");
  }
  if (!(o.unknown_probability >= 0.0 && o.unknown_probability <= 1.0)) {
    Fail("unknown_probability", o.unknown_probability, "must be in [0, 1]");
  }
}

std::vector<Eigen::Vector2d> ScanToPoints(const LaserScan& scan, double max_range) {
  std::vector<Eigen::Vector2d> points;
  if (scan.angles.size() != scan.ranges.size()) {
    throw std::invalid_argument("ScanToPoints: scan has " + std::to_string(scan.ranges.size()) +
                                " ranges but " + std::to_string(scan.angles.size()) + " angles");
  }
  const double limit = std::min(scan.range_max, max_range);
  const Pose2& s = scan.sensor_in_base;
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  points.reserve(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || !(r > scan.range_min) || !(r < limit)) continue;
    const double x = r * std::cos(scan.angles[i]), y = r * std::sin(scan.angles[i]);
    points.emplace_back(s.x + c * x - sn * y, s.y + sn * x + c * y);
  }
  return points;
}

// The search lattice for one scan: the angles, each with the scan's endpoints rotated into integer
// cells relative to the initial position, and the range of whole-cell translations.
struct CorrelativeSearch::Lattice {
  // An endpoint's cell at one angle; endpoints sharing a cell at that angle share it at every
  // level and translation, so they are merged and weighted.
  struct Endpoint {
    int x, y, weight;
  };
  int num_points = 0;
  std::vector<double> angles;       // headings in the grid frame
  std::vector<Endpoint> endpoints;  // endpoints of angle a: [begin[a], begin[a + 1])
  std::vector<int> begin;
  double x0 = 0.0, y0 = 0.0;   // initial position in the grid frame (m)
  int imin = 0, imax = -1, jmin = 0, jmax = -1;  // translations (cells), inclusive
  int need = 0;                // min_score as an integer sum of per-cent probabilities

  bool empty() const { return angles.empty() || imin > imax || jmin > jmax || num_points == 0; }
};

struct CorrelativeSearch::Candidate {
  int angle = 0, i = 0, j = 0;
  int score = 0;  // sum of per-cent probabilities: a bound above height 0, exact at height 0
};

CorrelativeSearch::CorrelativeSearch(const GridMap& map, const CorrelativeSearchOptions& options) {
  CheckCorrelativeSearchOptions(options);
  if (map.width <= 0 || map.height <= 0 ||
      map.data.size() != static_cast<std::size_t>(map.width) * map.height) {
    throw std::invalid_argument("correlative search: the map is empty or its data (" +
                                std::to_string(map.data.size()) + " cells) does not match " +
                                std::to_string(map.width) + " x " + std::to_string(map.height));
  }
  if (!(map.resolution > 0.0)) {
    throw std::invalid_argument("correlative search: map resolution must be > 0");
  }
  map_ = map;
  map_.data.clear();
  map_.data.shrink_to_fit();
  unknown_ = static_cast<std::uint8_t>(std::lround(options.unknown_probability * 100.0));

  const int w = map.width, h = map.height;
  std::vector<float> p(map.data.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    const int v = map.data[k];
    p[k] = v < 0 ? static_cast<float>(options.unknown_probability)
                 : static_cast<float>(std::min(v, 100)) / 100.0f;
  }
  if (options.blur_sigma > 0.0) {
    // max over neighbours of p · exp(−d² / 2σ²): the kernel is a product of an x and a y factor,
    // so the max can be taken along rows, then along columns.
    const int radius = static_cast<int>(std::ceil(3.0 * options.blur_sigma / map.resolution));
    std::vector<float> weight(radius + 1);
    for (int d = 0; d <= radius; ++d) {
      const double m = d * map.resolution / options.blur_sigma;
      weight[d] = static_cast<float>(std::exp(-0.5 * m * m));
    }
    std::vector<float> rows(p.size());
    for (int y = 0; y < h; ++y) {
      const float* in = p.data() + static_cast<std::size_t>(y) * w;
      float* out = rows.data() + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < w; ++x) {
        float m = in[x];
        for (int d = 1; d <= radius; ++d) {
          if (x - d >= 0) m = std::max(m, in[x - d] * weight[d]);
          if (x + d < w) m = std::max(m, in[x + d] * weight[d]);
        }
        out[x] = m;
      }
    }
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const float* column = rows.data() + x;
        float m = column[static_cast<std::size_t>(y) * w];
        for (int d = 1; d <= radius; ++d) {
          if (y - d >= 0) m = std::max(m, column[static_cast<std::size_t>(y - d) * w] * weight[d]);
          if (y + d < h) m = std::max(m, column[static_cast<std::size_t>(y + d) * w] * weight[d]);
        }
        p[static_cast<std::size_t>(y) * w + x] = m;
      }
    }
  }
  levels_.resize(options.branch_and_bound_depth);
  Level& base = levels_[0];
  base.pad = 0;
  base.stride = w;
  base.cells.resize(p.size());
  max_value_ = unknown_;
  for (std::size_t k = 0; k < p.size(); ++k) {
    base.cells[k] = static_cast<std::uint8_t>(std::lround(std::min(1.0f, p[k]) * 100.0f));
    max_value_ = std::max<int>(max_value_, base.cells[k]);
  }
  // Level l from level l−1: the max over [x, x + 2^l) is the max of the two halves' maxima.
  for (int l = 1; l < options.branch_and_bound_depth; ++l) {
    const Level& prev = levels_[l - 1];
    Level& level = levels_[l];
    const int half = 1 << (l - 1);
    level.pad = (1 << l) - 1;
    level.stride = w + level.pad;
    const int rows = h + level.pad;
    level.cells.resize(static_cast<std::size_t>(level.stride) * rows);
    for (int gy = 0; gy < rows; ++gy) {
      const int y = gy - level.pad;
      for (int gx = 0; gx < level.stride; ++gx) {
        const int x = gx - level.pad;
        level.cells[static_cast<std::size_t>(gy) * level.stride + gx] =
            std::max(std::max(At(prev, x, y), At(prev, x + half, y)),
                     std::max(At(prev, x, y + half), At(prev, x + half, y + half)));
      }
    }
  }
}

CorrelativeSearch::Stats CorrelativeSearch::LastStats() { return last_stats; }

CorrelativeSearch::Lattice CorrelativeSearch::MakeLattice(
    const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
    const CorrelativeSearchOptions& options) const {
  CheckCorrelativeSearchOptions(options);
  if (options.branch_and_bound_depth > depth()) {
    Fail("branch_and_bound_depth", options.branch_and_bound_depth,
         "must be <= " + std::to_string(depth()) +
             ", the depth the CorrelativeSearch was built with");
  }
  Lattice lattice;
  lattice.num_points = static_cast<int>(points.size());
  if (points.empty()) return lattice;
  const double r = map_.resolution;
  const Pose2 origin{map_.origin_x, map_.origin_y, map_.origin_theta};
  const Pose2 g = Between(origin, initial);  // the initial pose in the grid frame
  lattice.x0 = g.x;
  lattice.y0 = g.y;

  double step = options.angular_step;
  if (step == 0.0) {
    double d = 0.0;
    for (const Eigen::Vector2d& p : points) d = std::max(d, p.norm());
    step = d > 0.0 ? std::acos(std::max(-1.0, 1.0 - r * r / (2.0 * d * d))) : M_PI;
  }
  if (options.angular_search_window >= M_PI) {
    const int n = std::max(1, CeilDiv(2.0 * M_PI, step));
    for (int k = 0; k < n; ++k) lattice.angles.push_back(g.yaw + 2.0 * M_PI * k / n);
  } else {
    const int n = CeilDiv(options.angular_search_window, step);
    for (int k = -n; k <= n; ++k) lattice.angles.push_back(g.yaw + k * step);
  }

  // Translations (i, j) put the robot at (x0 + i·r, y0 + j·r); keep it on the map.
  const double cx = g.x / r, cy = g.y / r;
  lattice.imin = static_cast<int>(std::ceil(-cx));
  lattice.imax = static_cast<int>(std::ceil(map_.width - cx)) - 1;
  lattice.jmin = static_cast<int>(std::ceil(-cy));
  lattice.jmax = static_cast<int>(std::ceil(map_.height - cy)) - 1;
  if (std::isfinite(options.linear_search_window)) {
    const int n = CeilDiv(options.linear_search_window, r);
    lattice.imin = std::max(lattice.imin, -n);
    lattice.imax = std::min(lattice.imax, n);
    lattice.jmin = std::max(lattice.jmin, -n);
    lattice.jmax = std::min(lattice.jmax, n);
  }

  // Endpoints in bit-reversed order, so that any prefix is spread over the whole scan: a node that
  // cannot reach the bound shows it after a few endpoints (ScoreNode stops there), where in beam
  // order a whole wall that matches would come first.
  const int n = lattice.num_points;
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  std::vector<int> order;
  order.reserve(n);
  for (int k = 0; k < (1 << bits); ++k) {
    int rev = 0;
    for (int b = 0; b < bits; ++b) rev |= ((k >> b) & 1) << (bits - 1 - b);
    if (rev < n) order.push_back(rev);
  }
  struct Cell {
    int x, y, first;
  };
  std::vector<Cell> cells(n);
  lattice.begin.reserve(lattice.angles.size() + 1);
  lattice.endpoints.reserve(lattice.angles.size() * n);
  for (std::size_t a = 0; a < lattice.angles.size(); ++a) {
    const double c = std::cos(lattice.angles[a]), s = std::sin(lattice.angles[a]);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d& p = points[order[k]];
      cells[k] = {static_cast<int>(std::floor((c * p.x() - s * p.y() + g.x) / r)),
                  static_cast<int>(std::floor((s * p.x() + c * p.y() + g.y) / r)), k};
    }
    std::sort(cells.begin(), cells.end(), [](const Cell& u, const Cell& v) {
      return u.x != v.x ? u.x < v.x : u.y != v.y ? u.y < v.y : u.first < v.first;
    });
    const std::size_t start = lattice.endpoints.size();
    std::vector<std::pair<int, Lattice::Endpoint>> merged;
    for (int k = 0; k < n;) {
      int m = k;
      while (m < n && cells[m].x == cells[k].x && cells[m].y == cells[k].y) ++m;
      merged.push_back({cells[k].first, {cells[k].x, cells[k].y, m - k}});
      k = m;
    }
    std::sort(merged.begin(), merged.end(),
              [](const auto& u, const auto& v) { return u.first < v.first; });
    lattice.begin.push_back(static_cast<int>(start));
    for (const auto& e : merged) lattice.endpoints.push_back(e.second);
  }
  lattice.begin.push_back(static_cast<int>(lattice.endpoints.size()));
  lattice.need = static_cast<int>(std::ceil(options.min_score * 100.0 * n - 1e-6));
  return lattice;
}

// Depth-first branch and bound over one lattice. Accepting a leaf raises need_, the sum a node's
// bound must reach to be worth visiting.
class CorrelativeSearch::Searcher {
 public:
  Searcher(const CorrelativeSearch& grids, const Lattice& lattice,
           const CorrelativeSearchOptions& options, int max_kept, int need)
      : grids_(grids), lattice_(lattice), options_(options), max_kept_(max_kept), need_(need) {}

  // Two passes over the angles, each scoring every top-height node of its angles, then visiting
  // them best first. The first pass takes every kAngleStride-th angle: its best leaf is usually at
  // or next to the right place, and raises need_ before the second pass over the other angles,
  // where ScoreNode then gives up on most top nodes after a few endpoints. Each pass is an exact
  // branch and bound over its angles, so together they are one over all.
  void Run() {
    const int num_angles = static_cast<int>(lattice_.angles.size());
    std::vector<int> first, second;
    for (int a = 0; a < num_angles; ++a) {
      (num_angles >= 2 * kAngleStride && a % kAngleStride == 0 ? first : second).push_back(a);
    }
    Pass(first);
    Pass(second);
    stats_.angles = num_angles;
  }

  const Stats& stats() const { return stats_; }

  const std::vector<Candidate>& kept() const { return kept_; }

 private:
  static constexpr int kAngleStride = 8;

  void Pass(const std::vector<int>& angles) {
    const int top = options_.branch_and_bound_depth - 1;
    const int w = 1 << top;
    std::vector<Candidate> candidates;
    const std::int64_t lookups = stats_.lookups;
    for (int a : angles) {
      for (int j = lattice_.jmin; j <= lattice_.jmax; j += w) {
        for (int i = lattice_.imin; i <= lattice_.imax; i += w) {
          const int score = ScoreNode(top, a, i, j);
          ++stats_.top_nodes;
          if (score >= need_) candidates.push_back({a, i, j, score});
        }
      }
    }
    stats_.top_lookups += stats_.lookups - lookups;
    std::stable_sort(candidates.begin(), candidates.end(), Better);
    for (const Candidate& c : candidates) {
      if (c.score < need_) break;
      Visit(c, top);
    }
  }

  static bool Better(const Candidate& a, const Candidate& b) { return a.score > b.score; }

  // The node's bound, or -1 as soon as it cannot reach need_.
  int ScoreNode(int height, int angle, int i, int j) {
    ++stats_.nodes_scored;
    const Level& level = grids_.levels_[height];
    const Lattice::Endpoint* e = lattice_.endpoints.data() + lattice_.begin[angle];
    const int n = lattice_.begin[angle + 1] - lattice_.begin[angle];
    const unsigned width = static_cast<unsigned>(level.stride);
    const unsigned rows = static_cast<unsigned>(grids_.map_.height + level.pad);
    const int dx = i + level.pad, dy = j + level.pad;
    const std::uint8_t* data = level.cells.data();
    const std::uint8_t unknown = grids_.unknown_;
    int sum = 0;
    int ceiling = max_value_ * lattice_.num_points;  // sum + max_value_ · (endpoints left)
    for (int k = 0; k < n; ++k) {
      const unsigned gx = static_cast<unsigned>(e[k].x + dx);
      const unsigned gy = static_cast<unsigned>(e[k].y + dy);
      const int v = (gx < width && gy < rows) ? data[static_cast<std::size_t>(gy) * width + gx]
                                              : unknown;
      sum += e[k].weight * v;
      ceiling -= e[k].weight * (max_value_ - v);
      if (ceiling < need_) {
        stats_.lookups += k + 1;
        return -1;
      }
    }
    stats_.lookups += n;
    return sum;
  }

  void Visit(const Candidate& c, int height) {
    if (c.score < need_) return;
    if (height == 0) {
      Accept(c);
      return;
    }
    const int h = height - 1, w = 1 << h;
    Candidate children[4];
    int count = 0;
    for (int dj = 0; dj <= w; dj += w) {
      const int j = c.j + dj;
      if (j > lattice_.jmax) break;
      for (int di = 0; di <= w; di += w) {
        const int i = c.i + di;
        if (i > lattice_.imax) break;
        const int score = ScoreNode(h, c.angle, i, j);
        if (score >= need_) children[count++] = {c.angle, i, j, score};
      }
    }
    // Best first; an insertion sort keeps equal bounds in (y, x) order, as stable_sort would.
    for (int k = 1; k < count; ++k) {
      for (int m = k; m > 0 && Better(children[m], children[m - 1]); --m) {
        std::swap(children[m], children[m - 1]);
      }
    }
    for (int k = 0; k < count; ++k) Visit(children[k], h);
  }

  Pose2 GridPose(const Candidate& c) const {
    const double r = grids_.map_.resolution;
    return Pose2{lattice_.x0 + c.i * r, lattice_.y0 + c.j * r, lattice_.angles[c.angle]};
  }

  bool SamePlace(const Candidate& a, const Candidate& b) const {
    const Pose2 pa = GridPose(a), pb = GridPose(b);
    if (std::hypot(pa.x - pb.x, pa.y - pb.y) >= options_.min_separation_linear) return false;
    return options_.min_separation_angular >= M_PI ||
           std::fabs(NormalizeAngle(pa.yaw - pb.yaw)) < options_.min_separation_angular;
  }

  void Accept(const Candidate& c) {
    ++stats_.leaves;
    if (max_kept_ == 1) {
      kept_.assign(1, c);
      need_ = c.score + 1;
      return;
    }
    for (const Candidate& k : kept_) {
      if (k.score >= c.score && SamePlace(k, c)) return;
    }
    kept_.erase(std::remove_if(kept_.begin(), kept_.end(),
                               [&](const Candidate& k) { return SamePlace(k, c); }),
                kept_.end());
    kept_.insert(std::upper_bound(kept_.begin(), kept_.end(), c, Better), c);
    if (static_cast<int>(kept_.size()) > max_kept_) kept_.pop_back();
    if (static_cast<int>(kept_.size()) == max_kept_) need_ = kept_.back().score + 1;
  }

  const CorrelativeSearch& grids_;
  const Lattice& lattice_;
  const CorrelativeSearchOptions& options_;
  const int max_kept_;
  int need_;
  const int max_value_ = grids_.max_value_;
  std::vector<Candidate> kept_;
  Stats stats_;
};

std::vector<CorrelativeMatch> CorrelativeSearch::SearchAll(
    const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
    const CorrelativeSearchOptions& options) const {
  return SearchKept(points, initial, options, options.max_candidates);
}

std::optional<CorrelativeMatch> CorrelativeSearch::Search(
    const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
    const CorrelativeSearchOptions& options) const {
  const std::vector<CorrelativeMatch> best = SearchKept(points, initial, options, 1);
  if (best.empty()) return std::nullopt;
  return best.front();
}

std::vector<CorrelativeMatch> CorrelativeSearch::SearchKept(
    const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
    const CorrelativeSearchOptions& options, int max_kept) const {
  const Lattice lattice = MakeLattice(points, initial, options);
  std::vector<CorrelativeMatch> out;
  last_stats = Stats();
  if (lattice.empty()) return out;
  int need = lattice.need;
  if (max_kept > 1 && options.min_relative_score > 0.0) {
    // The best first (a search with a high bound is quick), then the others it makes relevant.
    Searcher best(*this, lattice, options, 1, need);
    best.Run();
    last_stats = best.stats();
    if (best.kept().empty()) return out;
    need = std::max(need, static_cast<int>(std::ceil(options.min_relative_score *
                                                     best.kept().front().score - 1e-6)));
  }
  Searcher searcher(*this, lattice, options, max_kept, need);
  searcher.Run();
  const Stats& s = searcher.stats();
  last_stats.angles = s.angles;
  last_stats.top_nodes += s.top_nodes;
  last_stats.nodes_scored += s.nodes_scored;
  last_stats.leaves += s.leaves;
  last_stats.lookups += s.lookups;
  last_stats.top_lookups += s.top_lookups;
  const Pose2 origin{map_.origin_x, map_.origin_y, map_.origin_theta};
  const double r = map_.resolution;
  for (const Candidate& c : searcher.kept()) {
    const Pose2 g{lattice.x0 + c.i * r, lattice.y0 + c.j * r, lattice.angles[c.angle]};
    out.push_back({Compose(origin, g), c.score / (100.0 * lattice.num_points)});
  }
  return out;
}

std::optional<CorrelativeMatch> CorrelativeSearch::BruteForceSearch(
    const std::vector<Eigen::Vector2d>& points, const Pose2& initial,
    const CorrelativeSearchOptions& options) const {
  const Lattice lattice = MakeLattice(points, initial, options);
  if (lattice.empty()) return std::nullopt;
  const Level& level = levels_[0];
  int best = -1, best_a = 0, best_i = 0, best_j = 0;
  for (int a = 0; a < static_cast<int>(lattice.angles.size()); ++a) {
    // Every endpoint on its own (not the merged ones) to check the merging too.
    const double c = std::cos(lattice.angles[a]), s = std::sin(lattice.angles[a]);
    const double r = map_.resolution;
    std::vector<std::pair<int, int>> cells;
    for (const Eigen::Vector2d& p : points) {
      cells.emplace_back(static_cast<int>(std::floor((c * p.x() - s * p.y() + lattice.x0) / r)),
                         static_cast<int>(std::floor((s * p.x() + c * p.y() + lattice.y0) / r)));
    }
    for (int j = lattice.jmin; j <= lattice.jmax; ++j) {
      for (int i = lattice.imin; i <= lattice.imax; ++i) {
        int sum = 0;
        for (const auto& cell : cells) sum += At(level, cell.first + i, cell.second + j);
        if (sum >= lattice.need && sum > best) {
          best = sum;
          best_a = a;
          best_i = i;
          best_j = j;
        }
      }
    }
  }
  if (best < 0) return std::nullopt;
  const double r = map_.resolution;
  const Pose2 origin{map_.origin_x, map_.origin_y, map_.origin_theta};
  const Pose2 g{lattice.x0 + best_i * r, lattice.y0 + best_j * r, lattice.angles[best_a]};
  return CorrelativeMatch{Compose(origin, g), best / (100.0 * lattice.num_points)};
}

double CorrelativeSearch::Score(const std::vector<Eigen::Vector2d>& points,
                                const Pose2& pose) const {
  if (points.empty()) return 0.0;
  const Pose2 g = Between(Pose2{map_.origin_x, map_.origin_y, map_.origin_theta}, pose);
  const double c = std::cos(g.yaw), s = std::sin(g.yaw), r = map_.resolution;
  int sum = 0;
  for (const Eigen::Vector2d& p : points) {
    const int x = static_cast<int>(std::floor((c * p.x() - s * p.y() + g.x) / r));
    const int y = static_cast<int>(std::floor((s * p.x() + c * p.y() + g.y) / r));
    sum += At(levels_[0], x, y);
  }
  return sum / (100.0 * points.size());
}

}  // namespace minibot3d_scan_matching
