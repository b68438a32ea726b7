#include "minibot3d_navigation/move_base/rotate_recovery.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace minibot3d_navigation {
namespace nav {

RotateRecovery::RotateRecovery(std::string name, const RotateRecoveryOptions& options,
                               Footprint footprint)
    : name_(std::move(name)), options_(options), footprint_(std::move(footprint)) {}

void RotateRecovery::Start(const RobotState& state) {
  start_time_ = state.time;
  last_yaw_ = state.local_pose.yaw;
  turned_ = 0.0;
}

bool RotateRecovery::Step(const RobotState& state, Twist2* cmd) {
  *cmd = Twist2();
  // Counter-clockwise progress since the last cycle (a turn of more than pi
  // between two cycles is impossible at these rates).
  turned_ += std::max(0.0, AngleDiff(state.local_pose.yaw, last_yaw_));
  last_yaw_ = state.local_pose.yaw;
  const double remaining = 2.0 * kPi - turned_;
  if (remaining <= options_.tolerance) return false;
  if (state.time - start_time_ > options_.timeout) return false;

  // Look ahead over what is left of the turn (at most the distance we could
  // need to stop) for a footprint collision on the local costmap, as
  // rotate_recovery does; stop the turn if one is in the way.
  if (state.local_costmap != nullptr && !footprint_.empty()) {
    const double look = std::min(remaining, options_.max_rotational_vel /
                                                std::max(1e-6, options_.acc_lim_th) +
                                            0.2);
    for (double a = 0.0; a <= look; a += options_.sim_granularity) {
      Pose2 p = state.local_pose;
      p.yaw = NormalizeAngle(p.yaw + a);
      const int c = FootprintCost(*state.local_costmap, footprint_, p);
      if (c < 0 || c == kLethalObstacle) return false;
    }
  }
  // Decelerate so that the turn ends near a full revolution.
  double vel = std::sqrt(2.0 * options_.acc_lim_th * remaining);
  vel = std::clamp(vel, options_.min_rotational_vel, options_.max_rotational_vel);
  cmd->wz = vel;
  return true;
}

}  // namespace nav
}  // namespace minibot3d_navigation
