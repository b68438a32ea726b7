// WorldSlice: cutting the world with z = height, and 2-D queries on the cut.
//
// Cutting: a box (any rotation) or a tilted cylinder (as a 64-gon prism) is cut edge by edge and the
// cut points' convex hull is its polygon; an upright cylinder and a sphere give circles; a mesh gives
// one segment per triangle that crosses the plane; a non-horizontal plane gives the segment where
// its sized rectangle crosses; horizontal planes (floors) are ignored.
// Queries: a uniform grid stores, per cell, every segment/circle touching it (conservatively, with a
// small epsilon). Rays walk the grid cell by cell (Amanatides & Woo) and stop as soon as the best hit
// is no farther than the current cell's exit; a thread-local stamp per item makes each item tested
// at most once per ray even when it spans many cells.
#include "minibot3d_sim/world_slice.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <utility>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_sim {
namespace {

using minibot3d_common::PointSegmentDistance;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Tilted cylinders are approximated by a prism with this many sides.
constexpr int kCylinderSides = 64;
// cos of the largest tilt for which a cylinder still counts as upright (≈ 0.0026°): the cut's
// ellipse then differs from the circle by less than 1e-9·r.
constexpr double kUprightCos = 1.0 - 1e-9;
// Grid cells are capped so a huge world cannot exhaust memory; the cell grows instead.
constexpr double kMaxCells = 4.0e6;
// Items are put in every cell they come within this distance of (m), so rounding never drops one.
constexpr double kGridSlack = 1e-7;

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Convex hull (Andrew's monotone chain), counter-clockwise, without repeated or collinear points.
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  // Merge points closer than this: cut points of edges meeting at one corner coincide up to
  // rounding.
  constexpr double kMerge = 1e-12;
  std::vector<Eigen::Vector2d> unique;
  for (const Eigen::Vector2d& p : pts) {
    bool dup = false;
    for (const Eigen::Vector2d& q : unique) {
      if ((p - q).squaredNorm() < kMerge * kMerge) {
        dup = true;
        break;
      }
    }
    if (!dup) unique.push_back(p);
  }
  if (unique.size() < 3) return unique;
  std::vector<Eigen::Vector2d> hull(2 * unique.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < unique.size(); ++i) {
    while (k >= 2 && Cross(hull[k - 1] - hull[k - 2], unique[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = unique[i];
  }
  for (std::size_t i = unique.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Cross(hull[k - 1] - hull[k - 2], unique[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = unique[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Where the 3-D edges (p[i], q[i]) cross z = h. Endpoints on the plane count, so a face lying in
// the plane contributes its corners.
void CutEdges(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& edges, double h,
              std::vector<Eigen::Vector2d>* out) {
  for (const auto& e : edges) {
    const double da = e.first.z() - h, db = e.second.z() - h;
    if (da == 0.0) out->push_back(e.first.head<2>());
    if (db == 0.0) out->push_back(e.second.head<2>());
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      const double t = da / (da - db);
      out->push_back((e.first + t * (e.second - e.first)).head<2>());
    }
  }
}

// Adds the cut polygon (or segment, when degenerate) of the convex solid with these edges.
void AddConvexCut(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& edges, double h,
                  int shape, std::vector<Segment2>* segments) {
  std::vector<Eigen::Vector2d> pts;
  CutEdges(edges, h, &pts);
  const std::vector<Eigen::Vector2d> hull = ConvexHull(std::move(pts));
  if (hull.size() == 2) {
    segments->push_back(Segment2{hull[0], hull[1], shape});
  } else if (hull.size() >= 3) {
    for (std::size_t i = 0; i < hull.size(); ++i) {
      segments->push_back(Segment2{hull[i], hull[(i + 1) % hull.size()], shape});
    }
  }
}

void SliceBox(const Shape& s, double h, int index, std::vector<Segment2>* segments) {
  const Eigen::Vector3d half = 0.5 * s.size;
  std::array<Eigen::Vector3d, 8> c;
  double zmin = kInf, zmax = -kInf;
  for (int i = 0; i < 8; ++i) {
    c[i] = s.pose * Eigen::Vector3d((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                    (i & 4) ? half.z() : -half.z());
    zmin = std::min(zmin, c[i].z());
    zmax = std::max(zmax, c[i].z());
  }
  if (h < zmin || h > zmax) return;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;
  for (int i = 0; i < 8; ++i) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (!(i & bit)) edges.emplace_back(c[i], c[i | bit]);  // the 12 edges, each once
    }
  }
  AddConvexCut(edges, h, index, segments);
}

void SliceCylinder(const Shape& s, double h, int index, std::vector<Segment2>* segments,
                   std::vector<Circle2>* circles) {
  const double r = s.size.x(), half_len = 0.5 * s.size.z();
  const Eigen::Vector3d axis = s.pose.linear().col(2);
  const Eigen::Vector3d c = s.pose.translation();
  if (std::abs(axis.z()) >= kUprightCos) {
    if (std::abs(h - c.z()) <= half_len) circles->push_back(Circle2{c.head<2>(), r, index});
    return;
  }
  // Quick reject on the z extent of the tilted cylinder.
  const double z_extent = half_len * std::abs(axis.z()) + r * std::sqrt(1.0 - axis.z() * axis.z());
  if (std::abs(h - c.z()) > z_extent) return;
  std::vector<Eigen::Vector3d> bottom(kCylinderSides), top(kCylinderSides);
  for (int i = 0; i < kCylinderSides; ++i) {
    const double a = 2.0 * M_PI * i / kCylinderSides;
    const Eigen::Vector3d rim(r * std::cos(a), r * std::sin(a), 0.0);
    bottom[i] = s.pose * (rim - Eigen::Vector3d(0, 0, half_len));
    top[i] = s.pose * (rim + Eigen::Vector3d(0, 0, half_len));
  }
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;
  for (int i = 0; i < kCylinderSides; ++i) {
    const int j = (i + 1) % kCylinderSides;
    edges.emplace_back(bottom[i], bottom[j]);
    edges.emplace_back(top[i], top[j]);
    edges.emplace_back(bottom[i], top[i]);
  }
  AddConvexCut(edges, h, index, segments);
}

void SlicePlane(const Shape& s, double h, int index, std::vector<Segment2>* segments) {
  const Eigen::Vector3d n_local = s.normal.normalized();
  const Eigen::Vector3d n = s.pose.linear() * n_local;
  if (std::abs(n.z()) >= kUprightCos) return;  // a floor or ceiling, not an obstacle in the slice
  // The plane's sides run along the shape frame's x and y turned so that z becomes the normal.
  const Eigen::Matrix3d rot =
      s.pose.linear() *
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n_local).toRotationMatrix();
  const Eigen::Vector3d o = s.pose.translation();
  const Eigen::Vector3d tx = rot.col(0) * (0.5 * s.size.x());
  const Eigen::Vector3d ty = rot.col(1) * (0.5 * s.size.y());
  const std::array<Eigen::Vector3d, 4> corner = {o - tx - ty, o + tx - ty, o + tx + ty,
                                                 o - tx + ty};
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;
  for (int i = 0; i < 4; ++i) edges.emplace_back(corner[i], corner[(i + 1) % 4]);
  AddConvexCut(edges, h, index, segments);
}

void SliceSphere(const Shape& s, double h, int index, std::vector<Circle2>* circles) {
  const double r = s.size.x();
  const double d = h - s.pose.translation().z();
  if (std::abs(d) < r) {
    circles->push_back(Circle2{s.pose.translation().head<2>(), std::sqrt(r * r - d * d), index});
  }
}

void SliceMesh(const Shape& s, double h, int index, std::vector<Segment2>* segments) {
  if (!s.mesh) return;
  const TriangleMesh& mesh = *s.mesh;
  std::vector<Eigen::Vector3d> v(mesh.vertices.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = s.pose * mesh.vertices[i].cast<double>();
  for (const auto& tri : mesh.triangles) {
    // A vertex exactly on the plane counts as above it (symbolic perturbation): every crossing
    // triangle then has exactly two crossing edges, and neighbouring triangles agree on the shared
    // point, so the cut stays a closed chain.
    std::array<Eigen::Vector3d, 3> p;
    std::array<bool, 3> above;
    for (int k = 0; k < 3; ++k) {
      p[k] = v[tri[k]];
      above[k] = p[k].z() >= h;
    }
    if (above[0] == above[1] && above[1] == above[2]) continue;
    Eigen::Vector2d cut[2];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& a = p[k];
      const Eigen::Vector3d& b = p[(k + 1) % 3];
      if (above[k] == above[(k + 1) % 3]) continue;
      const double t = (h - a.z()) / (b.z() - a.z());
      cut[n++] = (a + t * (b - a)).head<2>();
    }
    if (n == 2 && (cut[0] - cut[1]).squaredNorm() > 0.0) {
      segments->push_back(Segment2{cut[0], cut[1], index});
    }
  }
}

std::uint64_t NextSerial() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

// Per-thread "tested on ray #n" stamps; a few slots so alternating between slices does not reset.
struct StampSlot {
  std::uint64_t owner = 0;
  std::uint32_t ray = 0;
  std::vector<std::uint32_t> stamps;
};
thread_local std::array<StampSlot, 4> tl_stamp_slots;

// Whether closed segments [a, b] and [c, d] share a point.
bool SegmentsIntersect(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return true;
  }
  auto on_segment = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                       const Eigen::Vector2d& r) {  // r collinear with pq: within its box?
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
  };
  return (d1 == 0 && on_segment(a, b, c)) || (d2 == 0 && on_segment(a, b, d)) ||
         (d3 == 0 && on_segment(c, d, a)) || (d4 == 0 && on_segment(c, d, b));
}

// Point in a convex polygon (boundary included); `orientation` is +1 counter-clockwise, -1 clockwise.
bool InConvexPolygon(const std::vector<Eigen::Vector2d>& poly, double orientation,
                     const Eigen::Vector2d& p) {
  if (poly.size() < 3) return false;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % poly.size()];
    if (orientation * Cross(b - a, p - a) < 0.0) return false;
  }
  return true;
}

}  // namespace

WorldSlice::WorldSlice(const World& world, double height, double cell_size)
    : height_(height), cell_size_(cell_size > 0.0 ? cell_size : 0.25), serial_(NextSerial()) {
  for (std::size_t i = 0; i < world.shapes.size(); ++i) {
    const Shape& s = world.shapes[i];
    const int index = static_cast<int>(i);
    switch (s.type) {
      case ShapeType::kBox:
        SliceBox(s, height, index, &segments_);
        break;
      case ShapeType::kCylinder:
        SliceCylinder(s, height, index, &segments_, &circles_);
        break;
      case ShapeType::kSphere:
        SliceSphere(s, height, index, &circles_);
        break;
      case ShapeType::kPlane:
        SlicePlane(s, height, index, &segments_);
        break;
      case ShapeType::kMesh:
        SliceMesh(s, height, index, &segments_);
        break;
    }
  }
  BuildGrid();
}

void WorldSlice::BuildGrid() {
  prims_.clear();
  for (const Segment2& s : segments_) {
    prims_.push_back(Prim{s.a.x(), s.a.y(), s.b.x() - s.a.x(), s.b.y() - s.a.y()});
  }
  for (const Circle2& c : circles_) {
    prims_.push_back(Prim{c.center.x(), c.center.y(), c.radius * c.radius, c.radius});
  }
  grid_w_ = grid_h_ = 0;
  cell_start_.assign(1, 0);
  cell_items_.clear();
  if (prims_.empty()) return;

  Eigen::Vector2d lo(kInf, kInf), hi(-kInf, -kInf);
  for (const Segment2& s : segments_) {
    lo = lo.cwiseMin(s.a).cwiseMin(s.b);
    hi = hi.cwiseMax(s.a).cwiseMax(s.b);
  }
  for (const Circle2& c : circles_) {
    lo = lo.cwiseMin(c.center - Eigen::Vector2d::Constant(c.radius));
    hi = hi.cwiseMax(c.center + Eigen::Vector2d::Constant(c.radius));
  }
  const Eigen::Vector2d pad = Eigen::Vector2d::Constant(1e-6);
  lo -= pad;
  hi += pad;
  const Eigen::Vector2d extent = hi - lo;
  if (extent.x() * extent.y() / (cell_size_ * cell_size_) > kMaxCells) {
    cell_size_ = std::sqrt(extent.x() * extent.y() / kMaxCells);
  }
  grid_origin_ = lo;
  grid_w_ = std::max(1, static_cast<int>(std::ceil(extent.x() / cell_size_)));
  grid_h_ = std::max(1, static_cast<int>(std::ceil(extent.y() / cell_size_)));

  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(grid_w_) * grid_h_);
  const double inv = 1.0 / cell_size_;
  const double slack = kGridSlack * inv;  // in cell units
  auto clamp_i = [this](double u) {
    return static_cast<int>(std::clamp(std::floor(u), 0.0, static_cast<double>(grid_w_ - 1)));
  };
  auto clamp_j = [this](double v) {
    return static_cast<int>(std::clamp(std::floor(v), 0.0, static_cast<double>(grid_h_ - 1)));
  };
  // Segments: row by row, the columns spanned by the part of the segment inside the row.
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    const Eigen::Vector2d a = (segments_[k].a - grid_origin_) * inv;
    const Eigen::Vector2d b = (segments_[k].b - grid_origin_) * inv;
    const int j0 = clamp_j(std::min(a.y(), b.y()) - slack);
    const int j1 = clamp_j(std::max(a.y(), b.y()) + slack);
    for (int j = j0; j <= j1; ++j) {
      double s0 = 0.0, s1 = 1.0;
      const double dv = b.y() - a.y();
      if (std::abs(dv) > 1e-15) {
        double sa = (j - slack - a.y()) / dv, sb = (j + 1 + slack - a.y()) / dv;
        if (sa > sb) std::swap(sa, sb);
        s0 = std::max(0.0, sa);
        s1 = std::min(1.0, sb);
        if (s0 > s1) continue;
      }
      const double u0 = a.x() + s0 * (b.x() - a.x()), u1 = a.x() + s1 * (b.x() - a.x());
      const int i0 = clamp_i(std::min(u0, u1) - slack), i1 = clamp_i(std::max(u0, u1) + slack);
      for (int i = i0; i <= i1; ++i) {
        cells[static_cast<std::size_t>(j) * grid_w_ + i].push_back(static_cast<std::uint32_t>(k));
      }
    }
  }
  // Circles: every cell whose square comes within r of the centre.
  for (std::size_t k = 0; k < circles_.size(); ++k) {
    const Circle2& c = circles_[k];
    const double reach = c.radius + kGridSlack;
    int i0, j0, i1, j1;
    if (!CellRange(c.center - Eigen::Vector2d::Constant(reach),
                   c.center + Eigen::Vector2d::Constant(reach), &i0, &j0, &i1, &j1)) {
      continue;
    }
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Eigen::Vector2d cell_lo = grid_origin_ + cell_size_ * Eigen::Vector2d(i, j);
        const Eigen::Vector2d nearest =
            c.center.cwiseMax(cell_lo).cwiseMin(cell_lo + Eigen::Vector2d::Constant(cell_size_));
        if ((nearest - c.center).norm() <= reach) {
          cells[static_cast<std::size_t>(j) * grid_w_ + i].push_back(
              static_cast<std::uint32_t>(segments_.size() + k));
        }
      }
    }
  }
  cell_start_.resize(cells.size() + 1);
  cell_start_[0] = 0;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    cell_start_[c + 1] = cell_start_[c] + static_cast<std::uint32_t>(cells[c].size());
    cell_items_.insert(cell_items_.end(), cells[c].begin(), cells[c].end());
  }
}

bool WorldSlice::CellRange(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int* i0, int* j0,
                           int* i1, int* j1) const {
  if (grid_w_ == 0) return false;
  const Eigen::Vector2d a = (lo - grid_origin_) / cell_size_;
  const Eigen::Vector2d b = (hi - grid_origin_) / cell_size_;
  if (b.x() < 0.0 || b.y() < 0.0 || a.x() >= grid_w_ || a.y() >= grid_h_) return false;
  *i0 = std::max(0, static_cast<int>(std::floor(a.x())));
  *j0 = std::max(0, static_cast<int>(std::floor(a.y())));
  *i1 = std::min(grid_w_ - 1, static_cast<int>(std::floor(b.x())));
  *j1 = std::min(grid_h_ - 1, static_cast<int>(std::floor(b.y())));
  return true;
}

RayHit WorldSlice::CastRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                           double max_range) const {
  RayHit hit;
  if (grid_w_ == 0 || !(max_range >= 0.0)) return hit;
  const double ox = origin.x(), oy = origin.y(), dx = dir.x(), dy = dir.y();

  // Clip the ray to the grid's box (slab test) so rays from outside start where they enter.
  const double gx0 = grid_origin_.x(), gy0 = grid_origin_.y();
  const double gx1 = gx0 + grid_w_ * cell_size_, gy1 = gy0 + grid_h_ * cell_size_;
  double t_enter = 0.0, t_leave = max_range;
  auto slab = [&](double o, double d, double lo, double hi) {
    if (d == 0.0) return o >= lo && o <= hi;
    double ta = (lo - o) / d, tb = (hi - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t_enter = std::max(t_enter, ta);
    t_leave = std::min(t_leave, tb);
    return t_enter <= t_leave;
  };
  if (!slab(ox, dx, gx0, gx1) || !slab(oy, dy, gy0, gy1)) return hit;

  StampSlot& slot = tl_stamp_slots[serial_ % tl_stamp_slots.size()];
  if (slot.owner != serial_ || slot.stamps.size() != prims_.size()) {
    slot.owner = serial_;
    slot.stamps.assign(prims_.size(), 0);
    slot.ray = 0;
  }
  if (++slot.ray == 0) {  // wrapped: old stamps could collide with new ray numbers
    std::fill(slot.stamps.begin(), slot.stamps.end(), 0);
    slot.ray = 1;
  }
  const std::uint32_t ray = slot.ray;
  std::uint32_t* const stamps = slot.stamps.data();
  const std::uint32_t n_segments = static_cast<std::uint32_t>(segments_.size());
  const Prim* const prims = prims_.data();

  const double inv = 1.0 / cell_size_;
  int i = static_cast<int>(std::floor((ox + t_enter * dx - gx0) * inv));
  int j = static_cast<int>(std::floor((oy + t_enter * dy - gy0) * inv));
  i = std::clamp(i, 0, grid_w_ - 1);
  j = std::clamp(j, 0, grid_h_ - 1);
  const int step_i = dx > 0.0 ? 1 : -1, step_j = dy > 0.0 ? 1 : -1;
  double t_next_x = kInf, t_next_y = kInf, dt_x = kInf, dt_y = kInf;
  if (dx != 0.0) {
    t_next_x = (gx0 + (i + (dx > 0.0 ? 1 : 0)) * cell_size_ - ox) / dx;
    dt_x = cell_size_ / std::abs(dx);
  }
  if (dy != 0.0) {
    t_next_y = (gy0 + (j + (dy > 0.0 ? 1 : 0)) * cell_size_ - oy) / dy;
    dt_y = cell_size_ / std::abs(dy);
  }

  double best = kInf;
  int best_item = -1;
  for (;;) {
    const std::size_t cell = static_cast<std::size_t>(j) * grid_w_ + i;
    for (std::uint32_t k = cell_start_[cell], end = cell_start_[cell + 1]; k < end; ++k) {
      const std::uint32_t item = cell_items_[k];
      if (stamps[item] == ray) continue;
      stamps[item] = ray;
      const Prim& p = prims[item];
      const double wx = p.x - ox, wy = p.y - oy;
      double t;
      if (item < n_segments) {
        // origin + t·dir = a + s·e  ⇒  t = (w×e)/(d×e), s = (w×d)/(d×e), with w = a − origin.
        const double denom = dx * p.v - dy * p.u;
        const double w_cross_d = wx * dy - wy * dx;
        if (std::abs(denom) > 1e-14 * (std::abs(p.u) + std::abs(p.v))) {
          t = (wx * p.v - wy * p.u) / denom;
          const double s = w_cross_d / denom;
          if (s < -1e-12 || s > 1.0 + 1e-12) continue;
        } else {
          // Parallel: only a collinear segment is hit, at its nearer end (or at once if the origin
          // lies on it).
          if (std::abs(w_cross_d) > 1e-12) continue;
          const double ta = wx * dx + wy * dy;
          const double tb = ta + p.u * dx + p.v * dy;
          if (ta <= 0.0 && tb <= 0.0) continue;
          t = (ta <= 0.0 || tb <= 0.0) ? 0.0 : std::min(ta, tb);
        }
      } else {
        // |origin + t·dir − c|² = r²; from inside the circle the ray meets it on the way out.
        const double b = wx * dx + wy * dy;  // projection of (c − origin) on dir
        const double c2 = wx * wx + wy * wy - p.u;
        const double disc = b * b - c2;
        if (disc < 0.0) continue;
        const double root = std::sqrt(disc);
        t = b - root;
        if (t < 0.0) t = b + root;
      }
      if (t >= 0.0 && t < best) {
        best = t;
        best_item = static_cast<int>(item);
      }
    }
    const double t_exit = std::min(t_next_x, t_next_y);
    if (best <= t_exit || t_exit >= t_leave) break;
    if (t_next_x < t_next_y) {
      i += step_i;
      if (i < 0 || i >= grid_w_) break;
      t_next_x += dt_x;
    } else {
      j += step_j;
      if (j < 0 || j >= grid_h_) break;
      t_next_y += dt_y;
    }
  }
  if (best_item >= 0 && best <= max_range) {
    hit.range = best;
    hit.shape = static_cast<std::uint32_t>(best_item) < n_segments
                    ? segments_[best_item].shape
                    : circles_[best_item - n_segments].shape;
  }
  return hit;
}

void WorldSlice::CastFan(const Eigen::Vector2d& origin, double angle0, double increment, int n,
                         const double* dir_x, const double* dir_y, double max_range,
                         double* ranges) const {
  for (int k = 0; k < n; ++k) ranges[k] = kInf;
  if (n <= 0 || !(max_range >= 0.0)) return;
  const double ox = origin.x(), oy = origin.y();
  const double two_pi = 2.0 * M_PI;
  // Beams whose angle lies in [lo, lo + width] (radians, any lo), widened a hair so rounding never
  // drops a beam; the exact intersection test below rejects any extra one.
  auto for_beams = [&](double lo, double width, auto&& test) {
    if (n == 1 || increment <= 0.0) {
      const double d = std::remainder(angle0 - lo - width / 2, two_pi);
      if (std::abs(d) <= width / 2 + 1e-9) test(0);
      return;
    }
    double start = std::fmod(lo - angle0 - 1e-9, two_pi);
    if (start < 0.0) start += two_pi;
    const double end = start + width + 2e-9;
    // The interval, and its copy one turn earlier (for intervals that wrap past 2π).
    for (double shift : {0.0, -two_pi}) {
      const double a = start + shift, b = end + shift;
      if (b < 0.0) continue;
      int k0 = static_cast<int>(std::ceil(a / increment));
      int k1 = static_cast<int>(std::floor(b / increment));
      k0 = std::max(k0, 0);
      k1 = std::min(k1, n - 1);
      for (int k = k0; k <= k1; ++k) test(k);
    }
  };
  const std::size_t n_segments = segments_.size();
  for (std::size_t item = 0; item < prims_.size(); ++item) {
    const Prim& p = prims_[item];
    const double wx = p.x - ox, wy = p.y - oy;
    if (item < n_segments) {
      // Cull by the distance from the origin to the segment.
      const double len2 = p.u * p.u + p.v * p.v;
      double s = len2 > 0.0 ? -(wx * p.u + wy * p.v) / len2 : 0.0;
      s = std::clamp(s, 0.0, 1.0);
      const double cx = wx + s * p.u, cy = wy + s * p.v;
      if (cx * cx + cy * cy > max_range * max_range) continue;
      const double bx = wx + p.u, by = wy + p.v;  // the far end, relative to the origin
      const double cross = wx * by - wy * bx;
      if (std::abs(cross) <= 1e-12 * (len2 + 1e-30)) continue;  // seen edge-on: blocks no beam
      const double ang_a = std::atan2(wy, wx);
      const double span = std::atan2(cross, wx * bx + wy * by);  // signed angle a → b
      const double lo = span >= 0.0 ? ang_a : ang_a + span;
      for_beams(lo, std::abs(span), [&](int k) {
        const double dx = dir_x[k], dy = dir_y[k];
        const double denom = dx * p.v - dy * p.u;
        if (denom == 0.0) return;
        const double t = (wx * p.v - wy * p.u) / denom;
        const double sp = (wx * dy - wy * dx) / denom;
        if (sp < -1e-12 || sp > 1.0 + 1e-12 || t < 0.0) return;
        if (t < ranges[k]) ranges[k] = t;
      });
    } else {
      const double d2 = wx * wx + wy * wy, r = p.v;  // circles: u = r², v = r
      const double d = std::sqrt(d2);
      if (d - r > max_range) continue;
      // From inside the circle every beam meets it on the way out.
      const double half = d > r ? std::asin(r / d) : M_PI;
      const double centre = d > 0.0 ? std::atan2(wy, wx) : 0.0;
      for_beams(centre - half, 2.0 * half, [&](int k) {
        const double b = wx * dir_x[k] + wy * dir_y[k];
        const double disc = b * b - (d2 - p.u);
        if (disc < 0.0) return;
        const double root = std::sqrt(disc);
        double t = b - root;
        if (t < 0.0) t = b + root;
        if (t >= 0.0 && t < ranges[k]) ranges[k] = t;
      });
    }
  }
  for (int k = 0; k < n; ++k) {
    if (ranges[k] > max_range) ranges[k] = kInf;
  }
}

bool WorldSlice::ItemTouchesPolygon(std::uint32_t item,
                                    const std::vector<Eigen::Vector2d>& polygon,
                                    double orientation) const {
  const std::size_t n = polygon.size();
  if (item < segments_.size()) {
    const Eigen::Vector2d& a = segments_[item].a;
    const Eigen::Vector2d& b = segments_[item].b;
    if (InConvexPolygon(polygon, orientation, a) || InConvexPolygon(polygon, orientation, b)) {
      return true;
    }
    if (n == 1) return PointSegmentDistance(polygon[0], a, b) == 0.0;
    const std::size_t edges = n == 2 ? 1 : n;
    for (std::size_t e = 0; e < edges; ++e) {
      if (SegmentsIntersect(a, b, polygon[e], polygon[(e + 1) % n])) return true;
    }
    return false;
  }
  const Circle2& c = circles_[item - segments_.size()];
  if (InConvexPolygon(polygon, orientation, c.center)) return true;
  const std::size_t edges = n <= 2 ? 1 : n;
  for (std::size_t e = 0; e < edges; ++e) {
    const Eigen::Vector2d& a = polygon[e];
    const Eigen::Vector2d& b = polygon[(e + 1) % n];
    if (PointSegmentDistance(c.center, a, b) <= c.radius) return true;
  }
  return false;
}

bool WorldSlice::PolygonCollides(const std::vector<Eigen::Vector2d>& polygon, int* shape) const {
  if (polygon.empty() || grid_w_ == 0) return false;
  Eigen::Vector2d lo = polygon[0], hi = polygon[0];
  double area2 = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    lo = lo.cwiseMin(polygon[i]);
    hi = hi.cwiseMax(polygon[i]);
    area2 += Cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  }
  const double orientation = area2 >= 0.0 ? 1.0 : -1.0;
  int i0, j0, i1, j1;
  if (!CellRange(lo, hi, &i0, &j0, &i1, &j1)) return false;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const std::size_t cell = static_cast<std::size_t>(j) * grid_w_ + i;
      for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
        const std::uint32_t item = cell_items_[k];
        if (ItemTouchesPolygon(item, polygon, orientation)) {
          if (shape != nullptr) {
            *shape = item < segments_.size() ? segments_[item].shape
                                             : circles_[item - segments_.size()].shape;
          }
          return true;
        }
      }
    }
  }
  return false;
}

double WorldSlice::ItemDistance(std::uint32_t item, const Eigen::Vector2d& p) const {
  const Prim& q = prims_[item];
  if (item < segments_.size()) {
    return PointSegmentDistance(p, segments_[item].a, segments_[item].b);
  }
  // Circles are solid discs: zero inside.
  return std::max(0.0, (p - Eigen::Vector2d(q.x, q.y)).norm() - q.v);
}

double WorldSlice::Distance(const Eigen::Vector2d& p, Eigen::Vector2d* away) const {
  if (away) *away = Eigen::Vector2d::Zero();
  if (prims_.empty()) return kInf;
  double best = kInf;
  std::uint32_t nearest = 0;
  const auto consider = [&](std::uint32_t item) {
    const double d = ItemDistance(item, p);
    if (d < best) {
      best = d;
      nearest = item;
    }
  };
  const Eigen::Vector2d g = (p - grid_origin_) / cell_size_;
  if (!(g.x() >= 0.0 && g.y() >= 0.0 && g.x() < grid_w_ && g.y() < grid_h_)) {
    // Outside the grid the rings would mostly be empty: a plain scan is simpler and as fast.
    for (std::uint32_t k = 0; k < prims_.size(); ++k) consider(k);
  } else {
    const int ci = static_cast<int>(g.x()), cj = static_cast<int>(g.y());
    for (int ring = 0;; ++ring) {
      for (int j = cj - ring; j <= cj + ring; ++j) {
        if (j < 0 || j >= grid_h_) continue;
        const bool edge_row = j == cj - ring || j == cj + ring;
        for (int i = ci - ring; i <= ci + ring; i += (edge_row ? 1 : 2 * ring)) {
          if (i >= 0 && i < grid_w_) {
            const std::size_t cell = static_cast<std::size_t>(j) * grid_w_ + i;
            for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
              consider(cell_items_[k]);
            }
          }
          if (ring == 0) break;
        }
      }
      // Cells of ring + 1 and beyond are at least ring·cell_size away from p.
      if (best <= ring * cell_size_) break;
      if (ci - ring <= 0 && cj - ring <= 0 && ci + ring >= grid_w_ - 1 &&
          cj + ring >= grid_h_ - 1) {
        break;
      }
    }
  }
  if (away && std::isfinite(best)) {
    Eigen::Vector2d from;
    if (nearest < segments_.size()) {
      const Eigen::Vector2d& a = segments_[nearest].a;
      const Eigen::Vector2d ab = segments_[nearest].b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      from = p - (a + t * ab);
    } else {
      const Prim& q = prims_[nearest];
      from = p - Eigen::Vector2d(q.x, q.y);
    }
    const double n = from.norm();
    if (n > 1e-12) *away = from / n;
  }
  return best;
}

bool WorldSlice::SameGeometry(const WorldSlice& other) const {
  if (this == &other) return true;
  // A grid of its own visits the items in another order (PolygonCollides' shape).
  if (cell_size_ != other.cell_size_) return false;
  if (segments_.size() != other.segments_.size() || circles_.size() != other.circles_.size()) {
    return false;
  }
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const Segment2& s = segments_[i];
    const Segment2& o = other.segments_[i];
    if (s.shape != o.shape || s.a != o.a || s.b != o.b) return false;
  }
  for (std::size_t i = 0; i < circles_.size(); ++i) {
    const Circle2& c = circles_[i];
    const Circle2& o = other.circles_[i];
    if (c.shape != o.shape || c.center != o.center || c.radius != o.radius) return false;
  }
  return true;
}

}  // namespace minibot3d_sim
