// The static layer: the map (map_server / SLAM) as costs (costmap_2d's
// StaticLayer; Lu, Hershberger & Smart, IROS 2014).
//
// SetMap() converts every OccupancyGrid value once, as costmap_2d's
// interpretValue does:
//   value == unknown_cost_value  -> 255 unknown if track_unknown_space,
//                                   else 0 free
//   value >= lethal_cost_threshold -> 254 lethal
//   otherwise                    -> 0 free if trinary_costmap, else
//                                   value / lethal_cost_threshold * 254
// (values are compared as unsigned bytes, so -1 == 255, as in costmap_2d).
//
// UpdateCosts overwrites the master inside the update bounds wherever the map
// covers it (costmap_2d's updateWithTrueOverwrite), unknown included; master
// cells off the map keep the master's default.  When the master has the map's
// exact geometry (a fixed global costmap, which LayeredCostmap resizes to the
// map) this is a row copy; otherwise (a rolling window, or a costmap of
// another size) each master cell takes the map cell under its centre.
//
// The map frame is assumed to be the costmap's frame: no transform is
// applied.  For a rolling local costmap in `odom` that is only right if odom
// and map coincide (as in costmap_2d, which looks the map up through tf,
// this layer would need the map->odom transform; the node must not add a
// static layer to an odom-frame rolling window unless it re-expresses the
// map).  Maps with a rotated origin (origin_theta != 0) are rejected, since
// costmap_2d silently ignores the rotation.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_STATIC_LAYER_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_STATIC_LAYER_H_

#include <cstdint>
#include <string>

#include "minibot3d_navigation/costmap/costmap_options.h"
#include "minibot3d_navigation/costmap/layer.h"

namespace minibot3d_navigation {
namespace nav {


class StaticLayer : public Layer {
 public:
  // Reads track_unknown_space, unknown_cost_value, lethal_cost_threshold,
  // trinary_costmap.
  explicit StaticLayer(const CostmapOptions& options);

  // Replaces the map.  Throws std::invalid_argument naming the problem for a
  // malformed grid (non-positive size or resolution, data size mismatch,
  // non-finite or rotated origin); the previous map is kept then.
  void SetMap(const OccupancyGrid& grid);

  bool has_map() const { return has_map_; }
  // The map as costs, with the map's geometry.  Empty before SetMap().
  const Costmap2D& map() const { return map_; }

  // One OccupancyGrid value as a cost (see the header comment).
  uint8_t InterpretValue(int8_t value) const;

  std::string name() const override { return "static_layer"; }
  // Requests the map's extent after a new map or a Reset().
  void UpdateBounds(const Pose2& robot, Bounds* bounds) override;
  void UpdateCosts(const CellBounds& cells, Costmap2D* master) override;
  // Keeps the map (costmap_2d re-subscribes and gets the same map back) and
  // requests a full rewrite at the next update.
  void Reset() override { has_updated_data_ = has_map_; }

 private:
  bool track_unknown_space_;
  uint8_t unknown_cost_value_;
  uint8_t lethal_threshold_;
  bool trinary_costmap_;

  bool has_map_ = false;
  bool has_updated_data_ = false;
  Costmap2D map_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_STATIC_LAYER_H_
