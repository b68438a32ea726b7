#include "minibot3d_navigation/costmap/inflation_layer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#include <arm_neon.h>
#endif

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

void CheckParameters(double inflation_radius, double cost_scaling_factor) {
  if (!(std::isfinite(inflation_radius) && inflation_radius >= 0.0) ||
      !(std::isfinite(cost_scaling_factor) && cost_scaling_factor >= 0.0)) {
    throw std::invalid_argument("inflation layer: inflation_radius=" +
                                options::Num(inflation_radius) + ", cost_scaling_factor=" +
                                options::Num(cost_scaling_factor) + " must both be >= 0");
  }
}

// Byte-wise max and the combine rule, 16 cells at a time where the target
// has SIMD (SSE2 on x86-64, NEON on ARM): GCC does not vectorise these loops
// at -O2, and they are most of the inflation time.  Define
// MINIBOT3D_COSTMAP_NO_SIMD to use the scalar loops only.
#if defined(__SSE2__) && !defined(MINIBOT3D_COSTMAP_NO_SIMD)
using Vec = __m128i;
inline Vec Load(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const Vec*>(p)); }
inline void Store(uint8_t* p, Vec v) { _mm_storeu_si128(reinterpret_cast<Vec*>(p), v); }
inline Vec Max(Vec a, Vec b) { return _mm_max_epu8(a, b); }
inline Vec Splat(uint8_t v) { return _mm_set1_epi8(static_cast<char>(v)); }
// (old == 255 && cost >= 253) ? cost : max(old, cost)
inline Vec Combine(Vec old_cost, Vec cost) {
  const Vec take = _mm_and_si128(_mm_cmpeq_epi8(old_cost, Splat(kNoInformation)),
                                 _mm_cmpeq_epi8(Max(cost, Splat(kInscribedInflatedObstacle)), cost));
  return _mm_or_si128(_mm_and_si128(take, cost), _mm_andnot_si128(take, Max(old_cost, cost)));
}
#define MINIBOT3D_COSTMAP_SIMD 1
#elif defined(__ARM_NEON) && !defined(MINIBOT3D_COSTMAP_NO_SIMD)
using Vec = uint8x16_t;
inline Vec Load(const uint8_t* p) { return vld1q_u8(p); }
inline void Store(uint8_t* p, Vec v) { vst1q_u8(p, v); }
inline Vec Max(Vec a, Vec b) { return vmaxq_u8(a, b); }
inline Vec Splat(uint8_t v) { return vdupq_n_u8(v); }
inline Vec Combine(Vec old_cost, Vec cost) {
  const Vec take = vandq_u8(vceqq_u8(old_cost, Splat(kNoInformation)),
                            vcgeq_u8(cost, Splat(kInscribedInflatedObstacle)));
  return vbslq_u8(take, cost, vmaxq_u8(old_cost, cost));
}
#define MINIBOT3D_COSTMAP_SIMD 1
#endif

inline uint8_t CombineScalar(uint8_t old_cost, uint8_t cost) {
  if (old_cost == kNoInformation) return cost >= kInscribedInflatedObstacle ? cost : old_cost;
  return old_cost > cost ? old_cost : cost;
}

// dst[k] = max(dst[k], src[k])
inline void MaxInto(uint8_t* dst, const uint8_t* src, int n) {
  int k = 0;
#ifdef MINIBOT3D_COSTMAP_SIMD
  for (; k + 16 <= n; k += 16) Store(dst + k, Max(Load(dst + k), Load(src + k)));
#endif
  for (; k < n; ++k) dst[k] = dst[k] > src[k] ? dst[k] : src[k];
}

// dst[k] = max(dst[k], v)
inline void MaxFill(uint8_t* dst, uint8_t v, int n) {
  int k = 0;
#ifdef MINIBOT3D_COSTMAP_SIMD
  const Vec vv = Splat(v);
  for (; k + 16 <= n; k += 16) Store(dst + k, Max(Load(dst + k), vv));
#endif
  for (; k < n; ++k) dst[k] = dst[k] > v ? dst[k] : v;
}

// The master takes the inflated cost only upwards; an unknown cell only
// becomes inscribed or lethal (costmap_2d with inflate_unknown = false).
inline void CombineInto(uint8_t* dst, const uint8_t* src, int n) {
  int k = 0;
#ifdef MINIBOT3D_COSTMAP_SIMD
  for (; k + 16 <= n; k += 16) Store(dst + k, Combine(Load(dst + k), Load(src + k)));
#endif
  for (; k < n; ++k) dst[k] = CombineScalar(dst[k], src[k]);
}

}  // namespace

InflationLayer::InflationLayer(double inflation_radius, double cost_scaling_factor)
    : inflation_radius_(inflation_radius), weight_(cost_scaling_factor) {
  CheckParameters(inflation_radius, cost_scaling_factor);
}

void InflationLayer::SetInflationParameters(double inflation_radius,
                                            double cost_scaling_factor) {
  CheckParameters(inflation_radius, cost_scaling_factor);
  inflation_radius_ = inflation_radius;
  weight_ = cost_scaling_factor;
  ComputeKernel();
  need_reinflation_ = true;
}

uint8_t InflationLayer::ComputeCost(double distance) const {
  if (distance == 0) return kLethalObstacle;
  if (distance * resolution_ <= inscribed_radius_) return kInscribedInflatedObstacle;
  const double euclidean_distance = distance * resolution_;
  const double factor = std::exp(-1.0 * weight_ * (euclidean_distance - inscribed_radius_));
  return static_cast<uint8_t>((kInscribedInflatedObstacle - 1) * factor);
}

void InflationLayer::MatchSize(const Costmap2D& master) {
  resolution_ = master.resolution();
  ComputeKernel();
  need_reinflation_ = true;
}

void InflationLayer::OnFootprintChanged(const Footprint& /*padded_footprint*/,
                                        double inscribed_radius,
                                        double /*circumscribed_radius*/) {
  inscribed_radius_ = inscribed_radius;
  ComputeKernel();
  need_reinflation_ = true;
}

void InflationLayer::ComputeKernel() {
  kernel_.clear();
  half_width_.clear();
  row_start_.clear();
  cell_inflation_radius_ = 0;
  if (!(resolution_ > 0.0)) return;
  // costmap_2d's cellDistance.
  const double cells = std::max(0.0, std::ceil(inflation_radius_ / resolution_));
  cell_inflation_radius_ = static_cast<int>(std::min(cells, 1.0e4));
  const int r = cell_inflation_radius_;
  for (int dy = 0; dy <= r; ++dy) {
    // Cells within r of the source, as costmap_2d's enqueue test
    // (distance > cell_inflation_radius is rejected).
    int w = 0;
    while (w + 1 <= r && std::hypot(w + 1, dy) <= r) ++w;
    half_width_.push_back(w);
    row_start_.push_back(kernel_.size());
    for (int dx = -w; dx <= w; ++dx) kernel_.push_back(ComputeCost(std::hypot(dx, dy)));
  }
}

void InflationLayer::UpdateBounds(const Pose2& /*robot*/, Bounds* bounds) {
  if (need_reinflation_) {
    last_bounds_ = *bounds;
    *bounds = Bounds::All();
    need_reinflation_ = false;
    return;
  }
  const Bounds previous = last_bounds_;
  last_bounds_ = *bounds;
  Bounds b = *bounds;
  b.Merge(previous);
  if (b.empty()) return;
  b.min_x -= inflation_radius_;
  b.min_y -= inflation_radius_;
  b.max_x += inflation_radius_;
  b.max_y += inflation_radius_;
  *bounds = b;
}

void InflationLayer::UpdateCosts(const CellBounds& cells, Costmap2D* master) {
  const int r = cell_inflation_radius_;
  if (r == 0 || cells.empty() || master->resolution() != resolution_) return;
  const int size_x = master->size_x(), size_y = master->size_y();
  const int min_i = std::max(0, cells.min_i), max_i = std::min(size_x, cells.max_i);
  const int min_j = std::max(0, cells.min_j), max_j = std::min(size_y, cells.max_j);
  if (min_i >= max_i || min_j >= max_j) return;
  const int bw = max_i - min_i, bh = max_j - min_j;
  buffer_.assign(static_cast<size_t>(bw) * bh, 0);

  // Lethal cells up to r outside the block can raise costs inside it.
  const int src_min_i = std::max(0, min_i - r), src_max_i = std::min(size_x, max_i + r);
  const int src_min_j = std::max(0, min_j - r), src_max_j = std::min(size_y, max_j + r);
  const uint8_t* grid = master->data();

  // Stamps the kernel for the block of lethal cells [a, b] x [j0, j1]: a cell
  // at (x, y) is nearest to the block's cell (clamp(x, a, b), clamp(y, j0,
  // j1)), so each output row takes one kernel row (its distance to the block
  // in y) split at the block's ends.
  auto stamp_block = [&](int a, int b, int j0, int j1) {
    const int y_lo = std::max(min_j, j0 - r), y_hi = std::min(max_j - 1, j1 + r);
    for (int y = y_lo; y <= y_hi; ++y) {
      const int dy = y < j0 ? j0 - y : (y > j1 ? y - j1 : 0);
      const int w = half_width_[dy];
      const uint8_t* krow = kernel_.data() + row_start_[dy];  // krow[w] is dx = 0
      uint8_t* out = buffer_.data() + static_cast<size_t>(y - min_j) * bw;  // x = min_i
      // Left half: x in [a - w, a - 1], dx = x - a.
      int x0 = std::max(min_i, a - w), x1 = std::min(max_i, a);
      if (x0 < x1) MaxInto(out + (x0 - min_i), krow + (x0 - a + w), x1 - x0);
      // Centre: x in [a, b], dx = 0.  Inside the block these are the lethal
      // cells themselves, which the combine step leaves lethal anyway.
      if (dy != 0) {
        x0 = std::max(min_i, a);
        x1 = std::min(max_i, b + 1);
        if (x0 < x1) MaxFill(out + (x0 - min_i), krow[w], x1 - x0);
      }
      // Right half: x in [b + 1, b + w], dx = x - b.
      x0 = std::max(min_i, b + 1);
      x1 = std::min(max_i, b + w + 1);
      if (x0 < x1) MaxInto(out + (x0 - min_i), krow + (x0 - b + w), x1 - x0);
    }
  };

  // Runs of lethal cells, row by row; a run with the same ends as one in the
  // row below extends that block upwards (walls and furniture are mostly
  // such blocks), so each block is stamped once instead of once per row.
  open_blocks_.clear();
  next_blocks_.clear();
  for (int j = src_min_j; j < src_max_j; ++j) {
    const uint8_t* row = grid + static_cast<size_t>(j) * size_x;
    size_t k = 0;  // walks open_blocks_ (sorted by a) alongside this row's runs
    int i = src_min_i;
    while (i < src_max_i) {
      const void* hit = std::memchr(row + i, kLethalObstacle, static_cast<size_t>(src_max_i - i));
      if (hit == nullptr) break;
      const int a = static_cast<int>(static_cast<const uint8_t*>(hit) - row);
      int b = a;
      while (b + 1 < src_max_i && row[b + 1] == kLethalObstacle) ++b;
      i = b + 1;
      while (k < open_blocks_.size() && open_blocks_[k].a < a) {
        stamp_block(open_blocks_[k].a, open_blocks_[k].b, open_blocks_[k].j0, j - 1);
        ++k;
      }
      if (k < open_blocks_.size() && open_blocks_[k].a == a && open_blocks_[k].b == b) {
        next_blocks_.push_back(open_blocks_[k]);
        ++k;
      } else {
        next_blocks_.push_back({a, b, j});
      }
    }
    for (; k < open_blocks_.size(); ++k) {
      stamp_block(open_blocks_[k].a, open_blocks_[k].b, open_blocks_[k].j0, j - 1);
    }
    open_blocks_.swap(next_blocks_);
    next_blocks_.clear();
  }
  for (const auto& blk : open_blocks_) stamp_block(blk.a, blk.b, blk.j0, src_max_j - 1);

  uint8_t* data = master->mutable_data();
  for (int j = min_j; j < max_j; ++j) {
    CombineInto(data + static_cast<size_t>(j) * size_x + min_i,
                buffer_.data() + static_cast<size_t>(j - min_j) * bw, bw);
  }
}

}  // namespace nav
}  // namespace minibot3d_navigation
