// Copy-on-write tiled occupancy grid (see grid.h for the design).
#include "grid.h"

#include <algorithm>
#include <cstdlib>
#include <limits>

#include "minibot3d_common/line_walker.h"

namespace minibot3d_slam {

const GridCell Grid::kUnknown{};

Grid::Grid(double resolution)
    : resolution_(resolution), inv_resolution_(1.0 / resolution), mean_unit_(resolution / kMeanScale) {}

void Grid::Reserve(int ix0, int iy0, int ix1, int iy1) {
  const int tx0 = ix0 >> kTileBits, ty0 = iy0 >> kTileBits;
  const int tx1 = ix1 >> kTileBits, ty1 = iy1 >> kTileBits;
  if (tiles_x_ > 0 && tx0 >= tile_x0_ && ty0 >= tile_y0_ && tx1 < tile_x0_ + tiles_x_ &&
      ty1 < tile_y0_ + tiles_y_) {
    return;
  }
  // Grow with a margin so that a robot driving out of the map does not regrow it at every scan.
  constexpr int kMargin = 4;
  int nx0 = tx0 - kMargin, ny0 = ty0 - kMargin, nx1 = tx1 + kMargin, ny1 = ty1 + kMargin;
  if (tiles_x_ > 0) {
    nx0 = std::min(nx0, tile_x0_);
    ny0 = std::min(ny0, tile_y0_);
    nx1 = std::max(nx1, tile_x0_ + tiles_x_ - 1);
    ny1 = std::max(ny1, tile_y0_ + tiles_y_ - 1);
  }
  const int nw = nx1 - nx0 + 1, nh = ny1 - ny0 + 1;
  std::vector<std::shared_ptr<Tile>> grown(static_cast<std::size_t>(nw) * nh);
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      grown[static_cast<std::size_t>(ty + tile_y0_ - ny0) * nw + (tx + tile_x0_ - nx0)] =
          std::move(tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx]);
    }
  }
  tiles_ = std::move(grown);
  tile_x0_ = nx0;
  tile_y0_ = ny0;
  tiles_x_ = nw;
  tiles_y_ = nh;
}

Grid::Tile* Grid::MutableTile(int tx, int ty) {
  std::shared_ptr<Tile>& slot =
      tiles_[static_cast<std::size_t>(ty - tile_y0_) * tiles_x_ + (tx - tile_x0_)];
  if (!slot) {
    slot = std::make_shared<Tile>();
  } else if (slot.use_count() > 1) {
    // Another particle's grid holds this tile: clone it before writing.
    slot = std::make_shared<Tile>(*slot);
    ++tiles_copied_;
  }
  return slot.get();
}

GridCell* Grid::MutableCell(int ix, int iy) {
  Reserve(ix, iy, ix, iy);
  Tile* tile = MutableTile(ix >> kTileBits, iy >> kTileBits);
  return &tile->cells[((iy & kTileMask) << kTileBits) | (ix & kTileMask)];
}

namespace {

// Keeps the counters in 16 bits: halving both preserves the occupancy ratio.
inline void MakeRoom(GridCell* c) {
  if (c->visits == std::numeric_limits<std::uint16_t>::max()) {
    c->visits = static_cast<std::uint16_t>(c->visits / 2);
    c->hits = static_cast<std::uint16_t>(c->hits / 2);
  }
}

inline void Free(GridCell* c) {
  MakeRoom(c);
  ++c->visits;
}

inline void Hit(GridCell* c, double off_x, double off_y) {
  MakeRoom(c);
  ++c->visits;
  ++c->hits;
  // Running mean of the endpoints (offsets from the cell centre, in 1/65536 cells).
  const double inv_n = 1.0 / c->hits;
  const double mx = c->mean_x + (off_x * Grid::kMeanScale - c->mean_x) * inv_n;
  const double my = c->mean_y + (off_y * Grid::kMeanScale - c->mean_y) * inv_n;
  c->mean_x = static_cast<std::int16_t>(std::clamp(std::lround(mx), -32768L, 32767L));
  c->mean_y = static_cast<std::int16_t>(std::clamp(std::lround(my), -32768L, 32767L));
}

}  // namespace

void Grid::MarkFree(int ix, int iy) { Free(MutableCell(ix, iy)); }

void Grid::MarkHit(int ix, int iy, double x, double y) {
  Hit(MutableCell(ix, iy), x * inv_resolution_ - (ix + 0.5), y * inv_resolution_ - (iy + 0.5));
}

void Grid::TraceRay(double x0, double y0, double x1, double y1, bool hit) {
  const int ix = CellX(x0), iy = CellY(y0);
  const int ex = CellX(x1), ey = CellY(y1);
  Reserve(std::min(ix, ex), std::min(iy, ey), std::max(ix, ex), std::max(iy, ey));
  // The tile of the current cell is looked up (and made private) only when the line enters a
  // new tile.
  int cur_tx = std::numeric_limits<int>::min(), cur_ty = 0;
  Tile* tile = nullptr;
  for (minibot3d_common::LineWalker walk(ix, iy, ex, ey);; walk.Next()) {
    const int x = walk.x(), y = walk.y();
    const int tx = x >> kTileBits, ty = y >> kTileBits;
    if (tx != cur_tx || ty != cur_ty) {
      tile = MutableTile(tx, ty);
      cur_tx = tx;
      cur_ty = ty;
    }
    GridCell* cell = &tile->cells[((y & kTileMask) << kTileBits) | (x & kTileMask)];
    if (walk.done()) {
      if (hit) {
        Hit(cell, x1 * inv_resolution_ - (x + 0.5), y1 * inv_resolution_ - (y + 0.5));
      } else {
        Free(cell);
      }
      break;
    }
    Free(cell);
  }
}

bool Grid::AllocatedBounds(int* ix0, int* iy0, int* ix1, int* iy1) const {
  int tx0 = std::numeric_limits<int>::max(), ty0 = tx0;
  int tx1 = std::numeric_limits<int>::min(), ty1 = tx1;
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      if (!tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx]) continue;
      tx0 = std::min(tx0, tx);
      ty0 = std::min(ty0, ty);
      tx1 = std::max(tx1, tx);
      ty1 = std::max(ty1, ty);
    }
  }
  if (tx1 < tx0) return false;
  *ix0 = (tx0 + tile_x0_) * kTileSize;
  *iy0 = (ty0 + tile_y0_) * kTileSize;
  *ix1 = (tx1 + tile_x0_ + 1) * kTileSize - 1;
  *iy1 = (ty1 + tile_y0_ + 1) * kTileSize - 1;
  return true;
}

int Grid::TileCount() const {
  int n = 0;
  for (const auto& t : tiles_) n += t ? 1 : 0;
  return n;
}

int Grid::SharedTileCount(const Grid& other) const {
  int n = 0;
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      const Tile* t = tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx].get();
      if (t == nullptr) continue;
      const int ox = tx + tile_x0_ - other.tile_x0_, oy = ty + tile_y0_ - other.tile_y0_;
      if (ox < 0 || oy < 0 || ox >= other.tiles_x_ || oy >= other.tiles_y_) continue;
      if (other.tiles_[static_cast<std::size_t>(oy) * other.tiles_x_ + ox].get() == t) ++n;
    }
  }
  return n;
}

}  // namespace minibot3d_slam
