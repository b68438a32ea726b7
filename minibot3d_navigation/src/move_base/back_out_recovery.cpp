#include "minibot3d_navigation/move_base/back_out_recovery.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

namespace minibot3d_navigation {
namespace nav {

namespace {
constexpr double kLookahead = 0.1;  // m: the trail point steered at
constexpr double kMaxDistanceFactor = 3.0;  // route length cap, in `distance`s
}  // namespace

BackOutRecovery::BackOutRecovery(std::string name, const BackOutOptions& options,
                                 Footprint footprint)
    : name_(std::move(name)), options_(options), footprint_(std::move(footprint)) {}

void BackOutRecovery::Start(const RobotState& state) {
  route_.clear();
  route_length_ = 0.0;
  next_ = 0;
  start_time_ = state.time;
  start_pose_ = state.local_pose;
  outcome_.clear();
  if (state.trail == nullptr || state.trail->empty()) {
    outcome_ = "no trail recorded: nothing to back along";
    return;
  }
  // After oscillation or a planning failure the robot may still make
  // progress, unless it cannot turn where it is (a wedged robot cannot: its
  // own heading is one of those tried): then the way it came is the way out.
  if (!state.control_failed && CanTurnAt(state.local_costmap, state.local_pose)) {
    outcome_ = "not needed: the local planner still finds commands and the robot can turn here";
    return;
  }
  const std::vector<Pose2>& trail = *state.trail;
  // Back along the trail until `distance` from here in a straight line: the
  // wiggles of a robot that worked its way into the spot are replayed too.
  // Where the robot could not turn on the spot there, on to the first trail
  // pose where it can (a dead-end slot longer than `distance`), at most
  // kMaxDistanceFactor * distance.
  const Pose2& start = state.local_pose;
  for (auto it = trail.rbegin(); it != trail.rend(); ++it) {
    route_.push_back(*it);
    const double d = std::hypot(it->x - start.x, it->y - start.y);
    if (d >= kMaxDistanceFactor * options_.distance) break;
    if (d >= options_.distance && CanTurnAt(state.local_costmap, *it)) break;
  }
  for (size_t i = 1; i < route_.size(); ++i) {
    route_length_ += std::hypot(route_[i].x - route_[i - 1].x, route_[i].y - route_[i - 1].y);
  }
}

bool BackOutRecovery::BackClear(const Costmap2D& costmap, const Pose2& pose) const {
  // The back half of the footprint (reversing, the robot moves away from its
  // front), narrowed so that its sides move in by one cell.
  double half_width = 0.0;
  for (const Point2& v : footprint_) half_width = std::max(half_width, std::abs(v.y));
  const double scale = 1.0 - costmap.resolution() / std::max(1e-9, half_width);
  if (scale <= 0.0) return true;  // a robot under two cells wide
  Footprint narrowed = footprint_;
  for (Point2& v : narrowed) v = {std::min(v.x, 0.0), v.y * scale};
  return FootprintCost(costmap, narrowed, pose) != kLethalObstacle;
}

bool BackOutRecovery::CanTurnAt(const Costmap2D* costmap, const Pose2& pose) const {
  if (costmap == nullptr || footprint_.empty()) return true;
  constexpr int kHeadings = 16;
  for (int k = 0; k < kHeadings; ++k) {
    Pose2 q = pose;
    q.yaw = NormalizeAngle(pose.yaw + 2.0 * kPi * k / kHeadings);
    const int c = FootprintCost(*costmap, footprint_, q);
    if (c < 0 || c == kLethalObstacle) return false;
  }
  return true;
}

bool BackOutRecovery::OnTrail(const Pose2& q) const {
  for (const Pose2& t : route_) {
    if (std::hypot(t.x - q.x, t.y - q.y) < 0.04 && std::abs(AngleDiff(t.yaw, q.yaw)) < 0.3) {
      return true;
    }
  }
  return false;
}

bool BackOutRecovery::Step(const RobotState& state, Twist2* cmd) {
  *cmd = Twist2();
  if (route_.empty()) return false;
  const Pose2& p = state.local_pose;
  auto stop = [this, &p](const char* why) {
    std::ostringstream o;
    o << "backed " << std::fixed << std::setprecision(2)
      << std::hypot(p.x - start_pose_.x, p.y - start_pose_.y) << " m of a " << route_length_
      << " m route along the trail; " << why;
    outcome_ = o.str();
    return false;
  };
  if (state.time - start_time_ >
      options_.timeout_factor * std::max(options_.distance, route_length_) / options_.vel + 2.0) {
    return stop("timed out");
  }
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  auto dist = [&p](const Pose2& q) { return std::hypot(q.x - p.x, q.y - p.y); };
  // Steer at the first trail point at least kLookahead away (positions only:
  // the turns and wiggles of the way in need not be replayed).
  while (next_ + 1 < route_.size() && dist(route_[next_]) < kLookahead) ++next_;
  const Pose2& t = route_[next_];
  if (next_ + 1 == route_.size() && dist(t) < 0.03) return stop("reached its end");
  const double dx = c * (t.x - p.x) + s * (t.y - p.y);
  const double dy = -s * (t.x - p.x) + c * (t.y - p.y);
  // Heading error of the robot's back: the bearing of the target seen from
  // behind (dx < 0 when it is behind).
  const double e = std::atan2(-dy, -dx);
  Twist2 u;
  if (std::abs(e) > 0.6) {
    u.wz = std::copysign(std::max(options_.min_rotational_vel, std::min(
        options_.max_rotational_vel, 2.5 * std::abs(e))), e);
  } else {
    u.vx = -options_.vel;
    // Reverse pure pursuit: the arc through the target, w = v * 2 dy / d^2.
    u.wz = std::clamp(u.vx * 2.0 * dy / std::max(1e-6, dx * dx + dy * dy),
                          -options_.max_rotational_vel, options_.max_rotational_vel);
  }
  if (state.local_costmap != nullptr && !footprint_.empty()) {
    // Where the command leads in 0.2 s.  Poses the robot drove through are
    // known to be free, so on the trail a lethal cell under the front half of
    // the footprint (which it backs away from) or within a cell of its sides
    // is rounding (a wall mapped a cell thick, a desk it passed 3 cm from);
    // one deeper in the back half, the way it is going, is new and stops it.
    // Off the trail the footprint must stay clear of lethal cells.
    const double dt = 0.2;
    Pose2 ahead = p;
    ahead.yaw = NormalizeAngle(p.yaw + u.wz * dt);
    ahead.x += u.vx * dt * c;
    ahead.y += u.vx * dt * s;
    const int cost = FootprintCost(*state.local_costmap, footprint_, ahead);
    if (cost < 0) return stop("the pose 0.2 s ahead is off the local costmap");
    if (cost == kLethalObstacle && !(OnTrail(ahead) && BackClear(*state.local_costmap, ahead))) {
      return stop(!OnTrail(ahead)
                      ? "the footprint 0.2 s ahead would touch a lethal cell off the trail"
                      : "an obstacle lies in the back half of the footprint 0.2 s ahead, "
                        "more than a cell inside its sides");
    }
  }
  *cmd = u;
  return true;
}

}  // namespace nav
}  // namespace minibot3d_navigation
