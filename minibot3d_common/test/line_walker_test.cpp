#include "minibot3d_common/line_walker.h"

#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_common {
namespace {

std::vector<std::pair<int, int>> Walk(int x0, int y0, int x1, int y1) {
  std::vector<std::pair<int, int>> cells;
  for (LineWalker w(x0, y0, x1, y1);; w.Next()) {
    cells.emplace_back(w.x(), w.y());
    if (w.done()) break;
  }
  return cells;
}

TEST(LineWalkerTest, SingleCell) {
  const auto cells = Walk(3, -2, 3, -2);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0], std::make_pair(3, -2));
  EXPECT_EQ(LineWalker(3, -2, 3, -2).length(), 1);
}

TEST(LineWalkerTest, AxisAlignedAndDiagonalLines) {
  EXPECT_EQ(Walk(0, 0, 4, 0), (std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}}));
  EXPECT_EQ(Walk(0, 0, 0, -3), (std::vector<std::pair<int, int>>{{0, 0}, {0, -1}, {0, -2}, {0, -3}}));
  EXPECT_EQ(Walk(2, 2, -1, -1), (std::vector<std::pair<int, int>>{{2, 2}, {1, 1}, {0, 0}, {-1, -1}}));
}

// Worked out by hand: from (0, 0) to (5, 2) the line y = 0.4 x passes the cell centres' rows
// at x = 0..5: y = 0, 0.4, 0.8, 1.2, 1.6, 2 -> rows 0, 0, 1, 1, 2, 2.
TEST(LineWalkerTest, ShallowLineFollowsTheNearestRow) {
  EXPECT_EQ(Walk(0, 0, 5, 2),
            (std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {2, 1}, {3, 1}, {4, 2}, {5, 2}}));
}

// Every line in every octant: 8-connected steps, no cell twice, both ends, length() cells, and
// each cell within one cell of the true line.
TEST(LineWalkerTest, EveryOctantIsConnectedAndClose) {
  for (int x1 = -7; x1 <= 7; ++x1) {
    for (int y1 = -7; y1 <= 7; ++y1) {
      const auto cells = Walk(0, 0, x1, y1);
      ASSERT_EQ(cells.front(), std::make_pair(0, 0));
      ASSERT_EQ(cells.back(), std::make_pair(x1, y1));
      ASSERT_EQ(static_cast<int>(cells.size()), LineWalker(0, 0, x1, y1).length());
      const double len = std::hypot(x1, y1);
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (i > 0) {
          const int dx = std::abs(cells[i].first - cells[i - 1].first);
          const int dy = std::abs(cells[i].second - cells[i - 1].second);
          EXPECT_LE(std::max(dx, dy), 1);
          EXPECT_GE(dx + dy, 1);
        }
        if (len > 0) {
          const double dist =
              std::fabs(x1 * cells[i].second - y1 * cells[i].first) / len;  // to the line
          EXPECT_LE(dist, 0.75) << "(" << x1 << ", " << y1 << ") cell " << i;
        }
      }
    }
  }
}

}  // namespace
}  // namespace minibot3d_common
