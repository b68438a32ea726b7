#include "kinematic_backend.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace minibot3d_sim {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

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

// Height range of a world shape (planes: none).
bool ShapeHeights(const Shape& s, double* lo, double* hi) {
  const Eigen::Matrix3d& r = s.pose.linear();
  const double cz = s.pose.translation().z();
  double half = 0.0;
  switch (s.type) {
    case ShapeType::kBox:
      half = 0.5 * (std::abs(r(2, 0)) * s.size.x() + std::abs(r(2, 1)) * s.size.y() +
                    std::abs(r(2, 2)) * s.size.z());
      break;
    case ShapeType::kCylinder: {
      const double axis = std::abs(r(2, 2));
      half = 0.5 * s.size.z() * axis + s.size.x() * std::sqrt(std::max(0.0, 1.0 - axis * axis));
      break;
    }
    case ShapeType::kSphere:
      half = s.size.x();
      break;
    case ShapeType::kMesh: {
      if (!s.mesh || s.mesh->vertices.empty()) return false;
      *lo = std::numeric_limits<double>::infinity();
      *hi = -*lo;
      for (const auto& v : s.mesh->vertices) {
        const double z = (s.pose * v.cast<double>()).z();
        *lo = std::min(*lo, z);
        *hi = std::max(*hi, z);
      }
      return true;
    }
    case ShapeType::kPlane:
      return false;
  }
  *lo = cz - half;
  *hi = cz + half;
  return true;
}

// Heights (mm, sorted, unique) at which a part spanning [lo, hi] meets every world shape it can:
// just inside its ends, every 5 cm between, and just inside each world shape's own ends and a
// sphere's middle where they fall within the band.
std::vector<long> PartHeights(double lo, double hi, const World& world) {
  constexpr double kInside = 0.001, kSpacing = 0.05;
  std::vector<double> z;
  if (hi - lo <= 2 * kInside) {
    z.push_back(0.5 * (lo + hi));
  } else {
    z.push_back(lo + kInside);
    z.push_back(hi - kInside);
    const int n = static_cast<int>(std::floor((hi - lo) / kSpacing));
    for (int k = 1; k <= n; ++k) z.push_back(lo + k * (hi - lo) / (n + 1));
    for (const Shape& s : world.shapes) {
      double slo, shi;
      if (!ShapeHeights(s, &slo, &shi)) continue;
      for (double c : {slo + kInside, shi - kInside}) {
        if (c > lo && c < hi) z.push_back(c);
      }
      const double mid = 0.5 * (slo + shi);
      if (s.type == ShapeType::kSphere && mid > lo && mid < hi) z.push_back(mid);
    }
  }
  std::vector<long> mm;
  for (double v : z) mm.push_back(std::lround(v * 1000.0));
  std::sort(mm.begin(), mm.end());
  mm.erase(std::unique(mm.begin(), mm.end()), mm.end());
  return mm;
}

}  // namespace

KinematicBackend::KinematicBackend(const RobotModel& robot, const World& world) {
  wheel_velocities_.assign(robot.wheels.size(), 0.0);
  wheel_positions_.assign(robot.wheels.size(), 0.0);
  targets_.wheel_speeds.assign(robot.wheels.size(), 0.0);
  std::map<long, int> slice_of_height;  // mm -> index into slices_
  for (const BodyPart& body : BodyParts(robot)) {
    Part part;
    part.outline = body.outline;
    // RobotModel promises counter-clockwise outlines; a hand-made clockwise one is turned around
    // so that every polygon handed to a slice has the documented orientation.
    double area2 = 0.0;
    for (std::size_t i = 0; i < part.outline.size(); ++i) {
      area2 += Cross(part.outline[i], part.outline[(i + 1) % part.outline.size()]);
    }
    if (area2 < 0.0) std::reverse(part.outline.begin(), part.outline.end());
    for (const auto& v : part.outline) footprint_radius_ = std::max(footprint_radius_, v.norm());
    for (long mm : PartHeights(body.z_min, body.z_max, world)) {
      auto it = slice_of_height.find(mm);
      if (it == slice_of_height.end()) {
        it = slice_of_height.emplace(mm, static_cast<int>(slices_.size())).first;
        slice_heights_.push_back(mm / 1000.0);
        slices_.emplace_back(world, mm / 1000.0);
      }
      part.slices.push_back(it->second);
    }
    polygon_scratch_.resize(std::max(polygon_scratch_.size(), part.outline.size()));
    parts_.push_back(std::move(part));
  }
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
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const Part& part = parts_[k];
    std::vector<Eigen::Vector2d>& poly = polygon_scratch_;
    poly.resize(part.outline.size());
    for (std::size_t i = 0; i < part.outline.size(); ++i) {
      poly[i] = TransformPoint(p, part.outline[i]);
    }
    for (int s : part.slices) {
      if (slices_[s].PolygonCollides(poly, shape)) {
        hit_part_ = static_cast<int>(k);
        hit_slice_ = s;
        return true;
      }
    }
  }
  return false;
}

double KinematicBackend::Clearance(const Eigen::Vector2d& p) const {
  double d = std::numeric_limits<double>::infinity();
  for (const WorldSlice& slice : slices_) d = std::min(d, slice.Distance(p));
  return d;
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
    // Every footprint vertex is within footprint_radius_ of the root, which has moved at most
    // travelled_ + moved since nothing was closer than clearance_ + footprint_radius_.
    travelled_ += moved;
    free = true;
  } else {
    const double clearance = Clearance(Eigen::Vector2d(end.x, end.y)) - footprint_radius_;
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
  const Part& part = parts_[hit_part_];
  const WorldSlice& slice = slices_[hit_slice_];
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
  contact.point = Eigen::Vector3d(world_pt.x(), world_pt.y(), slice_heights_[hit_slice_]);
  Eigen::Vector2d n = robot_pt - world_pt;
  if (n.norm() < 1e-9) n = Eigen::Vector2d(pose_.x, pose_.y) - world_pt;  // touching: aim inward
  if (n.norm() > 0.0) n.normalize();
  contact.normal = Eigen::Vector3d(n.x(), n.y(), 0.0);
  contact.depth = 0.0;  // the refused step never overlaps
  return contact;
}

}  // namespace minibot3d_sim
