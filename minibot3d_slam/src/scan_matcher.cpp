// gmapping-style scan matcher and improved proposal (see scan_matcher.h).
#include "scan_matcher.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace minibot3d_slam {

namespace {
// gmapping's log-likelihood of a beam without any admissible hit, in units of 1/lsigma.
constexpr double kNoMatchLikelihood = -0.5;

// exp(-x) for x >= 0 by linear interpolation in a table (relative error < 2e-6 where it matters):
// the matching score calls it once per beam and pose, and libm's exp was ~10 % of the run time.
class NegExpTable {
 public:
  static constexpr double kMax = 20.0;   // exp(-20) ≈ 2e-9: treated as 0 beyond
  static constexpr int kPerUnit = 256;
  NegExpTable() {
    for (int i = 0; i <= kSize; ++i) table_[i] = std::exp(-static_cast<double>(i) / kPerUnit);
  }
  double operator()(double x) const {
    if (!(x < kMax)) return 0.0;
    const double f = x * kPerUnit;
    const int i = static_cast<int>(f);
    const double t = f - i;
    return table_[i] + t * (table_[i + 1] - table_[i]);
  }

 private:
  static constexpr int kSize = static_cast<int>(kMax * kPerUnit) + 1;
  double table_[kSize + 1];
};

// Stands in for unallocated tiles.
const Grid::Tile kUnknownTile{};

const NegExpTable& NegExp() {
  static const NegExpTable table;
  return table;
}

}  // namespace

// The hill climber and the proposal sampler evaluate many poses that share an orientation and
// differ by a fraction of a cell to a cell, so most beams end in the same or a neighbouring cell
// again. Whether a cell is an admissible match for a beam depends only on the map, the cell and the
// beam direction — not on where the endpoint fell — so it is worked out once per cell, beam and
// orientation and remembered: a window seen before only measures distances to its admissible cells,
// a window moved by a cell tests only the cells it newly covers. The result is bit-identical to
// evaluating every window afresh.
//
// Per beam the cache holds an 8×8 patch of cells around the endpoint as two bitmasks (row-major from
// the patch's lower-left cell: admissibility known, admissible); when a window leaves the patch the
// patch is re-centred and forgotten. Patches are kept for a few orientations (the exact θ of the
// sensor pose; least recently used replaced): the climber's current θ and its ±astep candidates, the
// proposal's three θ.
class ScanMatcher::WindowCache {
 public:
  struct Patch {
    int x0, y0;                // lower-left cell
    std::uint64_t known;       // bit (y - y0) · 8 + (x - x0): admissibility worked out
    std::uint64_t admissible;  // … and the cell is an admissible match
  };
  static constexpr int kSide = 8;
  static constexpr int kSlots = 4;

  // The window must fit in a patch.
  static bool Usable(int kernel_size) { return 2 * kernel_size + 1 <= kSide; }

  explicit WindowCache(std::size_t beams) : beams_(beams), patches_(kSlots * beams) {}

  // The patches (one per beam) for sensor orientation `theta`.
  Patch* Slot(double theta) {
    ++clock_;
    int victim = 0;
    for (int i = 0; i < kSlots; ++i) {
      if (used_[i] != 0 && theta_[i] == theta) {
        used_[i] = clock_;
        return &patches_[i * beams_];
      }
      if (used_[i] < used_[victim]) victim = i;
    }
    theta_[victim] = theta;
    used_[victim] = clock_;
    Patch* p = &patches_[victim * beams_];
    for (std::size_t j = 0; j < beams_; ++j) p[j] = Patch{0, 0, 0, 0};
    return p;
  }

 private:
  std::size_t beams_;
  std::vector<Patch> patches_;
  double theta_[kSlots] = {};
  std::uint64_t used_[kSlots] = {};  // 0: slot unused; else the clock_ of the last use
  std::uint64_t clock_ = 0;
};

ScanMatcher::ScanMatcher(const GmappingOptions& options)
    : options_(options), free_back_(options.delta * std::sqrt(2.0)) {
  const int w = 2 * options.kernelSize + 1;
  if (WindowCache::Usable(options.kernelSize)) {
    for (int row = 0; row < w; ++row) window_mask_ |= ((std::uint64_t{1} << w) - 1) << (row * WindowCache::kSide);
  }
}

PreparedScan ScanMatcher::Prepare(const LaserScan& scan) const {
  PreparedScan out;
  out.sensor_in_base = scan.sensor_in_base;
  const std::size_t n = std::min(scan.ranges.size(), scan.angles.size());
  const double range_min = std::max(scan.range_min, 0.0);
  const double sensor_max = scan.range_max > 0.0 ? scan.range_max : std::numeric_limits<double>::infinity();
  const double max_range = options_.maxRange > 0.0 ? std::min(options_.maxRange, sensor_max) : sensor_max;
  out.map_range.reserve(n);
  out.map_cos.reserve(n);
  out.map_sin.reserve(n);
  out.map_hit.reserve(n);
  out.map_beam.reserve(n);
  int skip = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = scan.ranges[i];
    // No-returns (NaN, ±inf, at or below range_min, at or beyond the maximum range) carry no
    // information about where free space ends, so they update nothing (as gmapping skips readings
    // beyond maxRange) — except, with clearMaxRange, +inf and readings at or beyond the maximum
    // range: nothing is there within the sensor's reach, so the beam clears free space out to
    // maxUrange (and the maximum range) like a reading beyond maxUrange.
    const bool beyond = r == std::numeric_limits<double>::infinity() || (std::isfinite(r) && r >= max_range);
    const bool clear_only = beyond && options_.clearMaxRange != 0;
    if (!clear_only && (!std::isfinite(r) || r <= range_min || r >= max_range)) continue;
    const double a = scan.angles[i];
    if (!std::isfinite(a)) continue;
    const double ca = std::cos(a), sa = std::sin(a);
    const bool hit = !clear_only && r <= options_.maxUrange;
    out.map_range.push_back(hit ? r : std::min(options_.maxUrange, max_range));
    out.map_cos.push_back(ca);
    out.map_sin.push_back(sa);
    out.map_hit.push_back(hit ? 1 : 0);
    out.map_beam.push_back(static_cast<std::uint32_t>(i));
    if (!hit) continue;
    if (skip == 0) {
      out.match_range.push_back(r);
      out.match_cos.push_back(ca);
      out.match_sin.push_back(sa);
    }
    skip = skip >= options_.lskip ? 0 : skip + 1;
  }
  return out;
}

template <class F>
void ScanMatcher::ForEachBeam(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                              WindowCache* cache, F&& f) const {
  const Pose2 lp = Compose(pose, scan.sensor_in_base);
  const double c = std::cos(lp.yaw), s = std::sin(lp.yaw);
  const int k = options_.kernelSize;
  const bool patches = WindowCache::Usable(k);
  constexpr int kSide = WindowCache::kSide;
  const std::size_t n = scan.match_range.size();
  constexpr double kNone = std::numeric_limits<double>::infinity();
  WindowCache::Patch* slot = cache != nullptr ? cache->Slot(lp.yaw) : nullptr;
  int last_tx = 0, last_ty = 0;
  const Grid::Tile* last_tile = nullptr;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = c * scan.match_cos[i] - s * scan.match_sin[i];
    const double dy = s * scan.match_cos[i] + c * scan.match_sin[i];
    const double r = scan.match_range[i];
    const double px = lp.x + r * dx, py = lp.y + r * dy;
    const int ix = grid.CellX(px), iy = grid.CellY(py);
    const double bx = free_back_ * dx, by = free_back_ * dy;  // one step back along the beam

    // An occupied cell is admissible when the point one step back along the beam from its mean
    // endpoint lies in a free or unknown cell: the wall was seen from the side this beam comes
    // from. (gmapping applies the endpoint cell's back-step offset to every cell of the window,
    // which rejects or accepts cells depending on where the endpoint falls within its cell and
    // makes the score jump by whole beams for millimetre moves.) `at` reads a cell.
    auto admissible = [&](const auto& at, int cx, int cy) {
      const GridCell& cell = at(cx, cy);
      if (!cell.Occupied()) return false;
      return at(grid.CellX(grid.MeanX(cx, cell) - bx), grid.CellY(grid.MeanY(cy, cell) - by)).FreeOrUnknown();
    };
    auto d2_to = [&](const GridCell& cell, int cx, int cy) {
      const double ex = px - grid.MeanX(cx, cell), ey = py - grid.MeanY(cy, cell);
      return ex * ex + ey * ey;
    };
    // Nearest admissible mean endpoint in the window, window cells visited row by row.
    int best_cx = 0, best_cy = 0;  // the cell of the nearest admissible mean endpoint
    auto nearest = [&](const auto& at) {
      double best = kNone;
      if (!patches) {  // a kernel too wide for a patch
        for (int cy = iy - k; cy <= iy + k; ++cy) {
          for (int cx = ix - k; cx <= ix + k; ++cx) {
            if (!admissible(at, cx, cy)) continue;
            const double d2 = d2_to(at(cx, cy), cx, cy);
            if (d2 < best) {
              best = d2;
              best_cx = cx;
              best_cy = cy;
            }
          }
        }
        return best;
      }
      // The window in a patch: the beam's cached one, or a throwaway one without cache.
      WindowCache::Patch local{ix - k, iy - k, 0, 0};
      WindowCache::Patch* patch = &local;
      if (slot != nullptr) {
        patch = &slot[i];
        // Re-centred when the window leaves it (an empty patch may sit anywhere).
        const unsigned room = static_cast<unsigned>(kSide - (2 * k + 1));
        if (static_cast<unsigned>(ix - k - patch->x0) > room || static_cast<unsigned>(iy - k - patch->y0) > room) {
          *patch = WindowCache::Patch{ix - kSide / 2, iy - kSide / 2, 0, 0};
        }
      }
      const std::uint64_t window = window_mask_ << ((iy - k - patch->y0) * kSide + (ix - k - patch->x0));
      for (std::uint64_t todo = window & ~patch->known; todo != 0; todo &= todo - 1) {
        const int b = __builtin_ctzll(todo);
        if (admissible(at, patch->x0 + (b & (kSide - 1)), patch->y0 + b / kSide)) {
          patch->admissible |= std::uint64_t{1} << b;
        }
      }
      patch->known |= window;
      for (std::uint64_t m = patch->admissible & window; m != 0; m &= m - 1) {
        const int b = __builtin_ctzll(m);
        const int cx = patch->x0 + (b & (kSide - 1)), cy = patch->y0 + b / kSide;
        const double d2 = d2_to(at(cx, cy), cx, cy);
        if (d2 < best) {
          best = d2;
          best_cx = cx;
          best_cy = cy;
        }
      }
      return best;
    };

    // Most windows lie, with every back-step partner, in one tile: the tile is then looked up once
    // and its cells addressed directly.
    constexpr int kReach = 2;  // the back step (√2 cells from a point in the cell) stays within 2
    const int lx = ix & Grid::kTileMask, ly = iy & Grid::kTileMask;
    double best = kNone;
    if (lx - k - kReach >= 0 && lx + k + kReach < Grid::kTileSize && ly - k - kReach >= 0 &&
        ly + k + kReach < Grid::kTileSize) {
      const int tx = ix >> Grid::kTileBits, ty = iy >> Grid::kTileBits;
      if (tx != last_tx || ty != last_ty || last_tile == nullptr) {  // neighbouring beams share tiles
        last_tile = grid.TileAt(tx, ty);
        if (last_tile == nullptr) last_tile = &kUnknownTile;  // unallocated: all unknown
        last_tx = tx;
        last_ty = ty;
      }
      const Grid::Tile* tile = last_tile;
      best = nearest([tile](int cx, int cy) -> const GridCell& {
        return tile->cells[((cy & Grid::kTileMask) << Grid::kTileBits) | (cx & Grid::kTileMask)];
      });
    } else {
      best = nearest([&grid](int cx, int cy) -> const GridCell& { return grid.At(cx, cy); });
    }
    if (best == kNone) {
      f(-1.0, BeamMatch{});
    } else {
      f(best, BeamMatch{px, py, best_cx, best_cy});
    }
  }
}

double ScanMatcher::Score(const Grid& grid, const PreparedScan& scan, const Pose2& pose) const {
  return ScoreCached(grid, scan, pose, nullptr);
}

double ScanMatcher::ScoreCached(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                                WindowCache* cache) const {
  double score = 0.0;
  const double inv_sigma = 1.0 / options_.sigma;  // gmapping: exp(-d² / sigma)
  const NegExpTable& neg_exp = NegExp();
  ForEachBeam(grid, scan, pose, cache, [&](double d2, const BeamMatch&) {
    if (d2 >= 0.0) score += neg_exp(d2 * inv_sigma);
  });
  return score;
}

double ScanMatcher::LogLikelihood(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                                  int* matched) const {
  return LogLikelihoodCached(grid, scan, pose, nullptr, matched);
}

double ScanMatcher::LogLikelihoodCached(const Grid& grid, const PreparedScan& scan, const Pose2& pose,
                                        WindowCache* cache, int* matched) const {
  double l = 0.0;
  int found = 0;
  const double inv_lsigma = 1.0 / options_.lsigma;
  ForEachBeam(grid, scan, pose, cache, [&](double d2, const BeamMatch&) {
    if (d2 >= 0.0) {
      l -= d2 * inv_lsigma;
      ++found;
    } else {
      l += kNoMatchLikelihood * inv_lsigma;
    }
  });
  if (matched != nullptr) *matched = found;
  return l;
}

double ScanMatcher::Optimize(const Grid& grid, const PreparedScan& scan, const Pose2& initial,
                             Pose2* best) const {
  std::optional<WindowCache> cache;
  if (WindowCache::Usable(options_.kernelSize)) cache.emplace(scan.match_range.size());
  WindowCache* const cache_ptr = cache ? &*cache : nullptr;
  Pose2 current = initial;
  double current_score = ScoreCached(grid, scan, current, cache_ptr);
  double ldelta = options_.lstep, adelta = options_.astep;
  int refinements = 0;
  // The move that would undo the last improving move: its pose is the previous one, whose score is
  // known to be lower, so it is not evaluated again (same result, ~10 % fewer evaluations).
  int undo = -1;
  // Bounded for safety; every improving round raises the score, so this is never reached in
  // practice.
  for (int round = 0; round < 1000; ++round) {
    const Pose2 moves[6] = {{ldelta, 0, 0}, {-ldelta, 0, 0}, {0, ldelta, 0},
                            {0, -ldelta, 0}, {0, 0, adelta}, {0, 0, -adelta}};
    int round_move = -1;
    Pose2 round_best = current;
    double round_score = current_score;
    for (int m = 0; m < 6; ++m) {
      if (m == undo) continue;
      const Pose2 candidate{current.x + moves[m].x, current.y + moves[m].y,
                            NormalizeAngle(current.yaw + moves[m].yaw)};
      const double sc = ScoreCached(grid, scan, candidate, cache_ptr);
      if (sc > round_score) {
        round_score = sc;
        round_best = candidate;
        round_move = m;
      }
    }
    if (round_move >= 0) {
      current = round_best;
      current_score = round_score;
      undo = round_move ^ 1;  // moves come in opposite pairs (0,1), (2,3), (4,5)
    } else {
      // No neighbour improves: refine the steps, or stop after `iterations` refinements.
      if (++refinements > options_.iterations) break;
      ldelta *= 0.5;
      adelta *= 0.5;
      undo = -1;
    }
  }
  *best = current;
  return current_score;
}

Pose2 ScanMatcher::Refine(const Grid& grid, const PreparedScan& scan, const Pose2& initial) const {
  // Residual of a beam: its endpoint minus the nearest admissible mean endpoint, in world
  // coordinates; weighted by a Gaussian of one cell so that beams far from any wall (people,
  // glass, a wrong correspondence) hardly pull. Re-associated at every iteration.
  const double inv_two_s2 = 1.0 / (2.0 * options_.delta * options_.delta);
  Pose2 pose = initial;
  for (int iteration = 0; iteration < kRefineIterations; ++iteration) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    int used = 0;
    ForEachBeam(grid, scan, pose, nullptr, [&](double d2, const BeamMatch& m) {
      if (d2 < 0.0) return;
      const GridCell& cell = grid.At(m.cx, m.cy);
      const double mx = grid.MeanX(m.cx, cell), my = grid.MeanY(m.cy, cell);
      const double w = std::exp(-d2 * inv_two_s2);
      // d(endpoint)/dθ: the endpoint's offset from the base, turned by 90°.
      const double jx = -(m.py - pose.y), jy = m.px - pose.x;
      // The wall through the mean endpoint: towards the nearest occupied neighbour's mean. With
      // one, the residual is the distance to that line (point-to-line: sliding along a wall costs
      // nothing, so the spacing of the means does not pull), else to the mean itself.
      double nx = 0.0, ny = 0.0, best_n = std::numeric_limits<double>::infinity();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          const GridCell& c = grid.At(m.cx + dx, m.cy + dy);
          if (!c.Occupied()) continue;
          const double ox = grid.MeanX(m.cx + dx, c) - m.px, oy = grid.MeanY(m.cy + dy, c) - m.py;
          const double o2 = ox * ox + oy * oy;
          if (o2 >= best_n) continue;
          const double tx = grid.MeanX(m.cx + dx, c) - mx, ty = grid.MeanY(m.cy + dy, c) - my;
          const double t = std::hypot(tx, ty);
          if (t < 0.3 * options_.delta) continue;  // too close for a direction
          best_n = o2;
          nx = -ty / t;
          ny = tx / t;
        }
      }
      auto add = [&](double ax, double ay, double r) {  // one residual r with gradient (ax, ay) in x, y
        const double at = ax * jx + ay * jy;
        h(0, 0) += w * ax * ax;
        h(0, 1) += w * ax * ay;
        h(1, 1) += w * ay * ay;
        h(0, 2) += w * ax * at;
        h(1, 2) += w * ay * at;
        h(2, 2) += w * at * at;
        g(0) += w * ax * r;
        g(1) += w * ay * r;
        g(2) += w * at * r;
      };
      const double rx = m.px - mx, ry = m.py - my;
      if (best_n < std::numeric_limits<double>::infinity()) {
        add(nx, ny, nx * rx + ny * ry);
      } else {
        add(1.0, 0.0, rx);
        add(0.0, 1.0, ry);
      }
      ++used;
    });
    if (used < kRefineMinBeams) return initial;  // too little to constrain three unknowns
    h(1, 0) = h(0, 1);
    h(2, 0) = h(0, 2);
    h(2, 1) = h(1, 2);
    // A little damping: along a corridor point-to-line leaves a direction unconstrained.
    h(0, 0) += 1e-3 * used;
    h(1, 1) += 1e-3 * used;
    h(2, 2) += 1e-3 * h(2, 2);
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(h);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return initial;
    const Eigen::Vector3d step = -ldlt.solve(g);
    if (!step.allFinite()) return initial;
    pose = Pose2{pose.x + step(0), pose.y + step(1), NormalizeAngle(pose.yaw + step(2))};
    if (std::hypot(step(0), step(1)) < 1e-5 && std::fabs(step(2)) < 1e-5) break;
  }
  // A refinement, not a search: a result more than a cell or astep away from the climber's pose
  // means the least-squares problem was degenerate (a corridor) or badly associated.
  if (std::hypot(pose.x - initial.x, pose.y - initial.y) > options_.delta ||
      std::fabs(NormalizeAngle(pose.yaw - initial.yaw)) > options_.astep) {
    return initial;
  }
  return pose;
}

ProposalFit ScanMatcher::SampleAround(const Grid& grid, const PreparedScan& scan,
                                      const Pose2& mode) const {
  const int nl = options_.llsamplestep > 0.0
                     ? static_cast<int>(std::floor(options_.llsamplerange / options_.llsamplestep + 1e-9))
                     : 0;
  const int na = options_.lasamplestep > 0.0
                     ? static_cast<int>(std::floor(options_.lasamplerange / options_.lasamplestep + 1e-9))
                     : 0;
  struct Sample {
    Eigen::Vector3d offset;
    double l;
  };
  std::optional<WindowCache> cache;
  if (WindowCache::Usable(options_.kernelSize)) cache.emplace(scan.match_range.size());
  WindowCache* const cache_ptr = cache ? &*cache : nullptr;
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>((2 * nl + 1) * (2 * nl + 1) * (2 * na + 1)));
  double lmax = -std::numeric_limits<double>::infinity();
  for (int i = -nl; i <= nl; ++i) {
    for (int j = -nl; j <= nl; ++j) {
      for (int t = -na; t <= na; ++t) {
        const Eigen::Vector3d off(i * options_.llsamplestep, j * options_.llsamplestep,
                                  t * options_.lasamplestep);
        const Pose2 p{mode.x + off.x(), mode.y + off.y(), NormalizeAngle(mode.yaw + off.z())};
        const double l = LogLikelihoodCached(grid, scan, p, cache_ptr, nullptr);
        samples.push_back({off, l});
        lmax = std::max(lmax, l);
      }
    }
  }
  // Normalise in the log domain: w_j = exp(l_j - lmax).
  double wsum = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Sample& s : samples) {
    const double w = std::exp(s.l - lmax);
    wsum += w;
    mean += w * s.offset;
  }
  mean /= wsum;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Sample& s : samples) {
    const double w = std::exp(s.l - lmax) / wsum;
    const Eigen::Vector3d d = s.offset - mean;
    cov += w * d * d.transpose();
  }
  ProposalFit fit;
  fit.mean = Pose2{mode.x + mean.x(), mode.y + mean.y(), NormalizeAngle(mode.yaw + mean.z())};
  fit.covariance = cov;
  fit.log_weight = lmax + std::log(wsum / static_cast<double>(samples.size()));
  return fit;
}

void ScanMatcher::Register(const PreparedScan& scan, const Pose2& pose, Grid* grid) const {
  const Pose2 lp = Compose(pose, scan.sensor_in_base);
  const double c = std::cos(lp.yaw), s = std::sin(lp.yaw);
  for (std::size_t i = 0; i < scan.map_range.size(); ++i) {
    const double dx = c * scan.map_cos[i] - s * scan.map_sin[i];
    const double dy = s * scan.map_cos[i] + c * scan.map_sin[i];
    const double r = scan.map_range[i];
    grid->TraceRay(lp.x, lp.y, lp.x + r * dx, lp.y + r * dy, scan.map_hit[i] != 0);
  }
}

}  // namespace minibot3d_slam
