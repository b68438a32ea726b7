// The obstacle layer: what the sensors see now (costmap_2d's ObstacleLayer;
// Lu, Hershberger & Smart, IROS 2014; ray-traced clearing after
// Marder-Eppstein et al., "The Office Marathon", ICRA 2010).
//
// The layer keeps its own grid, the master's size, across updates (a rolling
// window shifts it with the master).  Observations are buffered by
// AddObservation() and folded in by the next UpdateBounds():
//   1. clearing: from the sensor origin, a Bresenham ray towards every hit and
//      every clear endpoint sets cells free, up to but not including the end
//      cell, and no further than raytrace_range (costmap_2d's raytraceLine with
//      max_length = ceil(raytrace_range / resolution) cells).  Rays whose end
//      lies off the grid are first cut at the grid's edge, as costmap_2d does;
//      a sensor off the grid clears nothing.
//   2. marking: every hit closer than obstacle_range to the origin (strictly,
//      as costmap_2d) that falls on the grid becomes lethal (254).
//   3. with a decay time (obstacle_decay_time, not in costmap_2d; the
//      spatio-temporal voxel layer's voxel_decay, Macenski et al. 2020), a
//      lethal cell no observation has marked for that long returns to what it
//      was before anything was seen there (unknown with track_unknown_space,
//      else free): someone who walked off where no ray reaches (behind
//      another, beyond raytrace_range) leaves no obstacle behind. Time is the
//      newest observation's stamp, so nothing decays while no sensor reports.
//      The marks wait in a queue, oldest first, keyed by their cell counted
//      from where the grid started (a rolling window's shifts are whole
//      cells), so a decay pass costs only the marks that expire.
//   4. the robot's padded footprint, filled, is set free (costmap_2d's
//      footprint_clearing_enabled): the robot is never its own obstacle.
// All clearing happens before any marking, so a hit on one ray is not erased
// by a neighbouring ray that passes through it.  Each observation is used by
// one update and dropped (costmap_2d, with observation_persistence 0, keeps
// the latest scan and re-applies it every cycle until the next one arrives;
// here the node adds each scan once).
//
// UpdateCosts combines with the master by maximum, skipping this layer's
// unknown cells (costmap_2d's updateWithMax): a free cell seen by the sensor
// replaces an unknown master cell, a lethal one wins over anything.  With
// track_unknown_space the grid starts unknown (255); otherwise it starts free.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_OBSTACLE_LAYER_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_OBSTACLE_LAYER_H_

#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

#include "minibot3d_navigation/costmap/layer.h"

namespace minibot3d_navigation {
namespace nav {

// One sensor reading, already in the costmap's frame.
struct Observation {
  Point2 origin;                        // sensor position
  std::vector<Point2> hits;             // endpoints that clear up to and mark
  std::vector<Point2> clear_endpoints;  // endpoints that only clear (no return)
  double obstacle_range = 2.5;  // 0: marks nothing (a clearing-only source)
  double raytrace_range = 3.0;  // 0: clears nothing (a marking-only source)
  double stamp = 0.0;           // s, when the sensor saw it (the decay's clock)
};

// A planar laser scan as an Observation in the costmap's frame, converted as
// costmap_2d's laser callbacks do:
//   range_min <= r < range_max (finite)  -> hit at r
//   r == +inf and inf_is_valid           -> clear endpoint at range_max
//   anything else (NaN, -inf, out of the sensor's limits) -> dropped
// `sensor_pose` is the laser's pose in the costmap frame; beam k points at
// sensor_pose.yaw + scan.angles[k].  scan.sensor_in_base is ignored (the caller
// has already composed it into sensor_pose).  Throws std::invalid_argument if
// ranges and angles differ in length or the sensor pose is not finite.
Observation ObservationFromScan(const LaserScan& scan, const Pose2& sensor_pose,
                                double obstacle_range, double raytrace_range,
                                bool inf_is_valid);

// Points (x, y, z in the costmap's frame, z above the floor) as an Observation, as costmap_2d's
// point-cloud sources: points outside [min_height, max_height] or not finite are dropped; the
// others are hits seen from `origin` (the sensor's position in the costmap's frame), cleared
// towards and marked up to the given ranges like a scan's. Throws std::invalid_argument for a
// non-finite origin or min_height > max_height.
Observation ObservationFromPoints(const std::vector<double>& xyz, const Point2& origin,
                                  double min_height, double max_height, double obstacle_range,
                                  double raytrace_range);

class ObstacleLayer : public Layer {
 public:
  // decay_time: s after which a mark no observation renewed is forgotten
  // (step 3 above); 0: never (costmap_2d). Throws std::invalid_argument for a
  // negative or non-finite value.
  explicit ObstacleLayer(bool track_unknown_space, double decay_time = 0.0);

  // Buffers an observation for the next UpdateBounds.  Throws
  // std::invalid_argument (nothing buffered) if the origin is not finite or a
  // range is negative or NaN; single non-finite points are skipped and
  // counted in skipped_points().
  void AddObservation(const Observation& observation);
  size_t pending_observations() const { return pending_.size(); }
  uint64_t skipped_points() const { return skipped_points_; }

  // Sets every cell outside the square of side `side` centred on (cx, cy) to
  // unknown, as clear_costmap_recovery's clearMap (cells strictly inside the
  // square's cell bounds are kept).  With invert, clears inside instead.
  // The next UpdateBounds requests the whole grid.
  void ClearOutsideSquare(double cx, double cy, double side, bool invert = false);

  // This layer's grid (same geometry as the master).
  const Costmap2D& grid() const { return grid_; }

  std::string name() const override { return "obstacle_layer"; }
  void MatchSize(const Costmap2D& master) override;
  void OnFootprintChanged(const Footprint& padded_footprint, double inscribed_radius,
                          double circumscribed_radius) override;
  void UpdateOrigin(double new_origin_x, double new_origin_y) override;
  void UpdateBounds(const Pose2& robot, Bounds* bounds) override;
  void UpdateCosts(const CellBounds& cells, Costmap2D* master) override;
  // Forgets all obstacles and pending observations.
  void Reset() override;

 private:
  void RaytraceFreespace(const Observation& obs, Bounds* bounds);
  void ClearRay(int x0, int y0, int x1, int y1, unsigned int max_cells, bool include_end);
  void ClearFootprint(const Pose2& robot, Bounds* bounds);
  void RememberMark(int mx, int my, double stamp);
  void Decay(Bounds* bounds);
  void ForgetMarks();

  struct Mark {
    int64_t x, y;  // cell, counted from where the grid started
    double stamp;
  };

  bool track_unknown_space_;
  Costmap2D grid_;
  std::vector<Observation> pending_;
  Footprint footprint_;
  bool extra_full_bounds_ = false;  // after Reset/Clear: request everything
  uint64_t skipped_points_ = 0;
  std::vector<std::pair<int, int>> scratch_cells_;
  double decay_time_;
  double newest_stamp_;
  int64_t shift_x_ = 0, shift_y_ = 0;  // whole cells the grid has moved
  std::deque<Mark> marks_;              // oldest first
  std::unordered_map<uint64_t, double> last_marked_;  // cell -> newest stamp
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_OBSTACLE_LAYER_H_
