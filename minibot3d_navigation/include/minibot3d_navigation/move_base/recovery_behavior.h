// Recovery behaviours (nav_core::RecoveryBehavior), run by the navigation
// executive when planning or control keeps failing or the robot oscillates.
//
// Lifecycle: Start() once when the executive enters the recovery, then Step()
// every control cycle until it returns false (finished); the command it writes
// is sent to the base.  The behaviours, one file each:
//  - ClearCostmapRecovery (clear_costmap_recovery.h): resets the obstacle
//    layers outside a square of side reset_distance centred on the robot
//    (move_base's conservative_reset and aggressive_reset);
//  - RotateRecovery (rotate_recovery.h): turns in place one full turn so the
//    sensors see all around (rotate_recovery), stopping early if the
//    footprint would hit something it can see on the local costmap;
//  - BackOutRecovery (back_out_recovery.h; back_out, not in ROS): reverses
//    along the poses the robot drove through, newest first, so a robot that
//    squeezed into a spot it cannot leave forwards (a pocket, a gap narrower
//    than its footprint turns in) leaves it the way it came: ground it has
//    already covered;
//  - WaitRecovery (wait_recovery.h; wait, not in ROS; Nav2's Wait behaviour,
//    ended early): when no path to the goal exists, stands still until one
//    exists again or wait_duration has passed, so a robot whose only way is
//    shut by someone standing in a doorway waits for them and then replans,
//    instead of clearing its costmaps and turning on the spot beside them.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_

#include <functional>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

// What a recovery (and the executive) sees each cycle.
struct RobotState {
  double time = 0.0;      // seconds, the simulator's clock
  Pose2 global_pose;     // in the global costmap's frame (map)
  Pose2 local_pose;      // in the local costmap's frame (odom)
  Twist2 velocity;       // in the robot's frame
  const Costmap2D* global_costmap = nullptr;
  const Costmap2D* local_costmap = nullptr;
  // Poses the robot drove through, in the local frame, oldest first (the
  // executive records them; nullptr when nobody does).
  const std::vector<Pose2>* trail = nullptr;
  // Set while recovering because the local planner found no command (not
  // because of oscillation or a planning failure).
  bool control_failed = false;
  // Set while recovering because the planner found no path between a start
  // and a goal that are both free (not because either is in an obstacle).
  bool no_path = false;
  // Whether the global planner finds a path from the robot to the goal on the
  // global costmap as it is now (the executive supplies it while recovering;
  // empty when nobody can tell).
  std::function<bool()> path_exists;
};

class RecoveryBehavior {
 public:
  virtual ~RecoveryBehavior() = default;
  virtual std::string name() const = 0;
  // Whether it can help with this failure at all; the executive passes over one
  // that cannot, to the next in the list, as if it had run.
  virtual bool Applies(const RobotState& /*state*/) const { return true; }
  virtual void Start(const RobotState& state) = 0;
  virtual bool Step(const RobotState& state, Twist2* cmd) = 0;
  // After Step returned false: what it did and why it ended, for the log
  // ("" when there is nothing to say).
  virtual std::string outcome() const { return ""; }
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
