// One layer of a layered costmap (costmap_2d's Layer plugin interface; Lu,
// Hershberger & Smart, "Layered costmaps for context-sensitive navigation",
// IROS 2014).
//
// A LayeredCostmap owns an ordered list of layers and one master grid.  Every
// update cycle (LayeredCostmap::UpdateMap) calls, in order:
//
//   1. UpdateOrigin(x, y)        rolling window only: the master moved its
//                                corner to (x, y); layers with their own grid
//                                shift it the same way (Costmap2D::
//                                UpdateOrigin with the same argument snaps to
//                                the same whole cells, so grids stay aligned).
//   2. UpdateBounds(robot, &b)   every layer, bottom to top: fold new data into
//                                the layer's own state and grow `b` (world
//                                metres, costmap frame) to cover every cell
//                                whose master cost may change.  A layer may
//                                read the bounds the layers below requested
//                                (the inflation layer widens them by its
//                                radius).  Must not touch the master.
//   3. (master reset to its default value inside the bounds, as cells)
//   4. UpdateCosts(cells, master) every layer, bottom to top: write this
//                                layer's contribution into the master, only
//                                inside `cells`.  Each layer chooses how it
//                                combines: the static layer overwrites, the
//                                obstacle layer takes the maximum, the
//                                inflation layer inflates what is below it.
//
// Outside the cycle:
//   MatchSize(master)      the master's geometry changed (construction, a new
//                          static map): resize own grids, drop their content.
//   OnFootprintChanged(..) the robot's padded footprint changed.
//   Reset()                forget everything learned (clear_costmaps); the
//                          next UpdateBounds must request the whole grid.
//
// Layers are not thread-safe; the owner serialises all calls.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_LAYER_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_LAYER_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

// An axis-aligned box in world metres (costmap frame).  Starts empty.
struct Bounds {
  double min_x = std::numeric_limits<double>::infinity();
  double min_y = std::numeric_limits<double>::infinity();
  double max_x = -std::numeric_limits<double>::infinity();
  double max_y = -std::numeric_limits<double>::infinity();

  // Everything: whatever the grid is, all of it.
  static Bounds All() {
    const double inf = std::numeric_limits<double>::infinity();
    return {-inf, -inf, inf, inf};
  }
  bool empty() const { return !(min_x <= max_x && min_y <= max_y); }
  void Touch(double x, double y) {
    min_x = std::min(min_x, x);
    min_y = std::min(min_y, y);
    max_x = std::max(max_x, x);
    max_y = std::max(max_y, y);
  }
  void Merge(const Bounds& o) {
    min_x = std::min(min_x, o.min_x);
    min_y = std::min(min_y, o.min_y);
    max_x = std::max(max_x, o.max_x);
    max_y = std::max(max_y, o.max_y);
  }
};

// A half-open block of cells [min_i, max_i) x [min_j, max_j).
struct CellBounds {
  int min_i = 0;
  int min_j = 0;
  int max_i = 0;
  int max_j = 0;
  bool empty() const { return min_i >= max_i || min_j >= max_j; }
  static CellBounds Whole(const Costmap2D& grid) {
    return {0, 0, grid.size_x(), grid.size_y()};
  }
};

// The cells covering `bounds`, clamped to the grid (costmap_2d's
// worldToMapEnforceBounds on both corners, max corner inclusive).  Empty
// bounds give empty cells.
inline CellBounds ToCellBounds(const Bounds& bounds, const Costmap2D& grid) {
  if (bounds.empty() || grid.size_x() <= 0 || grid.size_y() <= 0) return {};
  auto cell = [&grid](double w, double origin, int size) {
    const double f = std::floor((w - origin) / grid.resolution());
    if (!(f >= 0.0)) return 0;  // also NaN
    if (f >= size - 1) return size - 1;
    return static_cast<int>(f);
  };
  CellBounds c;
  c.min_i = cell(bounds.min_x, grid.origin_x(), grid.size_x());
  c.min_j = cell(bounds.min_y, grid.origin_y(), grid.size_y());
  c.max_i = cell(bounds.max_x, grid.origin_x(), grid.size_x()) + 1;
  c.max_j = cell(bounds.max_y, grid.origin_y(), grid.size_y()) + 1;
  return c;
}

// True if the two grids have the same size, resolution and origin.
inline bool SameGeometry(const Costmap2D& a, const Costmap2D& b) {
  return a.size_x() == b.size_x() && a.size_y() == b.size_y() &&
         a.resolution() == b.resolution() && a.origin_x() == b.origin_x() &&
         a.origin_y() == b.origin_y();
}

class Layer {
 public:
  virtual ~Layer() = default;

  // "static_layer", "obstacle_layer", "inflation_layer" (costmap_2d names).
  virtual std::string name() const = 0;

  virtual void MatchSize(const Costmap2D& master) { (void)master; }
  virtual void OnFootprintChanged(const Footprint& padded_footprint, double inscribed_radius,
                                  double circumscribed_radius) {
    (void)padded_footprint;
    (void)inscribed_radius;
    (void)circumscribed_radius;
  }
  virtual void UpdateOrigin(double new_origin_x, double new_origin_y) {
    (void)new_origin_x;
    (void)new_origin_y;
  }
  virtual void UpdateBounds(const Pose2& robot, Bounds* bounds) = 0;
  virtual void UpdateCosts(const CellBounds& cells, Costmap2D* master) = 0;
  virtual void Reset() = 0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_LAYER_H_
