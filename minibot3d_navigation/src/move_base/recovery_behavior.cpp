#include "minibot3d_navigation/move_base/recovery_behavior.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace minibot3d_navigation {
namespace nav {

ClearCostmapRecovery::ClearCostmapRecovery(std::string name, double reset_distance,
                                           std::function<void(double)> clear)
    : name_(std::move(name)), reset_distance_(reset_distance), clear_(std::move(clear)) {}

void ClearCostmapRecovery::Start(const RobotState&) {
  if (clear_) clear_(reset_distance_);
}

bool ClearCostmapRecovery::Step(const RobotState&, Twist2D* cmd) {
  *cmd = Twist2D();
  return false;
}

RotateRecovery::RotateRecovery(std::string name, const RotateRecoveryOptions& options,
                               Footprint footprint)
    : name_(std::move(name)), options_(options), footprint_(std::move(footprint)) {}

void RotateRecovery::Start(const RobotState& state) {
  start_time_ = state.time;
  last_yaw_ = state.local_pose.yaw;
  turned_ = 0.0;
}

bool RotateRecovery::Step(const RobotState& state, Twist2D* cmd) {
  *cmd = Twist2D();
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
      Pose2D p = state.local_pose;
      p.yaw = NormalizeAngle(p.yaw + a);
      const int c = FootprintCost(*state.local_costmap, footprint_, p);
      if (c < 0 || c == kLethalObstacle) return false;
    }
  }
  // Decelerate so that the turn ends near a full revolution.
  double vel = std::sqrt(2.0 * options_.acc_lim_th * remaining);
  vel = std::clamp(vel, options_.min_rotational_vel, options_.max_rotational_vel);
  cmd->vtheta = vel;
  return true;
}

namespace {
constexpr double kLookahead = 0.1;  // m: the trail point steered at
}  // namespace

BackOutRecovery::BackOutRecovery(std::string name, const BackOutOptions& options,
                                 Footprint footprint)
    : name_(std::move(name)), options_(options), footprint_(std::move(footprint)) {}

void BackOutRecovery::Start(const RobotState& state) {
  route_.clear();
  next_ = 0;
  start_time_ = state.time;
  if (!state.control_failed || state.trail == nullptr || state.trail->empty()) return;
  const std::vector<Pose2D>& trail = *state.trail;
  // Back along the trail until `distance` from here in a straight line: the
  // wiggles of a robot that worked its way into the spot are replayed too.
  const Pose2D& start = state.local_pose;
  for (auto it = trail.rbegin(); it != trail.rend(); ++it) {
    route_.push_back(*it);
    if (std::hypot(it->x - start.x, it->y - start.y) >= options_.distance) break;
  }
}

bool BackOutRecovery::OnTrail(const Pose2D& q) const {
  for (const Pose2D& t : route_) {
    if (std::hypot(t.x - q.x, t.y - q.y) < 0.04 && std::abs(AngleDiff(t.yaw, q.yaw)) < 0.3) {
      return true;
    }
  }
  return false;
}

bool BackOutRecovery::Step(const RobotState& state, Twist2D* cmd) {
  *cmd = Twist2D();
  if (route_.empty()) return false;
  if (state.time - start_time_ >
      options_.timeout_factor * options_.distance / options_.vel + 2.0) {
    return false;
  }
  const Pose2D& p = state.local_pose;
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  auto dist = [&p](const Pose2D& q) { return std::hypot(q.x - p.x, q.y - p.y); };
  // Steer at the first trail point at least kLookahead away (positions only:
  // the turns and wiggles of the way in need not be replayed).
  while (next_ + 1 < route_.size() && dist(route_[next_]) < kLookahead) ++next_;
  const Pose2D& t = route_[next_];
  if (next_ + 1 == route_.size() && dist(t) < 0.03) return false;  // the end
  const double dx = c * (t.x - p.x) + s * (t.y - p.y);
  const double dy = -s * (t.x - p.x) + c * (t.y - p.y);
  // Heading error of the robot's back: the bearing of the target seen from
  // behind (dx < 0 when it is behind).
  const double e = std::atan2(-dy, -dx);
  Twist2D u;
  if (std::abs(e) > 0.6) {
    u.vtheta = std::copysign(std::max(options_.min_rotational_vel, std::min(
        options_.max_rotational_vel, 2.5 * std::abs(e))), e);
  } else {
    u.vx = -options_.vel;
    // Reverse pure pursuit: the arc through the target, w = v * 2 dy / d^2.
    u.vtheta = std::clamp(u.vx * 2.0 * dy / std::max(1e-6, dx * dx + dy * dy),
                          -options_.max_rotational_vel, options_.max_rotational_vel);
  }
  if (state.local_costmap != nullptr && !footprint_.empty()) {
    // Where the command leads in 0.2 s: poses the robot drove through are
    // known to be free (a cell it touched is lethal only by rounding); off
    // the trail, the footprint must stay clear of lethal cells.
    const double dt = 0.2;
    Pose2D ahead = p;
    ahead.yaw = NormalizeAngle(p.yaw + u.vtheta * dt);
    ahead.x += u.vx * dt * c;
    ahead.y += u.vx * dt * s;
    // A robot whose footprint touches nothing stops at any lethal cell.
    const int cost = FootprintCost(*state.local_costmap, footprint_, ahead);
    const bool wedged = FootprintCost(*state.local_costmap, footprint_, p) == kLethalObstacle;
    if (cost < 0 || (cost == kLethalObstacle && !(wedged && OnTrail(ahead)))) return false;
  }
  *cmd = u;
  return true;
}

}  // namespace nav
}  // namespace minibot3d_navigation
