#include "minibot3d_navigation/dwa/moving_obstacle_critic.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

// m: what counts as nearer or farther.
constexpr double kSlack = 0.005;
// m: within personal distance, any approach at all (rounding aside).
constexpr double kAnyNearer = 1e-4;
// m/s: slower obstacles have no lane to keep out of.
constexpr double kLaneMinSpeed = 0.1;

}  // namespace

bool MovingObstacleCritic::Prepare(const Pose2& pose, const Twist2& velocity,
                                   const Path& /*plan*/, const Costmap2D& /*costmap*/) {
  start_ = pose;
  start_vx_ = velocity.vx;
  return true;
}

double MovingObstacleCritic::Distance(const Pose2& pose, size_t k, double t) const {
  const MovingObstacle& o = obstacles_[k];
  // The obstacle's centre in the robot's frame at `pose`.
  const double wx = o.position.x + o.velocity.x * t - pose.x;
  const double wy = o.position.y + o.velocity.y * t - pose.y;
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  if (o.outline.empty()) {
    const double lx = c * wx + s * wy, ly = -s * wx + c * wy;
    return minibot3d_common::SignedPointPolygonDistance(footprint_, lx, ly) - o.radius;
  }
  double best = std::numeric_limits<double>::infinity();
  for (const Point2& q : o.outline) {
    const double px = wx + q.x, py = wy + q.y;
    best = std::min(best, minibot3d_common::SignedPointPolygonDistance(
                              footprint_, c * px + s * py, -s * px + c * py));
  }
  return best;
}

bool MovingObstacleCritic::ScorePose(const Pose2& pose, double t, bool binding,
                                     double* worst) const {
  if (t > horizon_) return true;
  const double weight = 1.0 - t / horizon_;
  for (size_t k = 0; k < obstacles_.size(); ++k) {
    const double d = Distance(pose, k, t);
    // Binding: clear of where the obstacle will be and of where it is now
    // (it may stop; a velocity estimate lags at contact range).
    const double now = binding ? Distance(pose, k, 0.0) : d;
    const double held = std::min(d, now);
    // Within personal distance of someone now, no way nearer to them.
    const double start_now = binding ? Distance(start_, k, 0.0) : 0.0;
    if (binding && start_now < personal_distance_ && now < start_now - kAnyNearer) return false;
    if (held < margin_ && binding) {
      // Within the margin: legal only when backing out is allowed, away from
      // an obstacle that is not closing in (a standoff); never towards or
      // along one, nor while one comes at the robot (it stands for the
      // contact).
      if (!backing_out_) return false;
      const double standing = Distance(start_, k, t);
      const bool closing = standing < Distance(start_, k, 0.0) - kSlack;
      const double standing_now = std::min(standing, start_now);
      if (closing || held < standing_now + kSlack) return false;
    }
    if (d < personal_distance_) {
      *worst = std::max(*worst, weight * (1.0 - d / personal_distance_));
    }
  }
  return true;
}

double MovingObstacleCritic::LaneCost(const Pose2& pose, double t) const {
  if (lane_time_ <= 0.0) return 0.0;
  double worst = 0.0;
  for (const MovingObstacle& o : obstacles_) {
    const double speed = std::hypot(o.velocity.x, o.velocity.y);
    if (speed < kLaneMinSpeed) continue;
    // u along the obstacle's way, n across it.
    const double ux = o.velocity.x / speed, uy = o.velocity.y / speed;
    double front = o.radius, left = o.radius, right = -o.radius;
    if (!o.outline.empty()) {
      front = left = -std::numeric_limits<double>::infinity();
      right = std::numeric_limits<double>::infinity();
      for (const Point2& q : o.outline) {
        front = std::max(front, q.x * ux + q.y * uy);
        const double across = -q.x * uy + q.y * ux;
        left = std::max(left, across);
        right = std::min(right, across);
      }
    }
    // The footprint at `p` relative to the obstacle moved on by `dt`: its
    // nearest point along u and its extent across.
    auto extent = [&](const Pose2& p, double dt, double* nearest, double* lo, double* hi) {
      const double rx = p.x - (o.position.x + o.velocity.x * dt);
      const double ry = p.y - (o.position.y + o.velocity.y * dt);
      const double c = std::cos(p.yaw), s = std::sin(p.yaw);
      *nearest = *lo = std::numeric_limits<double>::infinity();
      *hi = -*lo;
      for (const Point2& f : footprint_) {
        const double fx = rx + c * f.x - s * f.y, fy = ry + s * f.x + c * f.y;
        *nearest = std::min(*nearest, fx * ux + fy * uy);
        const double across = -fx * uy + fy * ux;
        *lo = std::min(*lo, across);
        *hi = std::max(*hi, across);
      }
    };
    // How soon the obstacle's front reaches the robot where it stands now:
    // the urgency, the same for every trajectory (slowing down does not
    // make the way clearer).
    double nearest, lo, hi;
    extent(start_, 0.0, &nearest, &lo, &hi);
    if (nearest - front < 0.0) continue;  // beside or behind it already
    // Closing at the obstacle's speed plus the robot's own towards it.
    const double towards = -(std::cos(start_.yaw) * ux + std::sin(start_.yaw) * uy) * start_vx_;
    const double arrival = (nearest - front) / (speed + std::max(0.0, towards));
    if (arrival >= lane_time_) continue;
    // The lateral gap to the band where the trajectory ends (also where the
    // prediction has already met the obstacle there); inside it, minus the
    // way out by the nearer side.
    extent(pose, t, &nearest, &lo, &hi);
    const double gap = std::max(right - hi, lo - left);
    if (gap >= personal_distance_) continue;
    worst = std::max(worst, (1.0 - gap / personal_distance_) * (1.0 - arrival / lane_time_));
  }
  return worst;
}

double MovingObstacleCritic::Score(const Trajectory& traj) {
  if (obstacles_.empty()) return 0.0;
  // Binding: the first control period and the braking tail, the way this
  // command still has to stop; the rest of the rollout only costs.
  const bool stopping = traj.kind == TrajectoryKind::kStop;
  double worst = 0.0;
  for (size_t i = 1; i < traj.poses.size(); ++i) {
    const double t = i * traj.dt;
    if (!ScorePose(traj.poses[i], t, !stopping && t <= traj.braking_t0, &worst)) return -1.0;
  }
  for (size_t k = 0; k < traj.braking_poses.size(); ++k) {
    if (!ScorePose(traj.braking_poses[k], traj.braking_t0 + k * traj.braking_dt, !stopping,
                   &worst)) {
      return -1.0;
    }
  }
  double lane = 0.0;
  if (!traj.poses.empty()) {
    lane = LaneCost(traj.poses.back(), (traj.poses.size() - 1) * traj.dt);
  }
  return proximity_weight_ * worst + lane_weight_ * lane;
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
