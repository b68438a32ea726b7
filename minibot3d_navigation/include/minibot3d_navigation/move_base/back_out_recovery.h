// back_out (not in ROS move_base): reverses out along the way the robot came.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_BACK_OUT_RECOVERY_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_BACK_OUT_RECOVERY_H_

#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/move_base/recovery_behavior.h"

namespace minibot3d_navigation {
namespace nav {

struct BackOutOptions {
  double distance = 0.6;          // m from the start, along the trail
  double vel = 0.15;              // m/s backwards
  double max_rotational_vel = 1.0;  // rad/s while straightening up
  double min_rotational_vel = 0.4;  // rad/s at least when turning on the spot
  double timeout_factor = 3.0;    // gives up after timeout_factor * route length / vel + 2 s
};

// Backs the robot out along the way it came.
// When: after a control failure (state.control_failed: the way ahead is
// blocked), or after any other trigger when the robot cannot turn on the spot
// where it is (its footprint at one of 16 headings touches a lethal cell on
// the local costmap): a robot that drove into a dead-end slot oscillates
// there, since the local planner finds no move out.  Otherwise (oscillation
// or a planning failure with room to turn) it does nothing: reversing would
// undo progress the robot may still make.
// How: reverse pure pursuit along the trail (Coulter, "Implementation of the
// Pure Pursuit Path Tracking Algorithm", CMU-RI-TR-92-01, driven backwards).
// Start takes the trail poses, newest first, up to the first one `distance`
// from the robot in a straight line, so a robot that wiggled its way into a
// spot gets that far out of it — or, if it could not turn on the spot there,
// on to the first trail pose where it can, at most 3 * distance away: a
// dead-end slot is left, not just reversed in.  Each Step steers the robot's
// back at the first of them at least 0.1 m away: turning on the spot while it
// lies more than 0.6 rad off the back, else reversing at `vel` on the arc
// through it (w = v * 2 dy / d^2).  Positions only: the turns of the way in
// are not replayed.
// It stops at the last pose, on timeout, or when the footprint 0.2 s ahead
// touches a lethal cell on the local costmap and either that pose is off the
// trail, or the cell lies in the back half of the footprint (the way it is
// going) more than a cell inside its sides: poses it drove through are free,
// so a cell grazed by a side or left at the front is rounding (a wall mapped a
// cell thick, a desk passed 3 cm away), while one behind it is something new.
// outcome() says how far it backed and why it stopped.
class BackOutRecovery : public RecoveryBehavior {
 public:
  BackOutRecovery(std::string name, const BackOutOptions& options, Footprint footprint);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;
  std::string outcome() const override { return outcome_; }
  // The poses still to back through (for tests and logs).
  const std::vector<Pose2>& route() const { return route_; }

 private:
  bool OnTrail(const Pose2& pose) const;
  bool CanTurnAt(const Costmap2D* costmap, const Pose2& pose) const;
  // No lethal cell under the back half of the footprint at `pose`, its sides
  // moved in by one cell.
  bool BackClear(const Costmap2D& costmap, const Pose2& pose) const;
  std::string name_;
  BackOutOptions options_;
  Footprint footprint_;
  std::vector<Pose2> route_;  // newest first
  double route_length_ = 0.0;  // m along the route
  Pose2 start_pose_;
  std::string outcome_;
  size_t next_ = 0;
  double start_time_ = 0.0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_BACK_OUT_RECOVERY_H_
