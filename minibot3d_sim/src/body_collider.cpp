#include "minibot3d_sim/body_collider.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minibot3d_sim {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
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
std::vector<long> PartHeights(double lo, double hi, const World& world) {  // NOLINT(runtime/int)
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
  std::vector<long> mm;  // NOLINT(runtime/int)
  for (double v : z) mm.push_back(std::lround(v * 1000.0));
  std::sort(mm.begin(), mm.end());
  mm.erase(std::unique(mm.begin(), mm.end()), mm.end());
  return mm;
}

// The projections of a convex polygon on an axis: [*lo, *hi].
void Project(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& axis, double* lo,
             double* hi) {
  *lo = std::numeric_limits<double>::infinity();
  *hi = -*lo;
  for (const auto& v : poly) {
    const double d = v.dot(axis);
    *lo = std::min(*lo, d);
    *hi = std::max(*hi, d);
  }
}

// Separating axis test of two convex polygons; on overlap, *depth and *axis (unit, pointing from
// b's side towards a's) give the axis of least overlap.
bool ConvexOverlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                   double* depth, Eigen::Vector2d* axis) {
  *depth = std::numeric_limits<double>::infinity();
  for (const std::vector<Eigen::Vector2d>* poly : {&a, &b}) {
    for (std::size_t i = 0; i < poly->size(); ++i) {
      const Eigen::Vector2d e = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      if (e.squaredNorm() < 1e-18) continue;
      const Eigen::Vector2d n = Eigen::Vector2d(e.y(), -e.x()).normalized();
      double alo, ahi, blo, bhi;
      Project(a, n, &alo, &ahi);
      Project(b, n, &blo, &bhi);
      const double overlap = std::min(ahi, bhi) - std::max(alo, blo);
      if (overlap <= 0.0) return false;
      if (overlap < *depth) {
        *depth = overlap;
        // a leaves b towards the side where a's middle lies.
        *axis = (alo + ahi) >= (blo + bhi) ? n : Eigen::Vector2d(-n);
      }
    }
  }
  return true;
}

}  // namespace

const WorldSlice* SliceCache::At(double height) {
  auto& slice = slices_[std::llround(height * 1e6)];
  if (!slice) slice = std::make_unique<WorldSlice>(*world_, height);
  return slice.get();
}

BodyCollider::BodyCollider(const RobotModel& robot, const World& world, SliceCache* cache) {
  for (const BodyPart& body : BodyParts(robot)) {
    Part part;
    part.outline = body.outline;
    part.z_min = body.z_min;
    part.z_max = body.z_max;
    // RobotModel promises counter-clockwise outlines; a hand-made clockwise one is turned around
    // so that every polygon handed to a slice has the documented orientation.
    double area2 = 0.0;
    for (std::size_t i = 0; i < part.outline.size(); ++i) {
      area2 += Cross(part.outline[i], part.outline[(i + 1) % part.outline.size()]);
    }
    if (area2 < 0.0) std::reverse(part.outline.begin(), part.outline.end());
    const std::size_t n = part.outline.size();
    if (n >= 3 && area2 != 0.0) {
      // Outward unit normal of edge i (from vertex i to i + 1) of a counter-clockwise outline.
      std::vector<Eigen::Vector2d> normals(n);
      bool degenerate = false;
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d e = part.outline[(i + 1) % n] - part.outline[i];
        degenerate |= e.squaredNorm() < 1e-18;
        normals[i] = Eigen::Vector2d(e.y(), -e.x()).normalized();
      }
      for (std::size_t i = 0; i < n && !degenerate; ++i) {
        const Eigen::Vector2d& a = normals[(i + n - 1) % n];
        const Eigen::Vector2d& b = normals[i];
        // The corner point at unit distance from both edges' lines: (a + b) / (1 + a·b).
        const double c = 1.0 + a.dot(b);
        if (c < 1e-6) {
          degenerate = true;  // a needle-thin corner: no useful bound
          break;
        }
        part.miter.push_back((a + b) / c);
      }
      if (degenerate) part.miter.clear();
    }
    for (const auto& v : part.outline) radius_ = std::max(radius_, v.norm());
    if (!part.outline.empty()) {
      Eigen::Vector2d lo = part.outline.front(), hi = lo;
      for (const auto& v : part.outline) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      part.center = 0.5 * (lo + hi);
      for (const auto& v : part.outline) {
        part.radius = std::max(part.radius, (v - part.center).norm());
      }
    }
    for (long mm : PartHeights(body.z_min, body.z_max, world)) {  // NOLINT(runtime/int)
      const WorldSlice* slice = cache->At(mm / 1000.0);
      // Heights in increasing order: the first of a geometry is its lowest.
      const auto same = [slice](const WorldSlice* s) { return s->SameGeometry(*slice); };
      if (std::none_of(part.slices.begin(), part.slices.end(), same)) {
        part.slices.push_back(slice);
        part.heights.push_back(slice->height());
      }
      if (std::none_of(all_slices_.begin(), all_slices_.end(), same)) all_slices_.push_back(slice);
    }
    scratch_.reserve(std::max(scratch_.capacity(), part.outline.size()));
    parts_.push_back(std::move(part));
  }
}

bool BodyCollider::Collides(const Pose2& pose, Hit* hit) const {
  const minibot3d_common::PoseTransform place(pose);
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const Part& part = parts_[k];
    scratch_.resize(part.outline.size());
    for (std::size_t i = 0; i < part.outline.size(); ++i) {
      scratch_[i] = place(part.outline[i]);
    }
    for (std::size_t s = 0; s < part.slices.size(); ++s) {
      const WorldSlice* slice = part.slices[s];
      int shape = -1;
      if (slice->PolygonCollides(scratch_, &shape)) {
        if (hit != nullptr) {
          hit->shape = shape;
          hit->part = static_cast<int>(k);
          hit->height = part.heights[s];
          hit->slice = slice;
        }
        return true;
      }
    }
  }
  return false;
}

bool BodyCollider::Clear(const Pose2& pose, double margin) const {
  const minibot3d_common::PoseTransform place(pose);
  for (const Part& part : parts_) {
    if (part.miter.size() != part.outline.size()) return false;
    scratch_.resize(part.outline.size());
    for (std::size_t i = 0; i < part.outline.size(); ++i) {
      scratch_[i] = place(Eigen::Vector2d(part.outline[i] + margin * part.miter[i]));
    }
    for (const WorldSlice* slice : part.slices) {
      if (slice->PolygonCollides(scratch_)) return false;
    }
  }
  return true;
}

double BodyCollider::Distance(const Eigen::Vector2d& p) const {
  double d = std::numeric_limits<double>::infinity();
  for (const WorldSlice* slice : all_slices_) d = std::min(d, slice->Distance(p));
  return d;
}

bool BodyOverlap(const BodyCollider& a, const Pose2& pose_a, const BodyCollider& b,
                 const Pose2& pose_b, Eigen::Vector2d* normal) {
  const double dx = pose_a.x - pose_b.x, dy = pose_a.y - pose_b.y;
  const double reach = a.radius() + b.radius();
  if (dx * dx + dy * dy > reach * reach) return false;
  const minibot3d_common::PoseTransform place_a(pose_a), place_b(pose_b);
  // b's outlines in the world frame, placed on first use; reused: no allocation per pair.
  thread_local std::vector<Eigen::Vector2d> pa;
  thread_local std::vector<std::vector<Eigen::Vector2d>> pb;
  thread_local std::vector<char> placed;
  thread_local std::vector<Eigen::Vector2d> centres_b;
  const auto& parts_b = b.parts();
  if (pb.size() < parts_b.size()) pb.resize(parts_b.size());
  placed.assign(parts_b.size(), 0);
  centres_b.clear();
  for (const BodyCollider::Part& y : parts_b) centres_b.push_back(place_b(y.center));
  double best = std::numeric_limits<double>::infinity();
  bool overlap = false;
  for (const BodyCollider::Part& x : a.parts()) {
    const Eigen::Vector2d xc = place_a(x.center);
    pa.clear();
    for (std::size_t k = 0; k < parts_b.size(); ++k) {
      const BodyCollider::Part& y = parts_b[k];
      if (x.z_max <= y.z_min || y.z_max <= x.z_min) continue;
      const double r = x.radius + y.radius;
      if ((xc - centres_b[k]).squaredNorm() > r * r) continue;
      if (pa.empty()) {
        for (const auto& v : x.outline) pa.push_back(place_a(v));
      }
      if (!placed[k]) {
        pb[k].clear();
        for (const auto& v : y.outline) pb[k].push_back(place_b(v));
        placed[k] = 1;
      }
      double depth = 0.0;
      Eigen::Vector2d axis = Eigen::Vector2d::UnitX();
      if (!ConvexOverlap(pa, pb[k], &depth, &axis)) continue;
      overlap = true;
      if (normal == nullptr) return true;
      if (depth < best) {
        best = depth;
        *normal = axis;
      }
    }
  }
  return overlap;
}

bool BodyTouchesDisc(const BodyCollider& body, const Pose2& pose, const Eigen::Vector2d& center,
                     double radius, double z_min, double z_max, Eigen::Vector2d* normal) {
  const double dx = pose.x - center.x(), dy = pose.y - center.y();
  const double reach = body.radius() + radius;
  if (dx * dx + dy * dy > reach * reach) return false;
  const minibot3d_common::PoseTransform place(pose);
  thread_local std::vector<Eigen::Vector2d> outline;
  for (const BodyCollider::Part& part : body.parts()) {
    if (part.z_max <= z_min || z_max <= part.z_min || part.outline.empty()) continue;
    outline.clear();
    for (const auto& v : part.outline) outline.push_back(place(v));
    const bool inside =
        outline.size() >= 3 && minibot3d_common::PointInPolygon(outline, center.x(), center.y());
    double nearest = std::numeric_limits<double>::infinity();
    Eigen::Vector2d closest = outline[0];
    for (size_t i = 0; i < outline.size(); ++i) {
      const Eigen::Vector2d& a = outline[i];
      const Eigen::Vector2d& b = outline[(i + 1) % outline.size()];
      const Eigen::Vector2d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((center - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const Eigen::Vector2d q = a + t * ab;
      const double d = (center - q).norm();
      if (d < nearest) {
        nearest = d;
        closest = q;
      }
    }
    if (!inside && nearest >= radius) continue;
    if (normal != nullptr) {
      Eigen::Vector2d n = inside ? Eigen::Vector2d(pose.x, pose.y) - center : closest - center;
      if (n.norm() < 1e-12) n = Eigen::Vector2d(pose.x, pose.y) - center;
      *normal = n.norm() < 1e-12 ? Eigen::Vector2d::UnitX() : Eigen::Vector2d(n.normalized());
    }
    return true;
  }
  return false;
}

}  // namespace minibot3d_sim
