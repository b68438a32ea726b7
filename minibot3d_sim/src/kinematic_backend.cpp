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
  const Pose2 to{pose.x, pose.y, NormalizeAngle(pose.yaw)};
  twist_ = Twist2{};
  std::fill(wheel_velocities_.begin(), wheel_velocities_.end(), 0.0);
  blocked_contact_valid_ = false;
  blocked_end_valid_ = false;
  if (step_start_.valid && minibot3d_common::SamePose(to, step_start_.pose)) {
    // Back to where the last step began (another robot was in the way): what was known of the
    // world around that pose still holds.
    pose_ = to;
    start_colliding_ = step_start_.colliding;
    cache_ = step_start_.cache;
    clearance_ = step_start_.clearance;
    travelled_ = step_start_.travelled;
    return;
  }
  pose_ = to;
  cache_ = Cache::kNone;
  step_start_.valid = false;
  int shape = -1;
  start_colliding_ = Collides(pose_, &shape);
}

void KinematicBackend::Fill(Cache kind, double clearance) {
  cache_ = kind;
  clearance_ = clearance;
  travelled_ = 0.0;
}

void KinematicBackend::SetTargets(const DriveTargets& targets) { targets_ = targets; }

bool KinematicBackend::Collides(const Pose2& p, int* shape) {
  ++collision_checks_;
  if (!collider_.Collides(p, &hit_)) return false;
  if (shape != nullptr) *shape = hit_.shape;
  return true;
}

void KinematicBackend::Step(double dt, std::vector<Contact>* contacts) {
  step_start_ = StepStart{true, pose_, start_colliding_, cache_, clearance_, travelled_};
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
  // No point of the body moves further than this in the step.
  const double swept = moved + collider_.radius() * std::abs(NormalizeAngle(end.yaw - pose_.yaw));
  const double used = cache_ == Cache::kCentre ? moved : swept;

  bool free = false;
  int shape = -1;
  if (cache_ != Cache::kNone && travelled_ + used < clearance_) {
    travelled_ += used;
    free = true;
  } else if (blocked_end_valid_ && minibot3d_common::SamePose(end, blocked_end_)) {
    // The very step refused last time (the robot has not moved and asks the same): refused again.
    shape = blocked_contact_.shape;
  } else {
    // Near something (the body cache ran out before its margin reached its top) the centre's
    // clearance is not worth computing: it would be used up by the parts' radius.
    const bool near = cache_ == Cache::kNone || (cache_ == Cache::kBody && margin_ < kMaxMargin);
    const double clearance =
        near ? 0.0 : collider_.Distance(Eigen::Vector2d(end.x, end.y)) - collider_.radius();
    if (clearance > 0.0) {
      // Every part's vertex is within collider_.radius() of the root, which may move clearance
      // before a vertex can reach anything.
      Fill(Cache::kCentre, clearance);
      free = true;
    } else if (collider_.Clear(end, margin_)) {
      // Near something, yet nothing within margin_ of the body: every body point may move margin_.
      Fill(Cache::kBody, margin_);
      margin_ = std::min(2.0 * margin_, kMaxMargin);
      free = true;
    } else {
      // Within margin_ of something: only the exact polygon test can tell; try a smaller margin
      // next time.
      cache_ = Cache::kNone;
      margin_ = std::max(0.5 * margin_, kMinMargin);
      free = !Collides(end, &shape);
    }
  }
  blocked_end_valid_ = false;

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
    blocked_end_ = end;
    blocked_end_valid_ = true;
  }
  for (size_t i = 0; i < wheel_positions_.size(); ++i) {
    wheel_positions_[i] += wheel_velocities_[i] * dt;
  }
}

Contact KinematicBackend::MakeContact(int shape) const {
  const BodyCollider::Part& part = collider_.parts()[hit_.part];
  const WorldSlice& slice = *hit_.slice;
  std::vector<Eigen::Vector2d> poly(part.outline.size());
  const minibot3d_common::PoseTransform place(pose_);
  for (std::size_t i = 0; i < part.outline.size(); ++i) poly[i] = place(part.outline[i]);

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
