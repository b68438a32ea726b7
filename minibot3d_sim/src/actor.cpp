#include "minibot3d_sim/actor.h"

#include <cmath>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_sim {
namespace {

Eigen::Vector2d Position(const ActorWaypoint& w) { return Eigen::Vector2d(w.x, w.y); }

// Tangent of the trajectory's spline at waypoint i (per unit of the segment parameter).
Eigen::Vector2d Tangent(const ActorTrajectory& tr, size_t i) {
  const auto& w = tr.waypoints;
  const size_t n = w.size();
  const double k = 0.5 * (1.0 - tr.tension);
  const bool closed = Position(w[0]) == Position(w[n - 1]);
  if (i == 0 || i == n - 1) {
    if (closed) return k * (Position(w[1]) - Position(w[n - 2]));
    return i == 0 ? k * (Position(w[1]) - Position(w[0]))
                  : k * (Position(w[n - 1]) - Position(w[n - 2]));
  }
  return k * (Position(w[i + 1]) - Position(w[i - 1]));
}

// The state `t` s into one trajectory (0 <= t <= duration).
ActorState TrajectoryAt(const ActorTrajectory& tr, double t) {
  const auto& w = tr.waypoints;
  ActorState s;
  if (w.size() == 1 || t <= w.front().time) {
    s.x = w.front().x, s.y = w.front().y, s.yaw = w.front().yaw;
    return s;
  }
  if (t >= w.back().time) {
    s.x = w.back().x, s.y = w.back().y, s.yaw = w.back().yaw;
    return s;
  }
  size_t i = 0;
  while (i + 2 < w.size() && w[i + 1].time <= t) ++i;
  const double span = w[i + 1].time - w[i].time;
  const double u = (t - w[i].time) / span;
  const Eigen::Vector2d p0 = Position(w[i]), p1 = Position(w[i + 1]);
  const Eigen::Vector2d m0 = Tangent(tr, i), m1 = Tangent(tr, i + 1);
  // Hermite basis and its derivative.
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h01 = -2 * u3 + 3 * u2, h10 = u3 - 2 * u2 + u,
               h11 = u3 - u2;
  const double d00 = 6 * u2 - 6 * u, d01 = -6 * u2 + 6 * u, d10 = 3 * u2 - 4 * u + 1,
               d11 = 3 * u2 - 2 * u;
  const Eigen::Vector2d p = h00 * p0 + h01 * p1 + h10 * m0 + h11 * m1;
  const Eigen::Vector2d v = (d00 * p0 + d01 * p1 + d10 * m0 + d11 * m1) / span;
  const double turn = minibot3d_common::NormalizeAngle(w[i + 1].yaw - w[i].yaw);
  s.x = p.x(), s.y = p.y();
  s.vx = v.x(), s.vy = v.y();
  s.yaw = minibot3d_common::NormalizeAngle(w[i].yaw + u * turn);
  s.wz = turn / span;
  return s;
}

}  // namespace

double ScriptLength(const Actor& actor) {
  double length = 0.0;
  for (const ActorTrajectory& tr : actor.trajectories) length += tr.duration();
  return length;
}

ActorState ActorAt(const Actor& actor, double t) {
  ActorState s;
  if (actor.trajectories.empty()) {
    s.x = actor.x, s.y = actor.y, s.yaw = actor.yaw;
    return s;
  }
  const double length = ScriptLength(actor);
  double script_time = t - actor.delay_start;
  if (!actor.auto_start || script_time <= 0.0) {
    ActorState first = TrajectoryAt(actor.trajectories.front(), 0.0);
    first.vx = first.vy = first.wz = 0.0;
    return first;
  }
  if (script_time >= length) {
    if (!actor.loop || length <= 0.0) {
      ActorState last = TrajectoryAt(actor.trajectories.back(),
                                     actor.trajectories.back().duration());
      last.vx = last.vy = last.wz = 0.0;
      return last;
    }
    script_time = std::fmod(script_time, length);
  }
  for (const ActorTrajectory& tr : actor.trajectories) {
    if (script_time < tr.duration()) return TrajectoryAt(tr, script_time);
    script_time -= tr.duration();
  }
  return TrajectoryAt(actor.trajectories.back(), actor.trajectories.back().duration());
}

}  // namespace minibot3d_sim
