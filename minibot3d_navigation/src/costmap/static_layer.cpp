#include "minibot3d_navigation/costmap/static_layer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace minibot3d_navigation {
namespace nav {

StaticLayer::StaticLayer(const CostmapOptions& options)
    : track_unknown_space_(options.track_unknown_space),
      unknown_cost_value_(static_cast<uint8_t>(options.unknown_cost_value)),
      lethal_threshold_(static_cast<uint8_t>(
          std::max(1, std::min(options.lethal_cost_threshold, 100)))),
      trinary_costmap_(options.trinary_costmap) {}

uint8_t StaticLayer::InterpretValue(int8_t signed_value) const {
  const uint8_t value = static_cast<uint8_t>(signed_value);
  if (value == unknown_cost_value_) {
    return track_unknown_space_ ? kNoInformation : kFreeSpace;
  }
  if (value >= lethal_threshold_) return kLethalObstacle;
  if (trinary_costmap_) return kFreeSpace;
  const double scale = static_cast<double>(value) / lethal_threshold_;
  return static_cast<uint8_t>(scale * kLethalObstacle);
}

void StaticLayer::SetMap(const OccupancyGrid& grid) {
  const std::string what = "static layer: map of " + std::to_string(grid.width) + "x" +
                           std::to_string(grid.height) + " cells at resolution " +
                           std::to_string(grid.resolution);
  if (grid.width <= 0 || grid.height <= 0 || !(grid.resolution > 0.0) ||
      !std::isfinite(grid.resolution)) {
    throw std::invalid_argument(what + ": size and resolution must be positive");
  }
  const size_t cells = static_cast<size_t>(grid.width) * grid.height;
  if (grid.data.size() != cells) {
    throw std::invalid_argument(what + ": has " + std::to_string(grid.data.size()) +
                                " values, expected " + std::to_string(cells));
  }
  if (!std::isfinite(grid.origin_x) || !std::isfinite(grid.origin_y) ||
      !std::isfinite(grid.origin_theta)) {
    throw std::invalid_argument(what + ": origin is not finite");
  }
  if (std::abs(grid.origin_theta) > 1e-6) {
    throw std::invalid_argument(what + ": origin yaw " + std::to_string(grid.origin_theta) +
                                " rad is not supported (costmaps are axis-aligned with the map)");
  }
  map_.Resize(grid.width, grid.height, grid.resolution, grid.origin_x, grid.origin_y,
              track_unknown_space_ ? kNoInformation : kFreeSpace);
  uint8_t lut[256];
  for (int v = 0; v < 256; ++v) lut[v] = InterpretValue(static_cast<int8_t>(v));
  uint8_t* out = map_.mutable_data();
  for (size_t k = 0; k < cells; ++k) out[k] = lut[static_cast<uint8_t>(grid.data[k])];
  has_map_ = true;
  has_updated_data_ = true;
}

void StaticLayer::UpdateBounds(const Pose2& /*robot*/, Bounds* bounds) {
  if (!has_updated_data_) return;
  bounds->Touch(map_.origin_x(), map_.origin_y());
  bounds->Touch(map_.origin_x() + map_.size_x_m(), map_.origin_y() + map_.size_y_m());
  has_updated_data_ = false;
}

void StaticLayer::UpdateCosts(const CellBounds& cells, Costmap2D* master) {
  if (!has_map_ || cells.empty()) return;
  const int w = cells.max_i - cells.min_i;
  if (SameGeometry(map_, *master)) {
    for (int j = cells.min_j; j < cells.max_j; ++j) {
      std::memcpy(master->mutable_data() + master->Index(cells.min_i, j),
                  map_.data() + map_.Index(cells.min_i, j), static_cast<size_t>(w));
    }
    return;
  }
  // Map cell under each master cell centre; the column lookup is the same for
  // every row, so compute it once.
  std::vector<int> map_i(static_cast<size_t>(w));
  for (int i = cells.min_i; i < cells.max_i; ++i) {
    double wx, wy;
    master->MapToWorld(i, cells.min_j, &wx, &wy);
    const double f = std::floor((wx - map_.origin_x()) / map_.resolution());
    map_i[i - cells.min_i] = (f >= 0.0 && f < map_.size_x()) ? static_cast<int>(f) : -1;
  }
  for (int j = cells.min_j; j < cells.max_j; ++j) {
    double wx, wy;
    master->MapToWorld(cells.min_i, j, &wx, &wy);
    const double f = std::floor((wy - map_.origin_y()) / map_.resolution());
    if (!(f >= 0.0 && f < map_.size_y())) continue;
    const uint8_t* map_row = map_.data() + map_.Index(0, static_cast<int>(f));
    uint8_t* out = master->mutable_data() + master->Index(cells.min_i, j);
    for (int k = 0; k < w; ++k) {
      if (map_i[k] >= 0) out[k] = map_row[map_i[k]];
    }
  }
}

}  // namespace nav
}  // namespace minibot3d_navigation
