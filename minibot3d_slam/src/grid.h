// Per-particle occupancy grid of the RBPF (Grisetti, Stachniss & Burgard, IEEE T-RO 2007), with
// memory shared between particles by copy-on-write tiles.
//
// Cells are gmapping's "point accumulators": a cell counts how often a beam ended in it (hits) and
// how often a beam touched it at all (visits); its occupancy is hits / visits, and it keeps the mean
// of the endpoints that fell into it, so the scan matcher can measure endpoint distances with
// sub-cell precision instead of to the cell centre.
//
// Memory sharing. A particle filter with N particles has N maps that differ only where the particles
// have written since their last common ancestor, i.e. around their recent trajectory. The grid is
// cut into square tiles of kTileSize × kTileSize cells held by std::shared_ptr; copying a Grid (what
// resampling does) copies only the table of tile pointers. A write to a tile that another grid also
// holds (use_count > 1) first clones that tile, so a particle pays memory only for tiles it changed
// since the last resampling. Reads never copy. (gmapping itself clones every tile in the "active
// area" of every particle at every scan, whether shared or not.)
//
// Cell coordinates are global integers: cell (i, j) covers [i·δ, (i+1)·δ) × [j·δ, (j+1)·δ). The
// tile table grows on demand, so maps grow in every direction as the robot explores; cells in no
// tile read as unknown.
#ifndef MINIBOT3D_SLAM_SRC_GRID_H_
#define MINIBOT3D_SLAM_SRC_GRID_H_

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace minibot3d_slam {

struct GridCell {
  std::uint16_t hits = 0;    // beams that ended here
  std::uint16_t visits = 0;  // beams that ended here or passed through
  // Mean of the endpoints that ended here, relative to the cell centre, in units of δ / 65536
  // (so the whole cell [-δ/2, δ/2) is representable).
  std::int16_t mean_x = 0, mean_y = 0;

  // gmapping's fullness tests at its threshold 0.1, in integers (hits/visits vs 1/10).
  bool Occupied() const { return 10 * static_cast<int>(hits) > static_cast<int>(visits); }
  // Unknown cells count as free (gmapping's value -1 < 0.1).
  bool FreeOrUnknown() const { return 10 * static_cast<int>(hits) < static_cast<int>(visits) || visits == 0; }
};

class Grid {
 public:
  static constexpr int kTileBits = 6;
  static constexpr int kTileSize = 1 << kTileBits;  // cells per tile side
  static constexpr int kTileMask = kTileSize - 1;
  static constexpr int kTileCells = kTileSize * kTileSize;
  static constexpr double kMeanScale = 65536.0;  // mean_x/mean_y units per cell (MeanUnits relies on it)

  struct Tile {
    GridCell cells[kTileCells];
  };

  explicit Grid(double resolution);

  double resolution() const { return resolution_; }
  int CellX(double x) const { return FloorToInt(x * inv_resolution_); }
  int CellY(double y) const { return FloorToInt(y * inv_resolution_); }
  // static_cast<int>(std::floor(v)) for |v| < 2³¹, without the libm call or the long SSE2
  // expansion of floor (the scan matcher calls this a few times per beam and cell).
  static int FloorToInt(double v) {
    const int i = static_cast<int>(v);  // truncates towards zero
    return i - (v < static_cast<double>(i) ? 1 : 0);
  }

  // Read access; cells outside every tile read as unknown.
  const GridCell& At(int ix, int iy) const {
    const int tx = (ix >> kTileBits) - tile_x0_, ty = (iy >> kTileBits) - tile_y0_;
    if (static_cast<unsigned>(tx) >= static_cast<unsigned>(tiles_x_) ||
        static_cast<unsigned>(ty) >= static_cast<unsigned>(tiles_y_)) {
      return kUnknown;
    }
    const Tile* tile = tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx].get();
    if (tile == nullptr) return kUnknown;
    return tile->cells[((iy & kTileMask) << kTileBits) | (ix & kTileMask)];
  }
  // The tile holding tile coordinates (tx, ty), or nullptr when unallocated (all unknown).
  const Tile* TileAt(int tx, int ty) const {
    tx -= tile_x0_;
    ty -= tile_y0_;
    if (static_cast<unsigned>(tx) >= static_cast<unsigned>(tiles_x_) ||
        static_cast<unsigned>(ty) >= static_cast<unsigned>(tiles_y_)) {
      return nullptr;
    }
    return tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx].get();
  }
  // World coordinates of the mean endpoint of a cell with hits.
  // (ix + 0.5 + mean_x / kMeanScale) · δ, computed as an integer count of mean units times
  // δ / kMeanScale: the sum is exact in either form and the one product rounds alike, so this is
  // bit-identical to the plain formula, with fewer conversions (the scan matcher's hot loop).
  double MeanX(int ix, const GridCell& c) const { return MeanUnits(ix, c.mean_x) * mean_unit_; }
  double MeanY(int iy, const GridCell& c) const { return MeanUnits(iy, c.mean_y) * mean_unit_; }

  // Makes sure cells [ix0, ix1] × [iy0, iy1] have a slot in the tile table (no tiles allocated).
  void Reserve(int ix0, int iy0, int ix1, int iy1);

  // A beam from world point (x0, y0) to (x1, y1): every cell of the Bresenham line but the last is
  // visited as free; the last is a hit at (x1, y1) when `hit`, else visited as free too.
  void TraceRay(double x0, double y0, double x1, double y1, bool hit);
  // Single-cell updates (tests and callers that do their own tracing).
  void MarkFree(int ix, int iy);
  void MarkHit(int ix, int iy, double x, double y);

  // Occupancy probability (hits / visits) or -1 when never visited.
  double Probability(int ix, int iy) const {
    const GridCell& c = At(ix, iy);
    return c.visits == 0 ? -1.0 : static_cast<double>(c.hits) / c.visits;
  }

  // Bounds of the allocated tiles, in cells (inclusive); false when nothing is allocated.
  bool AllocatedBounds(int* ix0, int* iy0, int* ix1, int* iy1) const;
  // Number of allocated tiles, and how many of them are the very same tile object in `other`.
  int TileCount() const;
  int SharedTileCount(const Grid& other) const;
  // Calls f(const Tile*) for every allocated tile (memory statistics).
  template <class F>
  void ForEachTile(F&& f) const {
    for (const auto& t : tiles_) {
      if (t) f(static_cast<const Tile*>(t.get()));
    }
  }
  // Tiles cloned by this grid's copy-on-write so far (statistics).
  long long tiles_copied() const { return tiles_copied_; }

 private:
  static const GridCell kUnknown;

  static double MeanUnits(int i, std::int16_t mean) {
    return static_cast<double>(static_cast<std::int64_t>(i) * 65536 + 32768 + mean);
  }

  GridCell* MutableCell(int ix, int iy);
  Tile* MutableTile(int tx, int ty);  // tx, ty: tile coordinates; must be reserved

  double resolution_;
  double inv_resolution_;
  double mean_unit_;  // δ / kMeanScale
  int tile_x0_ = 0, tile_y0_ = 0, tiles_x_ = 0, tiles_y_ = 0;
  std::vector<std::shared_ptr<Tile>> tiles_;
  long long tiles_copied_ = 0;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_GRID_H_
