#include "minibot3d_navigation/dwa/map_grid.h"

#include <algorithm>

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

void MapGrid::Resize(const Costmap2D& costmap) {
  size_x_ = costmap.size_x();
  size_y_ = costmap.size_y();
  cells_ = size_x_ * size_y_;
  dist_.assign(cells_, static_cast<float>(cells_ + 1));
  if (queue_.size() != static_cast<size_t>(cells_)) queue_.resize(cells_);
  if (robot_mask_.size() != static_cast<size_t>(cells_)) {
    robot_mask_.assign(cells_, 0);
  }
  queue_tail_ = 0;
}

void MapGrid::Seed(int index) {
  if (dist_[index] == 0.0f) return;
  dist_[index] = 0.0f;
  queue_[queue_tail_++] = index;
}

void MapGrid::Propagate(const Costmap2D& costmap) {
  const uint8_t* cost = costmap.data();
  const float obstacle = obstacle_distance();
  const float unreachable = unreachable_distance();
  size_t head = 0;
  auto visit = [&](int n, float d) {
    if (dist_[n] != unreachable) return;  // already reached or an obstacle
    if (cost[n] >= kInscribedInflatedObstacle && !robot_mask_[n]) {
      dist_[n] = obstacle;
      return;
    }
    dist_[n] = d;
    queue_[queue_tail_++] = n;
  };
  while (head < queue_tail_) {
    const int c = queue_[head++];
    const int cx = c % size_x_;
    const float d = dist_[c] + 1.0f;
    if (cx > 0) visit(c - 1, d);
    if (cx + 1 < size_x_) visit(c + 1, d);
    if (c >= size_x_) visit(c - size_x_, d);
    if (c + size_x_ < cells_) visit(c + size_x_, d);
  }
}

int MapGrid::SetTargetCells(const Costmap2D& costmap, const Path& plan,
                            const std::vector<int>& robot_cells) {
  Resize(costmap);
  for (int i : robot_cells) robot_mask_[i] = 1;
  bool started = false;
  ForEachDensifiedPoint(plan, costmap.resolution(), [&](double x, double y) {
    int mx, my;
    if (costmap.WorldToMap(x, y, &mx, &my) &&
        costmap.cost(mx, my) != kNoInformation) {
      Seed(costmap.Index(mx, my));
      started = true;
      return true;
    }
    return !started;  // stop once the plan has left the costmap
  });
  const int seeds = static_cast<int>(queue_tail_);
  Propagate(costmap);
  for (int i : robot_cells) robot_mask_[i] = 0;
  return seeds;
}

bool MapGrid::SetTargetCell(const Costmap2D& costmap, int mx, int my,
                            const std::vector<int>& robot_cells) {
  Resize(costmap);
  if (!costmap.InBounds(mx, my)) return false;
  for (int i : robot_cells) robot_mask_[i] = 1;
  Seed(costmap.Index(mx, my));
  Propagate(costmap);
  for (int i : robot_cells) robot_mask_[i] = 0;
  return true;
}

bool MapGrid::FindLocalGoal(const Costmap2D& costmap, const Path& plan,
                            int* goal_mx, int* goal_my, bool* in_obstacle,
                            int* before_block_mx, int* before_block_my) {
  if (before_block_mx != nullptr) *before_block_mx = -1;
  if (before_block_my != nullptr) *before_block_my = -1;
  if (plan.empty()) return false;
  const double x0 = plan.front().x, y0 = plan.front().y;
  bool started = false, away_from_start = false, goal_in_obstacle = true;
  bool blocked = false;
  ForEachDensifiedPoint(plan, costmap.resolution(), [&](double x, double y) {
    away_from_start =
        away_from_start || (x - x0) * (x - x0) + (y - y0) * (y - y0) > 1.0;
    int mx, my;
    if (costmap.WorldToMap(x, y, &mx, &my) &&
        costmap.cost(mx, my) != kNoInformation) {
      const bool obstacle = costmap.cost(mx, my) >= kInscribedInflatedObstacle;
      if (away_from_start && obstacle && !goal_in_obstacle) return false;
      if (obstacle && started && !goal_in_obstacle && !blocked) {
        blocked = true;
        if (before_block_mx != nullptr) *before_block_mx = *goal_mx;
        if (before_block_my != nullptr) *before_block_my = *goal_my;
      }
      *goal_mx = mx;
      *goal_my = my;
      goal_in_obstacle = obstacle;
      started = true;
      return true;
    }
    return !started;
  });
  *in_obstacle = goal_in_obstacle;
  return started;
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
