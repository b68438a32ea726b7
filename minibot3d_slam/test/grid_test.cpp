// Tests of the copy-on-write occupancy grid (src/grid.h) and of scan registration.
#include "grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scan_matcher.h"

namespace minibot3d_slam {
namespace {

TEST(GridTest, RayMarksFreeCellsAndAHit) {
  Grid g(0.1);
  g.TraceRay(0.05, 0.05, 1.07, 0.05, /*hit=*/true);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(g.At(i, 0).visits, 1) << i;
    EXPECT_EQ(g.At(i, 0).hits, 0) << i;
    EXPECT_DOUBLE_EQ(g.Probability(i, 0), 0.0);
  }
  const GridCell& end = g.At(10, 0);
  EXPECT_EQ(end.hits, 1);
  EXPECT_TRUE(end.Occupied());
  EXPECT_NEAR(g.MeanX(10, end), 1.07, 1e-5);  // the endpoint itself, not the cell centre
  EXPECT_NEAR(g.MeanY(0, end), 0.05, 1e-5);
  EXPECT_DOUBLE_EQ(g.Probability(11, 0), -1.0);
  EXPECT_DOUBLE_EQ(g.Probability(5, 1), -1.0);
  // Without a hit the last cell is free too.
  g.TraceRay(0.05, 0.35, 1.05, 0.35, false);
  EXPECT_EQ(g.At(10, 3).hits, 0);
  EXPECT_EQ(g.At(10, 3).visits, 1);
}

// CellX/CellY and MeanX/MeanY are computed without std::floor and with integer mean units for
// speed; they must give exactly what the plain formulas give.
TEST(GridTest, FastCellAndMeanArithmeticIsExact) {
  for (double resolution : {0.05, 0.1, 0.025, 0.07}) {
    const Grid g(resolution);
    for (double x : {0.0, -0.0, 1e-12, -1e-12, 0.05, -0.05, 0.049999, -0.050001, 3.2, -3.2, 123.456,
                     -123.456, 99.99, -100.0, 1e5 * resolution, -1e5 * resolution}) {
      EXPECT_EQ(g.CellX(x), static_cast<int>(std::floor(x * (1.0 / resolution)))) << x;
      EXPECT_EQ(g.CellY(x), static_cast<int>(std::floor(x * (1.0 / resolution)))) << x;
    }
    GridCell c;
    for (int ix : {0, 1, -1, 63, -64, 2000, -2000, 123457, -98765}) {
      for (int m : {0, 1, -1, 32767, -32768, 12345, -20001}) {
        c.mean_x = static_cast<std::int16_t>(m);
        c.mean_y = static_cast<std::int16_t>(-m - 1);
        EXPECT_EQ(g.MeanX(ix, c), (ix + 0.5 + c.mean_x / Grid::kMeanScale) * resolution) << ix << " " << m;
        EXPECT_EQ(g.MeanY(ix, c), (ix + 0.5 + c.mean_y / Grid::kMeanScale) * resolution) << ix << " " << m;
      }
    }
  }
}

TEST(GridTest, DiagonalRayIsConnected) {
  Grid g(0.05);
  g.TraceRay(0.01, 0.01, -3.0, 2.0, true);
  // Every column between the two ends has a visited cell (Bresenham leaves no gaps).
  for (int ix = g.CellX(-3.0); ix <= 0; ++ix) {
    bool any = false;
    for (int iy = -2; iy <= g.CellY(2.0) + 2; ++iy) any = any || g.At(ix, iy).visits > 0;
    EXPECT_TRUE(any) << ix;
  }
  EXPECT_TRUE(g.At(g.CellX(-3.0), g.CellY(2.0)).Occupied());
}

TEST(GridTest, OccupancyIsHitsOverVisits) {
  Grid g(0.05);
  for (int i = 0; i < 3; ++i) g.MarkHit(4, 4, 0.21, 0.22);
  for (int i = 0; i < 9; ++i) g.MarkFree(4, 4);
  EXPECT_DOUBLE_EQ(g.Probability(4, 4), 0.25);
  EXPECT_TRUE(g.At(4, 4).Occupied());          // > 0.1
  EXPECT_FALSE(g.At(4, 4).FreeOrUnknown());
  for (int i = 0; i < 30; ++i) g.MarkFree(4, 4);
  EXPECT_FALSE(g.At(4, 4).Occupied());         // 3 / 42 < 0.1
  EXPECT_TRUE(g.At(4, 4).FreeOrUnknown());
  // The counters saturate without losing the ratio.
  for (int i = 0; i < 70000; ++i) g.MarkHit(7, 7, 0.36, 0.36);
  EXPECT_DOUBLE_EQ(g.Probability(7, 7), 1.0);
}

TEST(GridTest, MapGrowsInEveryDirection) {
  Grid g(0.05);
  int x0, y0, x1, y1;
  EXPECT_FALSE(g.AllocatedBounds(&x0, &y0, &x1, &y1));
  g.TraceRay(0.0, 0.0, 1.0, 1.0, true);
  g.TraceRay(0.0, 0.0, -150.0, 80.0, true);
  g.TraceRay(0.0, 0.0, 120.0, -200.0, true);
  ASSERT_TRUE(g.AllocatedBounds(&x0, &y0, &x1, &y1));
  EXPECT_LE(x0, g.CellX(-150.0));
  EXPECT_GE(x1, g.CellX(120.0));
  EXPECT_LE(y0, g.CellY(-200.0));
  EXPECT_GE(y1, g.CellY(80.0));
  EXPECT_TRUE(g.At(g.CellX(-150.0), g.CellY(80.0)).Occupied());
  EXPECT_TRUE(g.At(g.CellX(120.0), g.CellY(-200.0)).Occupied());
  EXPECT_TRUE(g.At(g.CellX(0.5), g.CellY(0.5)).visits > 0);  // earlier content survived growth
}

TEST(GridTest, CopiesShareTilesUntilOneWrites) {
  Grid a(0.05);
  // Touch several tiles: a ray 20 m long crosses ⌈400 / kTileSize⌉ tiles.
  a.TraceRay(0.01, 0.01, 20.0, 0.01, true);
  const int tiles = a.TileCount();
  ASSERT_GE(tiles, 400 / Grid::kTileSize);
  Grid b = a;  // what resampling does
  EXPECT_EQ(b.SharedTileCount(a), tiles);
  EXPECT_EQ(b.tiles_copied(), a.tiles_copied());
  const long long copied_before = b.tiles_copied();
  // One write into one tile copies only that tile.
  b.MarkFree(3, 0);
  EXPECT_EQ(b.tiles_copied(), copied_before + 1);
  EXPECT_EQ(b.SharedTileCount(a), tiles - 1);
  EXPECT_EQ(a.At(3, 0).visits, 1);  // the other particle's map is unchanged
  EXPECT_EQ(b.At(3, 0).visits, 2);
  // Further writes to the now private tile copy nothing.
  b.MarkFree(4, 0);
  b.MarkHit(5, 0, 0.27, 0.02);
  EXPECT_EQ(b.tiles_copied(), copied_before + 1);
  // A write to a tile a alone holds copies nothing either.
  const long long a_copied = a.tiles_copied();
  a.MarkFree(3, 0);
  EXPECT_EQ(a.tiles_copied(), a_copied);
  // A new tile is allocated, not copied, and not shared.
  b.MarkFree(-1000, -1000);
  EXPECT_EQ(b.tiles_copied(), copied_before + 1);
  EXPECT_EQ(b.TileCount(), tiles + 1);
  EXPECT_EQ(b.SharedTileCount(a), tiles - 1);
}

TEST(GridTest, RegisterCutsReadingsAtMaxUrange) {
  GmappingOptions o;
  o.delta = 0.1;
  o.maxUrange = 5.0;
  const ScanMatcher matcher(o);
  LaserScan s;
  s.range_max = 30.0;
  s.ranges = {3.02, 10.0, std::numeric_limits<double>::infinity()};
  s.angles = {0.0, M_PI / 2, M_PI};
  Grid g(o.delta);
  matcher.Register(matcher.Prepare(s), Pose2{0.05, 0.05, 0.0}, &g);
  // Within maxUrange: free up to the hit, the hit marked.
  EXPECT_TRUE(g.At(g.CellX(3.07), 0).Occupied());
  EXPECT_GT(g.At(g.CellX(1.5), 0).visits, 0);
  // Beyond maxUrange: free up to maxUrange, nothing marked occupied, nothing beyond.
  EXPECT_GT(g.At(0, g.CellY(4.9)).visits, 0);
  for (int iy = 0; iy <= g.CellY(5.1); ++iy) EXPECT_EQ(g.At(0, iy).hits, 0) << iy;
  EXPECT_EQ(g.At(0, g.CellY(5.3)).visits, 0);
  EXPECT_EQ(g.At(0, g.CellY(10.0)).visits, 0);
  // A no-return clears nothing.
  EXPECT_EQ(g.At(g.CellX(-1.0), 0).visits, 0);
}

// Memory follows the explored area, not the bounding box: two short rays 2 km apart allocate the
// handful of tiles they cross; the 40 000 × 20 000-cell box between them costs a table of tile
// pointers only, and every cell outside the allocated tiles reads as unknown.
TEST(GridTest, ReadsOfUnallocatedTilesAreUnknownAndWritesAllocateOnlyTheirTiles) {
  Grid g(0.05);
  EXPECT_EQ(g.TileCount(), 0);
  EXPECT_EQ(g.At(0, 0).visits, 0);
  EXPECT_EQ(g.TileAt(0, 0), nullptr);
  EXPECT_DOUBLE_EQ(g.Probability(123456, -654321), -1.0);
  g.TraceRay(1.01, 1.01, 2.01, 1.01, true);          // 20 cells, one tile
  g.TraceRay(2001.01, 1001.01, 2002.01, 1001.01, true);  // 2 km east, 1 km north
  EXPECT_LE(g.TileCount(), 4);
  int x0, y0, x1, y1;
  ASSERT_TRUE(g.AllocatedBounds(&x0, &y0, &x1, &y1));
  EXPECT_GT(static_cast<double>(x1 - x0) * (y1 - y0), 7e8);  // the box: 40 000 × 20 000 cells…
  const std::size_t bytes = static_cast<std::size_t>(g.TileCount()) * sizeof(Grid::Tile);
  EXPECT_LT(bytes, 4u * sizeof(Grid::Tile) + 1);  // …the cells are a few tiles
  // In between: unknown, unallocated.
  for (double x = 10.0; x < 2000.0; x += 97.3) {
    EXPECT_EQ(g.At(g.CellX(x), g.CellY(x / 2)).visits, 0) << x;
    EXPECT_EQ(g.TileAt(g.CellX(x) >> Grid::kTileBits, g.CellY(x / 2) >> Grid::kTileBits), nullptr) << x;
  }
  EXPECT_TRUE(g.At(g.CellX(2.01), g.CellY(1.01)).Occupied());
  EXPECT_TRUE(g.At(g.CellX(2002.01), g.CellY(1001.01)).Occupied());
}

TEST(GridTest, CopiesAreIndependent) {
  Grid a(0.05);
  a.TraceRay(0.01, 0.01, 3.0, 0.01, true);
  Grid b = a;
  // Writes to either side, into shared and into new tiles, are invisible to the other.
  b.TraceRay(0.01, 0.01, 3.0, 0.01, true);
  b.MarkHit(1000, 1000, 50.01, 50.01);
  a.MarkFree(-500, 7);
  EXPECT_EQ(a.At(a.CellX(1.0), 0).visits, 1);
  EXPECT_EQ(b.At(b.CellX(1.0), 0).visits, 2);
  EXPECT_EQ(a.At(1000, 1000).visits, 0);
  EXPECT_EQ(b.At(1000, 1000).hits, 1);
  EXPECT_EQ(a.At(-500, 7).visits, 1);
  EXPECT_EQ(b.At(-500, 7).visits, 0);
  // Destroying the original leaves the copy intact.
  { Grid gone = std::move(a); }
  EXPECT_EQ(b.At(b.CellX(3.0), 0).hits, 2);
}

}  // namespace
}  // namespace minibot3d_slam
