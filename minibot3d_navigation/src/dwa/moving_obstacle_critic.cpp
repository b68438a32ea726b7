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

}  // namespace

bool MovingObstacleCritic::Prepare(const Pose2& pose, const Twist2& /*velocity*/,
                                   const Path& /*plan*/, const Costmap2D& /*costmap*/) {
  start_ = pose;
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
    if (binding && d < margin_ + deviation_ * t) {
      // Within the margin: legal only when backing out is allowed, away from
      // an obstacle that is not closing in (a standoff); never towards or
      // along one, nor while one comes at the robot (it stands for the
      // contact).
      if (!backing_out_) return false;
      const double standing = Distance(start_, k, t);
      const bool closing = standing < Distance(start_, k, 0.0) - kSlack;
      if (closing || d < standing + kSlack) return false;
    }
    if (d < personal_distance_) {
      *worst = std::max(*worst, weight * (1.0 - d / personal_distance_));
    }
  }
  return true;
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
  return worst;
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
