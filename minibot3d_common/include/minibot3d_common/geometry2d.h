// Planar geometry shared by every minibot3d core (simulator, SLAM, localization, navigation):
// poses and twists on the floor plane, pose composition, and the point-to-segment and
// point-in-polygon tests that footprints, costmaps and world slices are built on.
//
// Conventions: x forward, y left, yaw counter-clockwise from +x in radians, angles kept in
// [-pi, pi). A pose p "in frame F" places p's frame in F; Compose(a, b) is b (given in a's frame)
// expressed in a's parent, and Between(a, b) is b expressed in a's frame, so
// Compose(a, Between(a, b)) == b (up to rounding).
#ifndef MINIBOT3D_COMMON_GEOMETRY2D_H_
#define MINIBOT3D_COMMON_GEOMETRY2D_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace minibot3d_common {

constexpr double kPi = 3.14159265358979323846;

// A planar pose: position in metres, heading in radians (counter-clockwise from +x).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// Whether two poses are exactly the same numbers (no tolerance: a step repeated, a pose unchanged).
inline bool SamePose(const Pose2& a, const Pose2& b) {
  return a.x == b.x && a.y == b.y && a.yaw == b.yaw;
}

// A planar twist in the body frame: forward, leftward (m/s) and yaw rate (rad/s).
struct Twist2 {
  double vx = 0.0;
  double vy = 0.0;
  double wz = 0.0;
};

// A point on the plane (footprint vertices, cell centres in metres).
struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

// Wraps an angle to [-pi, pi).
inline double NormalizeAngle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

// The smallest signed difference a - b, in [-pi, pi).
inline double AngleDiff(double a, double b) { return NormalizeAngle(a - b); }

inline bool IsFinite(const Pose2& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw);
}

// a ⊕ b: the pose b, given in a's frame, expressed in a's parent frame.
inline Pose2 Compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return Pose2{a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, NormalizeAngle(a.yaw + b.yaw)};
}

// ⊖a ⊕ b: the pose b expressed in a's frame.
inline Pose2 Between(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return Pose2{c * dx + s * dy, -s * dx + c * dy, AngleDiff(b.yaw, a.yaw)};
}

// Coordinates of the point types the cores use (Point2 and Eigen's 2-vector), so that each
// test below has one implementation for both.
inline double X(const Point2& p) { return p.x; }
inline double Y(const Point2& p) { return p.y; }
inline double X(const Eigen::Vector2d& p) { return p.x(); }
inline double Y(const Eigen::Vector2d& p) { return p.y(); }

// Points given in the frame of pose p, expressed in p's parent frame: the pose's sine and cosine
// taken once for many points.
class PoseTransform {
 public:
  explicit PoseTransform(const Pose2& p)
      : x_(p.x), y_(p.y), c_(std::cos(p.yaw)), s_(std::sin(p.yaw)) {}
  template <typename P>
  P operator()(const P& q) const {
    return P{x_ + c_ * X(q) - s_ * Y(q), y_ + s_ * X(q) + c_ * Y(q)};
  }

 private:
  double x_, y_, c_, s_;
};

// A point given in the frame of pose p, expressed in p's parent frame.
template <typename P>
P TransformPoint(const Pose2& p, const P& q) {
  return PoseTransform(p)(q);
}

// Distance from point p to the closed segment [a, b] (to a when the segment is a point).
template <typename P>
double PointSegmentDistance(const P& p, const P& a, const P& b) {
  const double dx = X(b) - X(a), dy = Y(b) - Y(a);
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((X(p) - X(a)) * dx + (Y(p) - Y(a)) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(X(a) + t * dx - X(p), Y(a) + t * dy - Y(p));
}

// Whether (x, y) lies inside the polygon (even-odd rule; the vertices in either order, the
// polygon closed from the last vertex back to the first). Points on the boundary may fall on
// either side.
template <typename P>
bool PointInPolygon(const std::vector<P>& polygon, double x, double y) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const P& a = polygon[i];
    const P& b = polygon[j];
    if ((Y(a) > y) != (Y(b) > y) && x < (X(b) - X(a)) * (y - Y(a)) / (Y(b) - Y(a)) + X(a)) {
      inside = !inside;
    }
  }
  return inside;
}

// Distance from (x, y) to the polygon's outline (closed from the last vertex back to the first),
// negative inside the polygon; infinity for an empty polygon.
template <typename P>
double SignedPointPolygonDistance(const std::vector<P>& polygon, double x, double y) {
  const std::size_t n = polygon.size();
  if (n == 0) return std::numeric_limits<double>::infinity();
  const Point2 q{x, y};
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point2 a{X(polygon[i]), Y(polygon[i])}, b{X(polygon[j]), Y(polygon[j])};
    best = std::min(best, PointSegmentDistance(q, a, b));
  }
  return n >= 3 && PointInPolygon(polygon, x, y) ? -best : best;
}

// Distance from (x, y) to the polygon: 0 inside it, else to its nearest edge.
template <typename P>
double PointPolygonDistance(const std::vector<P>& polygon, double x, double y) {
  return std::max(0.0, SignedPointPolygonDistance(polygon, x, y));
}

}  // namespace minibot3d_common

#endif  // MINIBOT3D_COMMON_GEOMETRY2D_H_
