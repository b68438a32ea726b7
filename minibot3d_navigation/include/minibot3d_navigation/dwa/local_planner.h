// The local-planner (controller) extension point: nav_core's
// BaseLocalPlanner with explicit inputs (nav_core2 style).
//
// Lifecycle: construct with validated options; Reset() whenever a new goal
// arrives (clears latched goal tolerance and oscillation memory); each control
// cycle call ComputeVelocity with the robot's pose and velocity in the local
// costmap's frame, the global plan transformed into that frame, and the local
// costmap; stop when IsGoalReached.  ComputeVelocity throws ControlError when
// no admissible command exists (every rollout collides), so the caller can
// start recovery behaviours and say why.
#ifndef MINIBOT3D_NAVIGATION_DWA_LOCAL_PLANNER_H_
#define MINIBOT3D_NAVIGATION_DWA_LOCAL_PLANNER_H_

#include <stdexcept>
#include <string>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

class ControlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class LocalPlanner {
 public:
  virtual ~LocalPlanner() = default;
  virtual std::string name() const = 0;
  virtual void Reset() = 0;
  virtual Twist2 ComputeVelocity(const Pose2& pose, const Twist2& velocity,
                                  const Path& plan,
                                  const Costmap2D& costmap) = 0;
  virtual bool IsGoalReached(const Pose2& pose, const Twist2& velocity,
                             const Path& plan) = 0;
  // Whether the last ComputeVelocity stood (or braked) to let a moving
  // obstacle pass: waiting, which the caller does not count as oscillating.
  virtual bool Yielding() const { return false; }
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_LOCAL_PLANNER_H_
