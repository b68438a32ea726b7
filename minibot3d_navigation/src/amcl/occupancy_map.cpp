#include "minibot3d_navigation/amcl/occupancy_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace minibot3d_navigation {
namespace amcl {

MapModel::MapModel(const OccupancyGrid& grid, double max_occ_dist) {
  std::vector<std::string> errors;
  if (grid.width <= 0 || grid.height <= 0) {
    errors.push_back("size " + std::to_string(grid.width) + "x" +
                     std::to_string(grid.height) + " must be positive");
  }
  if (!(std::isfinite(grid.resolution) && grid.resolution > 0.0)) {
    std::ostringstream os;
    os << "resolution=" << grid.resolution << " must be > 0";
    errors.push_back(os.str());
  }
  if (!(std::isfinite(grid.origin_x) && std::isfinite(grid.origin_y) &&
        std::isfinite(grid.origin_theta))) {
    errors.push_back("origin must be finite");
  }
  if (!(std::isfinite(max_occ_dist) && max_occ_dist > 0.0)) {
    std::ostringstream os;
    os << "laser_likelihood_max_dist=" << max_occ_dist << " must be > 0";
    errors.push_back(os.str());
  }
  if (grid.width > 0 && grid.height > 0 &&
      grid.data.size() != static_cast<size_t>(grid.width) * grid.height) {
    errors.push_back("data has " + std::to_string(grid.data.size()) +
                     " cells, expected width*height=" +
                     std::to_string(static_cast<size_t>(grid.width) *
                                    grid.height));
  }
  if (!errors.empty()) {
    std::string msg = "invalid occupancy grid: ";
    for (size_t k = 0; k < errors.size(); ++k) {
      msg += (k ? "; " : "") + errors[k];
    }
    throw std::invalid_argument(msg);
  }

  width_ = grid.width;
  height_ = grid.height;
  resolution_ = grid.resolution;
  inv_resolution_ = 1.0 / grid.resolution;
  origin_ = {grid.origin_x, grid.origin_y, grid.origin_theta};
  cos_origin_ = std::cos(grid.origin_theta);
  sin_origin_ = std::sin(grid.origin_theta);
  max_occ_dist_ = max_occ_dist;

  const size_t n = grid.data.size();
  state_.resize(n);
  size_t occupied = 0;
  for (size_t k = 0; k < n; ++k) {
    const int v = grid.data[k];
    if (v < -1 || v > 100) {
      throw std::invalid_argument(
          "invalid occupancy grid: cell " + std::to_string(k) + " (i=" +
          std::to_string(k % width_) + ", j=" + std::to_string(k / width_) +
          ") has value " + std::to_string(v) + " outside -1..100");
    }
    if (v >= 0 && v <= kMaxFreeValue) {
      state_[k] = kFree;
      free_cells_.push_back(static_cast<int>(k));
    } else if (v >= kMinOccupiedValue) {
      state_[k] = kOccupied;
      ++occupied;
    } else {
      state_[k] = kUnknown;
    }
  }
  if (free_cells_.empty()) {
    throw std::invalid_argument(
        "occupancy grid " + std::to_string(width_) + "x" +
        std::to_string(height_) + " has no free cells (value 0.." +
        std::to_string(kMaxFreeValue) +
        "): cannot localize or sample particles in it");
  }

  distance_.assign(n, static_cast<float>(max_occ_dist_));
  if (occupied > 0) {
    // distanceTransform measures, for every non-zero pixel, the distance to
    // the nearest zero pixel: occupied cells are the zeros.  Row j is grid y.
    cv::Mat src(height_, width_, CV_8UC1);
    for (int j = 0; j < height_; ++j) {
      uint8_t* row = src.ptr<uint8_t>(j);
      for (int i = 0; i < width_; ++i) {
        row[i] = state_[Index(i, j)] == kOccupied ? 0 : 255;
      }
    }
    cv::Mat dist;
    cv::distanceTransform(src, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE,
                          CV_32F);
    const float cap = static_cast<float>(max_occ_dist_);
    const float res = static_cast<float>(resolution_);
    for (int j = 0; j < height_; ++j) {
      const float* row = dist.ptr<float>(j);
      for (int i = 0; i < width_; ++i) {
        distance_[Index(i, j)] = std::min(row[i] * res, cap);
      }
    }
  }
}

Pose2 MapModel::WorldToGridFrame(const Pose2& w) const {
  const double dx = w.x - origin_.x, dy = w.y - origin_.y;
  return {cos_origin_ * dx + sin_origin_ * dy,
          -sin_origin_ * dx + cos_origin_ * dy, AngleDiff(w.yaw, origin_.yaw)};
}

Pose2 MapModel::GridFrameToWorld(const Pose2& g) const {
  return {origin_.x + cos_origin_ * g.x - sin_origin_ * g.y,
          origin_.y + sin_origin_ * g.x + cos_origin_ * g.y,
          NormalizeAngle(g.yaw + origin_.yaw)};
}

bool MapModel::WorldToCell(double wx, double wy, int* i, int* j) const {
  const Pose2 g = WorldToGridFrame({wx, wy, 0.0});
  const double fi = std::floor(g.x * inv_resolution_);
  const double fj = std::floor(g.y * inv_resolution_);
  if (!(fi >= 0.0 && fj >= 0.0 && fi < width_ && fj < height_)) return false;
  *i = static_cast<int>(fi);
  *j = static_cast<int>(fj);
  return true;
}

void MapModel::CellCenterToWorld(int i, int j, double* wx, double* wy) const {
  const Pose2 w =
      GridFrameToWorld({(i + 0.5) * resolution_, (j + 0.5) * resolution_, 0.0});
  *wx = w.x;
  *wy = w.y;
}

double MapModel::CalcRangeGrid(double gx, double gy, double angle,
                               double max_range) const {
  int i = static_cast<int>(std::floor(gx * inv_resolution_));
  int j = static_cast<int>(std::floor(gy * inv_resolution_));
  if (!InBounds(i, j) || state_[Index(i, j)] != kFree) return 0.0;
  const double dx = std::cos(angle), dy = std::sin(angle);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // t_max_*: ray length at which the next vertical / horizontal cell border
  // is crossed; t_delta_*: ray length between two such borders.
  const int step_i = dx > 0.0 ? 1 : -1;
  const int step_j = dy > 0.0 ? 1 : -1;
  double t_max_x = kInf, t_max_y = kInf, t_delta_x = kInf, t_delta_y = kInf;
  if (dx != 0.0) {
    t_max_x = ((i + (dx > 0.0 ? 1 : 0)) * resolution_ - gx) / dx;
    t_delta_x = resolution_ / std::fabs(dx);
  }
  if (dy != 0.0) {
    t_max_y = ((j + (dy > 0.0 ? 1 : 0)) * resolution_ - gy) / dy;
    t_delta_y = resolution_ / std::fabs(dy);
  }
  while (true) {
    double t;
    if (t_max_x < t_max_y) {
      t = t_max_x;
      t_max_x += t_delta_x;
      i += step_i;
    } else {
      t = t_max_y;
      t_max_y += t_delta_y;
      j += step_j;
    }
    if (t >= max_range) return max_range;
    if (!InBounds(i, j) || state_[Index(i, j)] != kFree) {
      return std::max(t, 0.0);
    }
  }
}

double MapModel::CalcRange(const Pose2& world_ray, double max_range) const {
  const Pose2 g = WorldToGridFrame(world_ray);
  return CalcRangeGrid(g.x, g.y, g.yaw, max_range);
}

Pose2 MapModel::SampleFreePose(std::mt19937_64* rng) const {
  std::uniform_int_distribution<size_t> pick(0, free_cells_.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int k = free_cells_[pick(*rng)];
  const int i = k % width_, j = k / width_;
  const double gx = (i + unit(*rng)) * resolution_;
  const double gy = (j + unit(*rng)) * resolution_;
  const double yaw = -kPi + 2.0 * kPi * unit(*rng);
  Pose2 w = GridFrameToWorld({gx, gy, 0.0});
  w.yaw = NormalizeAngle(yaw);
  return w;
}

size_t MapModel::MemoryBytes() const {
  return state_.capacity() * sizeof(int8_t) +
         distance_.capacity() * sizeof(float) +
         free_cells_.capacity() * sizeof(int);
}

}  // namespace amcl
}  // namespace minibot3d_navigation
