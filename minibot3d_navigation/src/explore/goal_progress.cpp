#include "minibot3d_navigation/explore/goal_progress.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace minibot3d_navigation {
namespace nav {

GoalProgress::GoalProgress(double progress_timeout) : timeout_(progress_timeout) {
  if (!(progress_timeout > 0.0) || !std::isfinite(progress_timeout)) {
    std::ostringstream m;
    m << "explore: progress_timeout must be > 0 s, got " << progress_timeout;
    throw std::invalid_argument(m.str());
  }
}

void GoalProgress::Start(double now, const Point2& robot, const Point2& goal) {
  goal_ = goal;
  best_distance_ = std::hypot(goal.x - robot.x, goal.y - robot.y);
  progress_pose_ = robot;
  last_progress_ = now;
  last_closer_ = now;
}

std::string GoalProgress::Update(double now, const Point2& robot) {
  const double d = std::hypot(goal_.x - robot.x, goal_.y - robot.y);
  const bool closer = d < best_distance_ - kCloser;
  if (closer) {
    best_distance_ = d;
    last_closer_ = now;
  }
  if (closer || std::hypot(robot.x - progress_pose_.x, robot.y - progress_pose_.y) > kMoved) {
    progress_pose_ = robot;
    last_progress_ = now;
  }
  std::ostringstream why;
  if (now - last_progress_ > timeout_) {
    why << "made no progress for " << timeout_ << " s";
  } else if (now - last_closer_ > kMovingTimeouts * timeout_) {
    why << "got no closer for " << kMovingTimeouts * timeout_ << " s, though moving";
  }
  return why.str();
}

}  // namespace nav
}  // namespace minibot3d_navigation
