// When explore gives up on the goal it sent (explore_lite's progress_timeout): the robot has to
// get 0.1 m closer to the goal than it has been, or move 0.5 m from where it last did either,
// every progress_timeout seconds. Moving (a path may first lead away from the goal) keeps a goal
// only so long: without getting closer for kMovingTimeouts x progress_timeout, the goal is given
// up however much the robot moved — move_base oscillating in front of a gap, backing out as its
// recovery and driving back to try again, moves the robot a metre every cycle for ever.
#ifndef MINIBOT3D_NAVIGATION_EXPLORE_GOAL_PROGRESS_H_
#define MINIBOT3D_NAVIGATION_EXPLORE_GOAL_PROGRESS_H_

#include <string>

#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

class GoalProgress {
 public:
  static constexpr double kCloser = 0.1;       // m nearer the goal than ever before
  static constexpr double kMoved = 0.5;        // m from where progress was last seen
  static constexpr double kMovingTimeouts = 3.0;

  // Throws std::invalid_argument unless progress_timeout > 0 (seconds).
  explicit GoalProgress(double progress_timeout);

  // A goal was sent at time `now` (s) with the robot at `robot`.
  void Start(double now, const Point2& robot, const Point2& goal);
  // The robot is at `robot` at time `now`: "" while the goal is being progressed towards, else
  // why it is given up ("made no progress for 20 s", ...).
  std::string Update(double now, const Point2& robot);

 private:
  double timeout_;
  Point2 goal_{};
  double best_distance_ = 0.0;
  Point2 progress_pose_{};
  double last_progress_ = 0.0;  // closer, or moved kMoved
  double last_closer_ = 0.0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_EXPLORE_GOAL_PROGRESS_H_
