// A layered costmap: ordered layers composed into one master grid (costmap_2d's
// LayeredCostmap; Lu, Hershberger & Smart, "Layered costmaps for
// context-sensitive navigation", IROS 2014).
//
// Each layer keeps its own knowledge (the map, what the sensors saw) and
// writes its part of the master, in order, only where something may have
// changed: UpdateMap(robot) runs
//   1. rolling window: move the master's corner so the robot is at its
//      centre, shift the layers' grids the same whole number of cells (a
//      moved window is then rewritten entirely);
//      fixed costmap: take the static map's size, resolution and origin if
//      the static layer has a map of another geometry;
//   2. every layer's UpdateBounds, bottom to top, growing one box;
//   3. reset the master to its default (255 if track_unknown_space, else 0)
//      inside that box;
//   4. every layer's UpdateCosts inside the box, bottom to top.
// The usual stack (BuildLayeredCostmap) is static layer (if static_map) ->
// obstacle layer -> inflation layer; see layer.h for the layer lifecycle.
//
// Not thread-safe: the node serialises UpdateMap, observations and readers.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_LAYERED_COSTMAP_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_LAYERED_COSTMAP_H_

#include <memory>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/costmap_options.h"
#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/costmap/inflation_layer.h"
#include "minibot3d_navigation/costmap/layer.h"
#include "minibot3d_navigation/costmap/obstacle_layer.h"
#include "minibot3d_navigation/costmap/static_layer.h"

namespace minibot3d_navigation {
namespace nav {

class LayeredCostmap {
 public:
  // A master of size_x x size_y cells with its corner at (origin_x,
  // origin_y); a rolling window re-centres on the first UpdateMap.  Throws
  // std::invalid_argument for a non-positive size or resolution.
  LayeredCostmap(int size_x, int size_y, double resolution, double origin_x, double origin_y,
                 bool rolling_window, bool track_unknown_space);

  LayeredCostmap(LayeredCostmap&&) = default;
  LayeredCostmap& operator=(LayeredCostmap&&) = default;

  // Adds a layer on top of the others (sized to the master, told the
  // footprint if one is set).
  void AddLayer(std::unique_ptr<Layer> layer);

  // The robot's padded footprint (robot frame).  Throws std::invalid_argument
  // for fewer than 3 points.  Tells every layer; the inflation layer then
  // re-inflates everything at the next update.
  void SetFootprint(const Footprint& padded_footprint);

  // Changes the master's geometry (content reset to the default) and every
  // layer's; the next update rewrites everything.
  void Resize(int size_x, int size_y, double resolution, double origin_x, double origin_y);

  // Gives the static layer a new map; a fixed costmap takes its geometry
  // now.  Throws std::logic_error if there is no static layer, and
  // std::invalid_argument (from StaticLayer::SetMap) for a malformed grid.
  void SetStaticMap(const OccupancyGrid& grid);

  // One update cycle at the robot's pose in the costmap frame (see the
  // header comment).  Throws std::invalid_argument for a non-finite pose.
  void UpdateMap(const Pose2& robot);

  // clear_costmaps: master to its default, every layer Reset(); the next
  // UpdateMap rebuilds the whole master (static map, re-inflated).
  void ResetLayers();

  // clear_costmap_recovery (conservative/aggressive reset): every obstacle
  // layer forgets what lies outside the square of side `reset_distance`
  // centred on the robot, then UpdateMap(robot) runs so the master shows it
  // at once.  Throws std::invalid_argument for a negative or NaN distance.
  void ClearExceptAround(const Pose2& robot, double reset_distance);

  const Costmap2D& costmap() const { return costmap_; }
  const Footprint& footprint() const { return footprint_; }
  double inscribed_radius() const { return inscribed_radius_; }
  double circumscribed_radius() const { return circumscribed_radius_; }
  bool rolling_window() const { return rolling_window_; }
  bool track_unknown_space() const { return track_unknown_space_; }
  // The block of cells the last UpdateMap rewrote (empty if none); what a
  // node publishes as an OccupancyGridUpdate.
  const CellBounds& last_updated_cells() const { return last_updated_cells_; }

  size_t num_layers() const { return layers_.size(); }
  Layer* layer(size_t i) const { return layers_.at(i).get(); }
  // The first layer of each kind, or nullptr.
  StaticLayer* static_layer() const { return static_layer_; }
  ObstacleLayer* obstacle_layer() const { return obstacle_layer_; }
  InflationLayer* inflation_layer() const { return inflation_layer_; }

 private:
  void MatchStaticMapGeometry();

  Costmap2D costmap_;
  bool rolling_window_;
  bool track_unknown_space_;
  std::vector<std::unique_ptr<Layer>> layers_;
  StaticLayer* static_layer_ = nullptr;
  ObstacleLayer* obstacle_layer_ = nullptr;
  InflationLayer* inflation_layer_ = nullptr;
  Footprint footprint_;
  double inscribed_radius_ = 0.0;
  double circumscribed_radius_ = 0.0;
  CellBounds last_updated_cells_;
};

// costmap_2d's old-style stack from one options struct: validates the options
// (throws std::invalid_argument listing every problem), then builds static
// layer (if static_map) -> obstacle layer -> inflation layer with the padded
// EffectiveFootprint.  The master is width x height metres at `resolution`
// with its corner at (origin_x, origin_y) until a static map (fixed costmap)
// or the first update (rolling window) says otherwise.
LayeredCostmap BuildLayeredCostmap(const CostmapOptions& options);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_LAYERED_COSTMAP_H_
