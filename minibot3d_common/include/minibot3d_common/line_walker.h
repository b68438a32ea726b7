// The cells of a straight line between two grid cells, one at a time: Bresenham's integer line
// walk (Bresenham 1965, in its symmetric error-term form), which visits every cell a thin line
// from the centre of the first to the centre of the last passes through closely enough that
// successive cells touch by a side or a corner, and no cell twice.
//
//   for (LineWalker w(x0, y0, x1, y1);; w.Next()) {
//     Visit(w.x(), w.y());
//     if (w.done()) break;
//   }
//
// Ray tracing in the SLAM grid, the costmap's clearing, footprint outlines and exploration's
// line-of-sight checks all walk their lines with it.
#ifndef MINIBOT3D_COMMON_LINE_WALKER_H_
#define MINIBOT3D_COMMON_LINE_WALKER_H_

#include <cstdlib>

namespace minibot3d_common {

class LineWalker {
 public:
  // Starts at cell (x0, y0); the walk ends at (x1, y1).
  LineWalker(int x0, int y0, int x1, int y1)
      : x_(x0), y_(y0), x1_(x1), y1_(y1), dx_(std::abs(x1 - x0)), dy_(-std::abs(y1 - y0)),
        sx_(x0 < x1 ? 1 : -1), sy_(y0 < y1 ? 1 : -1), err_(dx_ + dy_) {}

  int x() const { return x_; }
  int y() const { return y_; }
  // At the last cell.
  bool done() const { return x_ == x1_ && y_ == y1_; }
  // Cells in the whole walk, both ends included.
  int length() const { return (dx_ > -dy_ ? dx_ : -dy_) + 1; }

  // Moves to the next cell; must not be called once done().
  void Next() {
    const int e2 = 2 * err_;
    if (e2 >= dy_) {
      err_ += dy_;
      x_ += sx_;
    }
    if (e2 <= dx_) {
      err_ += dx_;
      y_ += sy_;
    }
  }

 private:
  int x_, y_;
  const int x1_, y1_;
  const int dx_, dy_;
  const int sx_, sy_;
  int err_;
};

}  // namespace minibot3d_common

#endif  // MINIBOT3D_COMMON_LINE_WALKER_H_
