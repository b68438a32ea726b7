#include "kinematic_backend.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minibot3d_sim {
namespace {

Eigen::Vector2d ClosestOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                 const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Closest point of the (closed) polygon boundary to p.
Eigen::Vector2d ClosestOnPolygon(const std::vector<Eigen::Vector2d>& poly,
                                 const Eigen::Vector2d& p) {
  Eigen::Vector2d best = poly.front();
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d q = ClosestOnSegment(p, poly[i], poly[(i + 1) % poly.size()]);
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = q;
    }
  }
  return best;
}

}  // namespace

KinematicBackend::KinematicBackend(const RobotModel& robot, const World& world, SliceCache* slices)
    : own_slices_(slices == nullptr ? std::make_unique<SliceCache>(&world) : nullptr),
      collider_(robot, world, slices == nullptr ? own_slices_.get() : slices) {
  wheel_velocities_.assign(robot.wheels.size(), 0.0);
  wheel_positions_.assign(robot.wheels.size(), 0.0);
  targets_.wheel_speeds.assign(robot.wheels.size(), 0.0);
}

void KinematicBackend::SetPose(const Pose2& pose) {
  pose_ = pose;
  pose_.yaw = NormalizeAngle(pose.yaw);
  twist_ = Twist2{};
  std::fill(wheel_velocities_.begin(), wheel_velocities_.end(), 0.0);
  cache_valid_ = false;
  blocked_contact_valid_ = false;
  int shape = -1;
  start_colliding_ = Collides(pose_, &shape);
}

void KinematicBackend::SetTargets(const DriveTargets& targets) { targets_ = targets; }

bool KinematicBackend::Collides(const Pose2& p, int* shape) {
  ++collision_checks_;
  if (!collider_.Collides(p, &hit_)) return false;
  if (shape != nullptr) *shape = hit_.shape;
  return true;
}

void KinematicBackend::Step(double dt, std::vector<Contact>* contacts) {
  const Twist2 nominal = targets_.body_twist;
  // A holonomic base's wheels (if any) are not driven.
  const std::vector<double>& wheels = targets_.wheel_speeds;
  if (nominal.vx == 0.0 && nominal.vy == 0.0 && nominal.wz == 0.0) {
    // Nothing to move (the wheels may still counter-rotate pairwise; they cannot without slip).
    twist_ = Twist2{};
    wheel_velocities_ = wheels;
    for (size_t i = 0; i < wheel_positions_.size(); ++i) {
      wheel_positions_[i] += wheel_velocities_[i] * dt;
    }
    return;
  }
  const Pose2 end = IntegrateTwist(pose_, nominal, dt);
  const double moved = std::hypot(end.x - pose_.x, end.y - pose_.y);

  bool free = false;
  int shape = -1;
  if (cache_valid_ && travelled_ + moved < clearance_) {
    // Every part's vertex is within collider_.radius() of the root, which has moved at most
    // travelled_ + moved since nothing was closer than clearance_ + that radius.
    travelled_ += moved;
    free = true;
  } else {
    const double clearance = collider_.Distance(Eigen::Vector2d(end.x, end.y)) - collider_.radius();
    if (clearance > 0.0) {
      cache_valid_ = true;
      clearance_ = clearance;
      travelled_ = 0.0;
      free = true;
    } else {
      // Within reach of something: only the exact polygon test can tell; check every step.
      cache_valid_ = false;
      free = !Collides(end, &shape);
    }
  }

  if (free || start_colliding_) {
    // A robot placed inside an obstacle may drive (out): refusing every step would lock it there.
    if (free) start_colliding_ = false;
    pose_ = end;
    twist_ = nominal;
    wheel_velocities_ = wheels;
    blocked_contact_valid_ = false;
    if (!free && contacts != nullptr) contacts->push_back(MakeContact(shape));
  } else {
    twist_ = Twist2{};
    std::fill(wheel_velocities_.begin(), wheel_velocities_.end(), 0.0);
    if (!blocked_contact_valid_ || blocked_contact_.shape != shape) {
      // Blocked steps repeat while the robot pushes against a wall without moving: the contact is
      // the same every time, so it is worked out once.
      blocked_contact_ = MakeContact(shape);
      blocked_contact_valid_ = true;
    }
    if (contacts != nullptr) contacts->push_back(blocked_contact_);
  }
  for (size_t i = 0; i < wheel_positions_.size(); ++i) {
    wheel_positions_[i] += wheel_velocities_[i] * dt;
  }
}

Contact KinematicBackend::MakeContact(int shape) const {
  const BodyCollider::Part& part = collider_.parts()[hit_.part];
  const WorldSlice& slice = *hit_.slice;
  std::vector<Eigen::Vector2d> poly(part.outline.size());
  for (std::size_t i = 0; i < part.outline.size(); ++i) {
    poly[i] = TransformPoint(pose_, part.outline[i]);
  }

  // Closest pair (world point, robot point) over the slice geometry of `shape`; a plain scan, as
  // this runs once per blocking event.
  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector2d world_pt = Eigen::Vector2d::Zero(), robot_pt = Eigen::Vector2d::Zero();
  int best_shape = shape;
  for (int pass = 0; pass < 2 && !std::isfinite(best_d2); ++pass) {
    const bool any_shape = pass == 1 || shape < 0;
    for (const Segment2& s : slice.segments()) {
      if (!any_shape && s.shape != shape) continue;
      auto consider = [&](const Eigen::Vector2d& w, const Eigen::Vector2d& r) {
        const double d2 = (w - r).squaredNorm();
        if (d2 < best_d2) {
          best_d2 = d2;
          world_pt = w;
          robot_pt = r;
          best_shape = s.shape;
        }
      };
      consider(s.a, ClosestOnPolygon(poly, s.a));
      consider(s.b, ClosestOnPolygon(poly, s.b));
      for (const auto& v : poly) consider(ClosestOnSegment(v, s.a, s.b), v);
    }
    for (const Circle2& c : slice.circles()) {
      if (!any_shape && c.shape != shape) continue;
      const Eigen::Vector2d r = ClosestOnPolygon(poly, c.center);
      const Eigen::Vector2d dir = r - c.center;
      const double n = dir.norm();
      const Eigen::Vector2d w = n > 0.0 ? Eigen::Vector2d(c.center + dir * (c.radius / n)) : r;
      const double d2 = (w - r).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        world_pt = w;
        robot_pt = r;
        best_shape = c.shape;
      }
    }
  }

  Contact contact;
  contact.shape = best_shape;
  contact.point = Eigen::Vector3d(world_pt.x(), world_pt.y(), hit_.height);
  Eigen::Vector2d n = robot_pt - world_pt;
  if (n.norm() < 1e-9) n = Eigen::Vector2d(pose_.x, pose_.y) - world_pt;  // touching: aim inward
  if (n.norm() > 0.0) n.normalize();
  contact.normal = Eigen::Vector3d(n.x(), n.y(), 0.0);
  contact.depth = 0.0;  // the refused step never overlaps
  return contact;
}

}  // namespace minibot3d_sim
