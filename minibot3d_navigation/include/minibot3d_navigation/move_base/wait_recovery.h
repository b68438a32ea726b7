// wait (not in ROS move_base; Nav2's Wait, ended early): waits at a distance
// for the way to the goal to open.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_WAIT_RECOVERY_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_WAIT_RECOVERY_H_

#include <string>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/move_base/recovery_behavior.h"

namespace minibot3d_navigation {
namespace nav {

struct WaitOptions {
  double duration = 30.0;      // s; the longest wait (wait_duration)
  double check_period = 0.5;   // s between two checks for a path
  double clearance = 0.45;     // m kept in front of the footprint while waiting
  double backoff_vel = 0.15;   // m/s backwards while making room
  double max_backoff = 1.0;    // m; the farthest it backs off
};

// Waits for the way to open.
// When: after a planning failure with no path between a free start and a
// free goal (state.no_path): something shuts the only way (a person in a
// doorway, a trolley left in a corridor). After a control failure or
// oscillation a path exists, and a goal or start in an obstacle is not a way
// that opens by waiting: then it does not apply (Applies) and does nothing.
// How: first it makes room. A robot that drove up to whoever blocks the way
// (the old plan is followed for planner_patience after replanning fails)
// backs straight off while anything lethal on the local costmap lies within
// `clearance` of the front half of its footprint (0.45 m: the edge of the
// intimate zone of proxemics, Hall 1966), for at most max_backoff, stopping
// where the footprint a step behind would touch a lethal cell or leave the
// costmap. Then it commands zero while the costmaps keep updating from the
// sensors. Every check_period it asks state.path_exists and ends as soon as a
// path exists (the executive then plans and drives on), or when `duration`
// has passed (the next recovery in the list runs). outcome() says which,
// after how long, and how far it backed off.
class WaitRecovery : public RecoveryBehavior {
 public:
  WaitRecovery(std::string name, const WaitOptions& options, Footprint footprint);
  std::string name() const override { return name_; }
  bool Applies(const RobotState& state) const override { return state.no_path; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;
  std::string outcome() const override { return outcome_; }
  // Distance (m) from the footprint at `pose` to the nearest lethal cell of
  // `costmap` in front of the robot's centre (infinity when none is within
  // `range`).
  double ClearanceAhead(const Costmap2D& costmap, const Pose2& pose, double range) const;

 private:
  std::string name_;
  WaitOptions options_;
  Footprint footprint_;
  double circumscribed_ = 0.0;
  bool needed_ = false;
  bool backing_ = false;
  Pose2 start_pose_;
  double start_time_ = 0.0;
  double next_check_ = 0.0;
  std::string outcome_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_WAIT_RECOVERY_H_
