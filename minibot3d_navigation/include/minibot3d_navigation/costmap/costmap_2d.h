// A 2-D grid of 8-bit traversal costs, after costmap_2d's Costmap2D.
//
// Cell (mx, my) is data()[my * size_x() + mx]; (0, 0) is the cell whose outer
// corner is at (origin_x, origin_y) in the costmap's frame, x and y grow with
// mx and my, and cells are resolution metres square.  The cost values are
// costmap_2d's, so the published OccupancyGrid and every YAML threshold mean
// what ROS users expect:
//   0 free, 1..252 inflated (decaying with distance), 253 inscribed (the
//   robot's centre here puts its footprint on an obstacle), 254 lethal
//   (an obstacle), 255 unknown.
// The global costmap is fixed in the map frame; the local costmap is a rolling
// window in odom whose origin moves with the robot (UpdateOrigin keeps the
// cells the old and new windows share).
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_2D_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_2D_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace minibot3d_navigation {
namespace nav {

constexpr uint8_t kFreeSpace = 0;
constexpr uint8_t kInscribedInflatedObstacle = 253;
constexpr uint8_t kLethalObstacle = 254;
constexpr uint8_t kNoInformation = 255;

class Costmap2D {
 public:
  Costmap2D() = default;
  Costmap2D(int size_x, int size_y, double resolution, double origin_x,
            double origin_y, uint8_t default_value = kFreeSpace) {
    Resize(size_x, size_y, resolution, origin_x, origin_y, default_value);
  }

  // Throws std::invalid_argument for a non-positive size or resolution.
  void Resize(int size_x, int size_y, double resolution, double origin_x,
              double origin_y, uint8_t default_value = kFreeSpace) {
    if (size_x <= 0 || size_y <= 0 || !(resolution > 0.0) ||
        !std::isfinite(origin_x) || !std::isfinite(origin_y)) {
      throw std::invalid_argument(
          "Costmap2D: invalid geometry " + std::to_string(size_x) + "x" +
          std::to_string(size_y) + " cells at resolution " +
          std::to_string(resolution) + " m");
    }
    size_x_ = size_x;
    size_y_ = size_y;
    resolution_ = resolution;
    origin_x_ = origin_x;
    origin_y_ = origin_y;
    default_value_ = default_value;
    data_.assign(static_cast<size_t>(size_x) * size_y, default_value);
  }

  int size_x() const { return size_x_; }
  int size_y() const { return size_y_; }
  double resolution() const { return resolution_; }
  double origin_x() const { return origin_x_; }
  double origin_y() const { return origin_y_; }
  uint8_t default_value() const { return default_value_; }
  double size_x_m() const { return size_x_ * resolution_; }
  double size_y_m() const { return size_y_ * resolution_; }

  bool InBounds(int mx, int my) const {
    return mx >= 0 && my >= 0 && mx < size_x_ && my < size_y_;
  }
  int Index(int mx, int my) const { return my * size_x_ + mx; }
  uint8_t cost(int mx, int my) const { return data_[Index(mx, my)]; }
  void set_cost(int mx, int my, uint8_t c) { data_[Index(mx, my)] = c; }
  const uint8_t* data() const { return data_.data(); }
  uint8_t* mutable_data() { return data_.data(); }
  const std::vector<uint8_t>& cells() const { return data_; }

  // World (costmap frame) to cell; false when outside the grid.
  bool WorldToMap(double wx, double wy, int* mx, int* my) const {
    const double fx = (wx - origin_x_) / resolution_;
    const double fy = (wy - origin_y_) / resolution_;
    if (!(fx >= 0.0) || !(fy >= 0.0)) return false;
    *mx = static_cast<int>(fx);
    *my = static_cast<int>(fy);
    return *mx < size_x_ && *my < size_y_;
  }
  // Like WorldToMap but clamps to the nearest cell (cells may be outside).
  void WorldToMapNoBounds(double wx, double wy, int* mx, int* my) const {
    *mx = static_cast<int>(std::floor((wx - origin_x_) / resolution_));
    *my = static_cast<int>(std::floor((wy - origin_y_) / resolution_));
  }
  // Centre of cell (mx, my).
  void MapToWorld(int mx, int my, double* wx, double* wy) const {
    *wx = origin_x_ + (mx + 0.5) * resolution_;
    *wy = origin_y_ + (my + 0.5) * resolution_;
  }

  void ResetAll(uint8_t value) { std::fill(data_.begin(), data_.end(), value); }
  void ResetAll() { ResetAll(default_value_); }

  // Moves the window so its corner is near (new_origin_x, new_origin_y),
  // snapped to whole cells so that kept cells do not shift by a fraction.
  // Cells the old and new windows share keep their value; new ones get the
  // default value.
  void UpdateOrigin(double new_origin_x, double new_origin_y) {
    const int cell_ox =
        static_cast<int>(std::floor((new_origin_x - origin_x_) / resolution_));
    const int cell_oy =
        static_cast<int>(std::floor((new_origin_y - origin_y_) / resolution_));
    if (cell_ox == 0 && cell_oy == 0) return;
    std::vector<uint8_t> next(data_.size(), default_value_);
    const int x0 = std::max(0, cell_ox), x1 = std::min(size_x_, size_x_ + cell_ox);
    const int y0 = std::max(0, cell_oy), y1 = std::min(size_y_, size_y_ + cell_oy);
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        next[Index(x - cell_ox, y - cell_oy)] = data_[Index(x, y)];
      }
    }
    data_.swap(next);
    origin_x_ += cell_ox * resolution_;
    origin_y_ += cell_oy * resolution_;
  }

 private:
  int size_x_ = 0;
  int size_y_ = 0;
  double resolution_ = 0.05;
  double origin_x_ = 0.0;
  double origin_y_ = 0.0;
  uint8_t default_value_ = kFreeSpace;
  std::vector<uint8_t> data_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_2D_H_
