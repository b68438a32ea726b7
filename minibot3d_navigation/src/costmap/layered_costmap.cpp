#include "minibot3d_navigation/costmap/layered_costmap.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {

LayeredCostmap::LayeredCostmap(int size_x, int size_y, double resolution, double origin_x,
                               double origin_y, bool rolling_window, bool track_unknown_space)
    : costmap_(size_x, size_y, resolution, origin_x, origin_y,
               track_unknown_space ? kNoInformation : kFreeSpace),
      rolling_window_(rolling_window),
      track_unknown_space_(track_unknown_space) {}

void LayeredCostmap::AddLayer(std::unique_ptr<Layer> layer) {
  if (!layer) throw std::invalid_argument("LayeredCostmap::AddLayer: null layer");
  layer->MatchSize(costmap_);
  if (!footprint_.empty()) {
    layer->OnFootprintChanged(footprint_, inscribed_radius_, circumscribed_radius_);
  }
  if (static_layer_ == nullptr) static_layer_ = dynamic_cast<StaticLayer*>(layer.get());
  if (obstacle_layer_ == nullptr) obstacle_layer_ = dynamic_cast<ObstacleLayer*>(layer.get());
  if (inflation_layer_ == nullptr) inflation_layer_ = dynamic_cast<InflationLayer*>(layer.get());
  layers_.push_back(std::move(layer));
}

void LayeredCostmap::SetFootprint(const Footprint& padded_footprint) {
  if (padded_footprint.size() < 3) {
    throw std::invalid_argument("LayeredCostmap::SetFootprint: footprint has " +
                                std::to_string(padded_footprint.size()) +
                                " points, needs at least 3");
  }
  footprint_ = padded_footprint;
  FootprintRadii(footprint_, &inscribed_radius_, &circumscribed_radius_);
  for (auto& layer : layers_) {
    layer->OnFootprintChanged(footprint_, inscribed_radius_, circumscribed_radius_);
  }
}

void LayeredCostmap::Resize(int size_x, int size_y, double resolution, double origin_x,
                            double origin_y) {
  costmap_.Resize(size_x, size_y, resolution, origin_x, origin_y, costmap_.default_value());
  for (auto& layer : layers_) layer->MatchSize(costmap_);
}

void LayeredCostmap::MatchStaticMapGeometry() {
  if (rolling_window_ || static_layer_ == nullptr || !static_layer_->has_map()) return;
  const Costmap2D& map = static_layer_->map();
  if (SameGeometry(map, costmap_)) return;
  Resize(map.size_x(), map.size_y(), map.resolution(), map.origin_x(), map.origin_y());
}

void LayeredCostmap::SetStaticMap(const OccupancyGrid& grid) {
  if (static_layer_ == nullptr) {
    throw std::logic_error("LayeredCostmap::SetStaticMap: this costmap has no static layer "
                           "(static_map is false)");
  }
  static_layer_->SetMap(grid);
  MatchStaticMapGeometry();
}

void LayeredCostmap::UpdateMap(const Pose2& robot) {
  if (!minibot3d_common::IsFinite(robot)) {
    throw std::invalid_argument("LayeredCostmap::UpdateMap: robot pose (" +
                                options::Num(robot.x) + ", " + options::Num(robot.y) + ", " +
                                options::Num(robot.yaw) + ") is not finite");
  }
  Bounds bounds;
  if (rolling_window_) {
    const double new_origin_x = robot.x - costmap_.size_x_m() / 2;
    const double new_origin_y = robot.y - costmap_.size_y_m() / 2;
    const double old_x = costmap_.origin_x(), old_y = costmap_.origin_y();
    costmap_.UpdateOrigin(new_origin_x, new_origin_y);
    for (auto& layer : layers_) layer->UpdateOrigin(new_origin_x, new_origin_y);
    if (costmap_.origin_x() != old_x || costmap_.origin_y() != old_y) {
      // Cells that entered the window hold only the default: rewrite it all.
      bounds.Touch(costmap_.origin_x(), costmap_.origin_y());
      bounds.Touch(costmap_.origin_x() + costmap_.size_x_m(),
                   costmap_.origin_y() + costmap_.size_y_m());
    }
  } else {
    MatchStaticMapGeometry();
  }

  for (auto& layer : layers_) layer->UpdateBounds(robot, &bounds);

  const CellBounds cells = ToCellBounds(bounds, costmap_);
  last_updated_cells_ = cells;
  if (cells.empty()) return;
  const uint8_t def = costmap_.default_value();
  for (int j = cells.min_j; j < cells.max_j; ++j) {
    std::memset(costmap_.mutable_data() + costmap_.Index(cells.min_i, j), def,
                static_cast<size_t>(cells.max_i - cells.min_i));
  }
  for (auto& layer : layers_) layer->UpdateCosts(cells, &costmap_);
}

void LayeredCostmap::ResetLayers() {
  costmap_.ResetAll();
  for (auto& layer : layers_) layer->Reset();
}

void LayeredCostmap::ClearExceptAround(const Pose2& robot, double reset_distance) {
  if (!(reset_distance >= 0.0)) {
    throw std::invalid_argument("LayeredCostmap::ClearExceptAround: reset_distance=" +
                                options::Num(reset_distance) + " must be >= 0");
  }
  for (auto& layer : layers_) {
    if (auto* obstacles = dynamic_cast<ObstacleLayer*>(layer.get())) {
      obstacles->ClearOutsideSquare(robot.x, robot.y, reset_distance);
    }
  }
  UpdateMap(robot);
}

LayeredCostmap BuildLayeredCostmap(const CostmapOptions& o) {
  ValidateCostmapOptions(o);
  LayeredCostmap costmap(CostmapCells(o.width, o.resolution), CostmapCells(o.height, o.resolution),
                         o.resolution, o.origin_x, o.origin_y, o.rolling_window,
                         o.track_unknown_space);
  if (o.static_map) costmap.AddLayer(std::make_unique<StaticLayer>(o));
  costmap.AddLayer(std::make_unique<ObstacleLayer>(o.track_unknown_space, o.obstacle_decay_time));
  costmap.AddLayer(std::make_unique<InflationLayer>(o.inflation_radius, o.cost_scaling_factor));
  costmap.SetFootprint(EffectiveFootprint(o));
  return costmap;
}

}  // namespace nav
}  // namespace minibot3d_navigation
