#include "minibot3d_navigation/costmap/obstacle_layer.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "minibot3d_common/line_walker.h"
#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

bool FinitePoint(const Point2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// costmap_2d's cellDistance: ceil(world / resolution) cells, never negative,
// saturated for huge or infinite ranges.
unsigned int CellDistance(double world, double resolution) {
  const double cells = std::ceil(world / resolution);
  if (!(cells > 0.0)) return 0;
  if (cells >= static_cast<double>(INT_MAX)) return INT_MAX;
  return static_cast<unsigned int>(cells);
}

}  // namespace

Observation ObservationFromScan(const LaserScan& scan, const Pose2& sensor_pose,
                                double obstacle_range, double raytrace_range,
                                bool inf_is_valid) {
  if (scan.ranges.size() != scan.angles.size()) {
    throw std::invalid_argument("obstacle layer: scan has " + std::to_string(scan.ranges.size()) +
                                " ranges but " + std::to_string(scan.angles.size()) + " angles");
  }
  if (!minibot3d_common::IsFinite(sensor_pose)) {
    throw std::invalid_argument("obstacle layer: scan sensor pose is not finite");
  }
  Observation obs;
  obs.origin = {sensor_pose.x, sensor_pose.y};
  obs.obstacle_range = obstacle_range;
  obs.raytrace_range = raytrace_range;
  obs.hits.reserve(scan.ranges.size());
  for (size_t k = 0; k < scan.ranges.size(); ++k) {
    const double r = scan.ranges[k];
    const double a = sensor_pose.yaw + scan.angles[k];
    if (std::isfinite(r) && r >= scan.range_min && r < scan.range_max) {
      obs.hits.push_back({sensor_pose.x + r * std::cos(a), sensor_pose.y + r * std::sin(a)});
    } else if (inf_is_valid && std::isinf(r) && r > 0.0 && std::isfinite(scan.range_max)) {
      obs.clear_endpoints.push_back({sensor_pose.x + scan.range_max * std::cos(a),
                                     sensor_pose.y + scan.range_max * std::sin(a)});
    }
  }
  return obs;
}

Observation ObservationFromPoints(const std::vector<double>& xyz, const Point2& origin,
                                  double min_height, double max_height, double obstacle_range,
                                  double raytrace_range) {
  if (!std::isfinite(origin.x) || !std::isfinite(origin.y)) {
    throw std::invalid_argument("obstacle layer: point cloud sensor origin is not finite");
  }
  if (!(min_height <= max_height)) {
    throw std::invalid_argument("obstacle layer: min_obstacle_height > max_obstacle_height");
  }
  Observation obs;
  obs.origin = origin;
  obs.obstacle_range = obstacle_range;
  obs.raytrace_range = raytrace_range;
  for (size_t k = 0; k + 2 < xyz.size(); k += 3) {
    const double x = xyz[k], y = xyz[k + 1], z = xyz[k + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    if (z < min_height || z > max_height) continue;
    obs.hits.push_back({x, y});
  }
  return obs;
}

ObstacleLayer::ObstacleLayer(bool track_unknown_space, double decay_time)
    : track_unknown_space_(track_unknown_space),
      decay_time_(decay_time),
      newest_stamp_(-std::numeric_limits<double>::infinity()) {
  if (!(decay_time >= 0.0) || !std::isfinite(decay_time)) {
    throw std::invalid_argument("obstacle layer: obstacle_decay_time=" +
                                options::Num(decay_time) + " must be >= 0 s (0 = never)");
  }
}

void ObstacleLayer::MatchSize(const Costmap2D& master) {
  grid_.Resize(master.size_x(), master.size_y(), master.resolution(), master.origin_x(),
               master.origin_y(), track_unknown_space_ ? kNoInformation : kFreeSpace);
  ForgetMarks();
  extra_full_bounds_ = true;
}

namespace {
uint64_t CellKey(int64_t x, int64_t y) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(x)) << 32) |
         static_cast<uint64_t>(static_cast<uint32_t>(y));
}
}  // namespace

void ObstacleLayer::ForgetMarks() {
  marks_.clear();
  last_marked_.clear();
  shift_x_ = shift_y_ = 0;
}

void ObstacleLayer::RememberMark(int mx, int my, double stamp) {
  const int64_t x = mx + shift_x_, y = my + shift_y_;
  last_marked_[CellKey(x, y)] = stamp;
  marks_.push_back({x, y, stamp});
}

void ObstacleLayer::Decay(Bounds* bounds) {
  const double before = newest_stamp_ - decay_time_;
  const uint8_t unseen = track_unknown_space_ ? kNoInformation : kFreeSpace;
  while (!marks_.empty() && marks_.front().stamp <= before) {
    const Mark m = marks_.front();
    marks_.pop_front();
    const auto it = last_marked_.find(CellKey(m.x, m.y));
    if (it == last_marked_.end() || it->second != m.stamp) continue;  // marked again since
    last_marked_.erase(it);
    const int64_t mx = m.x - shift_x_, my = m.y - shift_y_;
    if (mx < 0 || my < 0 || mx >= grid_.size_x() || my >= grid_.size_y()) continue;
    if (grid_.cost(static_cast<int>(mx), static_cast<int>(my)) != kLethalObstacle) continue;
    grid_.set_cost(static_cast<int>(mx), static_cast<int>(my), unseen);
    double wx, wy;
    grid_.MapToWorld(static_cast<int>(mx), static_cast<int>(my), &wx, &wy);
    bounds->Touch(wx, wy);
  }
}

void ObstacleLayer::OnFootprintChanged(const Footprint& padded_footprint, double /*inscribed*/,
                                       double /*circumscribed*/) {
  footprint_ = padded_footprint;
}

void ObstacleLayer::UpdateOrigin(double new_origin_x, double new_origin_y) {
  if (grid_.size_x() <= 0) return;
  const double old_x = grid_.origin_x(), old_y = grid_.origin_y();
  grid_.UpdateOrigin(new_origin_x, new_origin_y);
  // The grid moves by whole cells: the marks' cells, counted from where it started, stay put.
  shift_x_ += std::llround((grid_.origin_x() - old_x) / grid_.resolution());
  shift_y_ += std::llround((grid_.origin_y() - old_y) / grid_.resolution());
}

void ObstacleLayer::AddObservation(const Observation& obs) {
  if (!FinitePoint(obs.origin)) {
    throw std::invalid_argument("obstacle layer: observation origin (" +
                                options::Num(obs.origin.x) + ", " + options::Num(obs.origin.y) +
                                ") is not finite; observation dropped");
  }
  if (!(obs.obstacle_range >= 0.0) || !(obs.raytrace_range >= 0.0)) {
    throw std::invalid_argument("obstacle layer: observation obstacle_range=" +
                                options::Num(obs.obstacle_range) + ", raytrace_range=" +
                                options::Num(obs.raytrace_range) +
                                " must be >= 0; observation dropped");
  }
  Observation copy;
  copy.origin = obs.origin;
  copy.obstacle_range = obs.obstacle_range;
  copy.raytrace_range = obs.raytrace_range;
  copy.stamp = obs.stamp;
  copy.hits.reserve(obs.hits.size());
  for (const Point2& p : obs.hits) {
    if (FinitePoint(p)) copy.hits.push_back(p); else ++skipped_points_;
  }
  copy.clear_endpoints.reserve(obs.clear_endpoints.size());
  for (const Point2& p : obs.clear_endpoints) {
    if (FinitePoint(p)) copy.clear_endpoints.push_back(p); else ++skipped_points_;
  }
  pending_.push_back(std::move(copy));
}

void ObstacleLayer::ClearRay(int x0, int y0, int x1, int y1, unsigned int max_cells,
                             bool include_end) {
  // costmap_2d's raytraceLine: the Bresenham line cut to max_cells of its length.
  const int size_x = grid_.size_x();
  const int dx = x1 - x0, dy = y1 - y0;
  const double dist = std::sqrt(static_cast<double>(dx) * dx + static_cast<double>(dy) * dy);
  const double scale = dist == 0.0 ? 1.0 : std::min(1.0, max_cells / dist);
  minibot3d_common::LineWalker walk(x0, y0, x1, y1);
  const unsigned int steps = static_cast<unsigned int>(walk.length() - 1);
  const unsigned int end = std::min(static_cast<unsigned int>(scale * steps), steps);
  uint8_t* data = grid_.mutable_data();
  for (unsigned int i = 0; i < end; ++i) {
    data[static_cast<long>(walk.y()) * size_x + walk.x()] = kFreeSpace;  // NOLINT(runtime/int)
    walk.Next();
  }
  // The cell reached after `end` steps: the hit cell itself (kept) unless the
  // ray was cut short by raytrace_range or by the grid's edge.
  if (end < steps || include_end) {
    data[static_cast<long>(walk.y()) * size_x + walk.x()] = kFreeSpace;  // NOLINT(runtime/int)
  }
}

void ObstacleLayer::RaytraceFreespace(const Observation& obs, Bounds* bounds) {
  if (!(obs.raytrace_range > 0.0)) return;  // a marking-only source
  const double ox = obs.origin.x, oy = obs.origin.y;
  int x0, y0;
  if (!grid_.WorldToMap(ox, oy, &x0, &y0)) return;  // sensor off the grid
  bounds->Touch(ox, oy);
  const double origin_x = grid_.origin_x(), origin_y = grid_.origin_y();
  const double map_end_x = origin_x + grid_.size_x_m();
  const double map_end_y = origin_y + grid_.size_y_m();
  const unsigned int max_cells = CellDistance(obs.raytrace_range, grid_.resolution());

  auto trace = [&](const Point2& p) {
    double wx = p.x, wy = p.y;
    const double a = wx - ox, b = wy - oy;
    bool clipped = false;
    // Cut the ray at the grid's edge (costmap_2d's raytraceFreespace).
    if (wx < origin_x) {
      const double t = (origin_x - ox) / a;
      wx = origin_x;
      wy = oy + b * t;
      clipped = true;
    }
    if (wy < origin_y) {
      const double t = (origin_y - oy) / b;
      wx = ox + a * t;
      wy = origin_y;
      clipped = true;
    }
    if (wx > map_end_x) {
      const double t = (map_end_x - ox) / a;
      wx = map_end_x - .001;
      wy = oy + b * t;
      clipped = true;
    }
    if (wy > map_end_y) {
      const double t = (map_end_y - oy) / b;
      wx = ox + a * t;
      wy = map_end_y - .001;
      clipped = true;
    }
    int x1, y1;
    if (!grid_.WorldToMap(wx, wy, &x1, &y1)) return;
    ClearRay(x0, y0, x1, y1, max_cells, clipped);
    // Bounds: the ray's end, no further than raytrace_range.
    const double ddx = wx - ox, ddy = wy - oy;
    const double full = std::sqrt(ddx * ddx + ddy * ddy);
    const double s = full > 0.0 ? std::min(1.0, obs.raytrace_range / full) : 1.0;
    bounds->Touch(ox + ddx * s, oy + ddy * s);
  };
  for (const Point2& p : obs.hits) trace(p);
  for (const Point2& p : obs.clear_endpoints) trace(p);
}

void ObstacleLayer::ClearFootprint(const Pose2& robot, Bounds* bounds) {
  if (footprint_.empty() || grid_.size_x() <= 0) return;
  const Footprint placed = TransformFootprint(footprint_, robot);
  for (const Point2& p : placed) bounds->Touch(p.x, p.y);
  // Fill the convex polygon row by row between its outline's extreme cells
  // (costmap_2d's convexFillCells), clipped to the grid.
  PolygonOutlineCells(grid_, placed, &scratch_cells_);
  if (scratch_cells_.empty()) return;
  int min_y = INT_MAX, max_y = INT_MIN;
  for (const auto& c : scratch_cells_) {
    min_y = std::min(min_y, c.second);
    max_y = std::max(max_y, c.second);
  }
  const int y_lo = std::max(min_y, 0), y_hi = std::min(max_y, grid_.size_y() - 1);
  if (y_lo > y_hi) return;
  std::vector<int> row_min(static_cast<size_t>(max_y - min_y + 1), INT_MAX);
  std::vector<int> row_max(row_min.size(), INT_MIN);
  for (const auto& c : scratch_cells_) {
    const size_t r = static_cast<size_t>(c.second - min_y);
    row_min[r] = std::min(row_min[r], c.first);
    row_max[r] = std::max(row_max[r], c.first);
  }
  for (int y = y_lo; y <= y_hi; ++y) {
    const size_t r = static_cast<size_t>(y - min_y);
    const int x_lo = std::max(row_min[r], 0), x_hi = std::min(row_max[r], grid_.size_x() - 1);
    for (int x = x_lo; x <= x_hi; ++x) grid_.set_cost(x, y, kFreeSpace);
  }
}

void ObstacleLayer::UpdateBounds(const Pose2& robot, Bounds* bounds) {
  if (grid_.size_x() <= 0) return;
  if (extra_full_bounds_) {
    bounds->Touch(grid_.origin_x(), grid_.origin_y());
    bounds->Touch(grid_.origin_x() + grid_.size_x_m(), grid_.origin_y() + grid_.size_y_m());
    extra_full_bounds_ = false;
  }
  Bounds layer;
  layer.Touch(robot.x, robot.y);
  for (const Observation& obs : pending_) RaytraceFreespace(obs, &layer);
  for (const Observation& obs : pending_) {
    const double sq_range = obs.obstacle_range * obs.obstacle_range;
    for (const Point2& p : obs.hits) {
      const double ddx = p.x - obs.origin.x, ddy = p.y - obs.origin.y;
      if (ddx * ddx + ddy * ddy >= sq_range) continue;
      int mx, my;
      if (!grid_.WorldToMap(p.x, p.y, &mx, &my)) continue;
      grid_.set_cost(mx, my, kLethalObstacle);
      layer.Touch(p.x, p.y);
      if (decay_time_ > 0.0) RememberMark(mx, my, obs.stamp);
    }
    if (std::isfinite(obs.stamp)) newest_stamp_ = std::max(newest_stamp_, obs.stamp);
  }
  pending_.clear();
  if (decay_time_ > 0.0) Decay(&layer);
  ClearFootprint(robot, &layer);
  // One cell of margin so that points on the edge are processed.
  const double r = grid_.resolution();
  layer.min_x -= r;
  layer.min_y -= r;
  layer.max_x += r;
  layer.max_y += r;
  bounds->Merge(layer);
}

void ObstacleLayer::UpdateCosts(const CellBounds& cells, Costmap2D* master) {
  if (cells.empty() || !SameGeometry(grid_, *master)) return;
  const int w = cells.max_i - cells.min_i;
  for (int j = cells.min_j; j < cells.max_j; ++j) {
    const uint8_t* src = grid_.data() + grid_.Index(cells.min_i, j);
    uint8_t* dst = master->mutable_data() + master->Index(cells.min_i, j);
    for (int k = 0; k < w; ++k) {
      const uint8_t v = src[k];
      if (v == kNoInformation) continue;
      if (dst[k] == kNoInformation || dst[k] < v) dst[k] = v;
    }
  }
}

void ObstacleLayer::ClearOutsideSquare(double cx, double cy, double side, bool invert) {
  if (grid_.size_x() <= 0) return;
  int sx, sy, ex, ey;
  grid_.WorldToMapNoBounds(cx - side / 2, cy - side / 2, &sx, &sy);
  grid_.WorldToMapNoBounds(cx - side / 2 + side, cy - side / 2 + side, &ex, &ey);
  for (int y = 0; y < grid_.size_y(); ++y) {
    const bool yrange = y > sy && y < ey;
    for (int x = 0; x < grid_.size_x(); ++x) {
      const bool inside = yrange && x > sx && x < ex;
      if (inside != invert) continue;
      grid_.set_cost(x, y, kNoInformation);
    }
  }
  extra_full_bounds_ = true;
}

void ObstacleLayer::Reset() {
  if (grid_.size_x() > 0) grid_.ResetAll();
  pending_.clear();
  ForgetMarks();
  extra_full_bounds_ = true;
}

}  // namespace nav
}  // namespace minibot3d_navigation
