// One cost term of the dynamic-window local planner, after DWB's
// dwb_core::TrajectoryCritic (robot_navigation), reduced to what every
// critic here needs.
//
// Lifecycle, once per control cycle:
//   Prepare(pose, velocity, plan, costmap)  -> false: the critic cannot score
//       anything this cycle (failure() says why); the planner raises
//       ControlError with that message.
//   Score(trajectory) for every candidate   -> cost >= 0, or negative when
//       the trajectory is illegal (collision, no path, oscillation); the
//       planner discards it and counts the rejection under name().
//   Debrief(chosen)                         -> state updates that depend on
//       what was finally commanded (oscillation memory).
// The planner's total cost of a legal trajectory is sum(scale() * Score()).
// Critics keep references to Prepare's inputs until the cycle ends.
#ifndef MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_CRITIC_H_
#define MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_CRITIC_H_

#include <string>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/dwa/trajectory.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

class TrajectoryCritic {
 public:
  virtual ~TrajectoryCritic() = default;

  virtual std::string name() const = 0;

  // `plan` is the pruned plan in the costmap frame (non-empty).
  virtual bool Prepare(const Pose2& pose, const Twist2& velocity,
                       const Path& plan, const Costmap2D& costmap) = 0;

  virtual double Score(const Trajectory& traj) = 0;

  virtual void Debrief(const Trajectory& /*chosen*/) {}

  // Forgets state kept across cycles (new goal).
  virtual void Reset() {}

  // Why Prepare returned false.  (Score only returns a negative number; the
  // planner counts those per critic.)
  const std::string& failure() const { return failure_; }

  double scale() const { return scale_; }
  void set_scale(double scale) { scale_ = scale; }

 protected:
  std::string failure_;

 private:
  double scale_ = 1.0;
};

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_TRAJECTORY_CRITIC_H_
