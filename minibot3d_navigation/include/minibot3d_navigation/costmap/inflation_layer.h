// The inflation layer: cost decaying with the distance to the nearest lethal
// cell (costmap_2d's InflationLayer; Lu, Hershberger & Smart, IROS 2014).
//
// Cost of a cell at distance d cells (Euclidean, cell centre to cell centre)
// from the nearest lethal cell, exactly costmap_2d's computeCost:
//   d == 0                           254 lethal
//   d * resolution <= inscribed      253 inscribed (the robot's centre here
//                                        puts its footprint on the obstacle)
//   otherwise                        (uint8)(252 * exp(-cost_scaling_factor *
//                                        (d * resolution - inscribed)))
// for d <= cell_inflation_radius = ceil(inflation_radius / resolution) cells,
// 0 beyond.  A cell only ever gets more expensive (max with what the layers
// below wrote), and an unknown (255) cell keeps 255 unless the inflated cost
// is 253 or 254 (costmap_2d with inflate_unknown = false).
//
// How it is computed (not how costmap_2d does it): costmap_2d grows a
// priority-ordered wavefront from every lethal cell.  Here a kernel of costs,
// indexed by the cell offset (|dx|, |dy|), is precomputed per radius,
// resolution and inscribed radius.  The lethal cells are cut into blocks
// (horizontal runs, merged with identical runs in the rows below: a wall or a
// desk is one block), and each block stamps the kernel once per output row:
// the row's distance to the block picks the kernel row, the block's ends
// stamp its two halves and the cells between get its centre value.  The
// maximum of the stamps (SIMD byte max) is each cell's cost for its nearest
// lethal cell, because the cost only falls with distance.  Only the update
// bounds are written; lethal cells up to cell_inflation_radius outside them
// are used as sources.  The work is one kernel row per block and output row,
// instead of one heap operation per inflated cell (bench/costmap_bench.cpp
// times it on a 2000 x 2000 office map).
//
// This is the exact nearest-obstacle distance; costmap_2d's wavefront can,
// where two obstacles' fronts meet, give a cell the distance to the farther
// one, so rarely a cell here costs a little more than in costmap_2d, never
// less.  Around a single obstacle the two agree exactly.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_INFLATION_LAYER_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_INFLATION_LAYER_H_

#include <cstdint>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/layer.h"

namespace minibot3d_navigation {
namespace nav {

class InflationLayer : public Layer {
 public:
  // Throws std::invalid_argument for a negative or non-finite value.
  InflationLayer(double inflation_radius, double cost_scaling_factor);

  // Changes the parameters (dynamic reconfigure); the next update
  // re-inflates the whole grid.  Throws like the constructor.
  void SetInflationParameters(double inflation_radius, double cost_scaling_factor);

  // costmap_2d's computeCost for a distance in cells (uses the current
  // resolution and inscribed radius).
  uint8_t ComputeCost(double distance_cells) const;

  double inflation_radius() const { return inflation_radius_; }
  double cost_scaling_factor() const { return weight_; }
  double inscribed_radius() const { return inscribed_radius_; }
  int cell_inflation_radius() const { return cell_inflation_radius_; }

  std::string name() const override { return "inflation_layer"; }
  void MatchSize(const Costmap2D& master) override;
  void OnFootprintChanged(const Footprint& padded_footprint, double inscribed_radius,
                          double circumscribed_radius) override;
  // Widens the bounds by inflation_radius (and by the previous cycle's
  // bounds, as costmap_2d); everything after a parameter, size or footprint
  // change.
  void UpdateBounds(const Pose2& robot, Bounds* bounds) override;
  void UpdateCosts(const CellBounds& cells, Costmap2D* master) override;
  void Reset() override { need_reinflation_ = true; }

 private:
  void ComputeKernel();

  double inflation_radius_;
  double weight_;
  double inscribed_radius_ = 0.0;
  double resolution_ = 0.0;
  int cell_inflation_radius_ = 0;
  bool need_reinflation_ = true;
  Bounds last_bounds_;

  // Kernel row |dy| covers dx in [-half_width_[|dy|], half_width_[|dy|]],
  // stored from kernel_[row_start_[|dy|]].
  std::vector<uint8_t> kernel_;
  std::vector<int> half_width_;
  std::vector<size_t> row_start_;
  std::vector<uint8_t> buffer_;  // inflated costs of the update block
  struct Block {                 // lethal cells [a, b] x [j0, current row)
    int a, b, j0;
  };
  std::vector<Block> open_blocks_, next_blocks_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_INFLATION_LAYER_H_
