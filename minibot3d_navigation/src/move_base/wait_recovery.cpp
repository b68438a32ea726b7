#include "minibot3d_navigation/move_base/wait_recovery.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <utility>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_navigation {
namespace nav {

WaitRecovery::WaitRecovery(std::string name, const WaitOptions& options, Footprint footprint)
    : name_(std::move(name)), options_(options), footprint_(std::move(footprint)) {
  double inscribed = 0.0;
  if (!footprint_.empty()) FootprintRadii(footprint_, &inscribed, &circumscribed_);
}

double WaitRecovery::ClearanceAhead(const Costmap2D& costmap, const Pose2& pose,
                                    double range) const {
  double best = std::numeric_limits<double>::infinity();
  if (footprint_.empty()) return best;
  const Footprint placed = TransformFootprint(footprint_, pose);
  const double reach = circumscribed_ + range;
  int x0, y0, x1, y1;
  costmap.WorldToMapNoBounds(pose.x - reach, pose.y - reach, &x0, &y0);
  costmap.WorldToMapNoBounds(pose.x + reach, pose.y + reach, &x1, &y1);
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  for (int my = std::max(0, y0); my <= std::min(costmap.size_y() - 1, y1); ++my) {
    for (int mx = std::max(0, x0); mx <= std::min(costmap.size_x() - 1, x1); ++mx) {
      if (costmap.cost(mx, my) != kLethalObstacle) continue;
      double wx, wy;
      costmap.MapToWorld(mx, my, &wx, &wy);
      if ((wx - pose.x) * c + (wy - pose.y) * s <= 0.0) continue;  // behind the centre
      best = std::min(best, minibot3d_common::PointPolygonDistance(placed, wx, wy));
    }
  }
  return best;
}

void WaitRecovery::Start(const RobotState& state) {
  needed_ = state.no_path;
  start_time_ = state.time;
  start_pose_ = state.local_pose;
  next_check_ = state.time + options_.check_period;
  backing_ = needed_ && state.local_costmap != nullptr &&
             ClearanceAhead(*state.local_costmap, state.local_pose, options_.clearance) <
                 options_.clearance;
  outcome_ = needed_ ? "" : "not needed: the way to the goal is not shut";
}

bool WaitRecovery::Step(const RobotState& state, Twist2* cmd) {
  *cmd = Twist2();
  if (!needed_) return false;
  const double waited = state.time - start_time_;
  const double backed = std::hypot(state.local_pose.x - start_pose_.x,
                                   state.local_pose.y - start_pose_.y);
  std::string end;
  if (state.time >= next_check_ - 1e-9) {
    next_check_ += options_.check_period;
    if (state.path_exists && state.path_exists()) end = "the way opened after ";
  }
  if (end.empty() && waited >= options_.duration - 1e-9) end = "still no path to the goal after ";
  if (!end.empty()) {
    std::ostringstream out;
    out << end << std::fixed << std::setprecision(1) << waited << " s";
    if (backed >= 0.05) out << std::setprecision(2) << " (backed off " << backed << " m first)";
    outcome_ = out.str();
    return false;
  }
  if (backing_) {
    // Stop making room once there is enough, or the way back is blocked.
    constexpr double kStep = 0.05;  // m: the footprint is checked this far behind
    const Costmap2D* costmap = state.local_costmap;
    Pose2 behind = state.local_pose;
    behind.x -= kStep * std::cos(behind.yaw);
    behind.y -= kStep * std::sin(behind.yaw);
    const int rear = costmap != nullptr ? FootprintCost(*costmap, footprint_, behind) : -1;
    backing_ = rear >= 0 && rear != kLethalObstacle && backed < options_.max_backoff &&
               ClearanceAhead(*costmap, state.local_pose, options_.clearance) < options_.clearance;
    if (backing_) cmd->vx = -options_.backoff_vel;
  }
  return true;
}

}  // namespace nav
}  // namespace minibot3d_navigation
