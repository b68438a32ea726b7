// A horizontal cross-section of the world at one height: line segments and circles in the plane.
//
// The lidar of a 2-D robot only ever sees one plane, and the kinematic backend only needs the
// chassis' plane, so casting against a precomputed slice replaces a 3-D ray test with a 2-D one.
// Boxes become polygons, upright cylinders and spheres circles, tilted cylinders polygons, meshes the
// segments where their triangles cross the plane. A uniform grid over the segments' and circles'
// bounds lets a ray visit only the cells it crosses (Amanatides & Woo 1987 traversal).
#ifndef MINIBOT3D_SIM_WORLD_SLICE_H_
#define MINIBOT3D_SIM_WORLD_SLICE_H_

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

struct Segment2 {
  Eigen::Vector2d a, b;
  int shape = -1;  // index into World::shapes
};

struct Circle2 {
  Eigen::Vector2d center;
  double radius = 0.0;
  int shape = -1;
};

struct RayHit {
  double range = std::numeric_limits<double>::infinity();  // +inf: nothing within max_range
  int shape = -1;
};

class WorldSlice {
 public:
  // Cuts `world` with the plane z = height. `cell_size` is the acceleration grid's cell (m).
  WorldSlice(const World& world, double height, double cell_size = 0.25);

  double height() const { return height_; }
  const std::vector<Segment2>& segments() const { return segments_; }
  const std::vector<Circle2>& circles() const { return circles_; }

  // First hit of the ray origin + t·dir (|dir| = 1) with t in [0, max_range].
  RayHit CastRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                 double max_range) const;

  // Casts a fan of n rays from one origin at once, ray k along (dir_x[k], dir_y[k]) (unit
  // vectors whose angles increase with k by `increment`, starting at `angle0`; the fan spans less
  // than 2π + increment). ranges[k] = the first hit within max_range, else +inf. Same answers as n
  // calls of CastRay, much cheaper for a lidar: every primitive within max_range is visited once,
  // its angular extent seen from the origin gives the beams it can block, and only those beams are
  // intersected with it — a polar z-buffer.
  void CastFan(const Eigen::Vector2d& origin, double angle0, double increment, int n,
               const double* dir_x, const double* dir_y, double max_range, double* ranges) const;

  // Whether the closed convex polygon (vertices in order, world frame) touches any geometry; if it
  // does and `shape` is not null, the index of one shape it touches.
  bool PolygonCollides(const std::vector<Eigen::Vector2d>& polygon, int* shape = nullptr) const;

  // Distance from p to the nearest geometry (inf when the slice is empty); with `away`, also the
  // unit vector from the nearest geometry's closest point to p (zero where p touches it and
  // inside a disc's centre).
  double Distance(const Eigen::Vector2d& p, Eigen::Vector2d* away = nullptr) const;

  // Whether `other` holds exactly the same segments and circles (same shapes, same order) on the
  // same grid: every query answers the same on both.
  bool SameGeometry(const WorldSlice& other) const;

 private:
  // Builds the acceleration grid over segments_ and circles_.
  void BuildGrid();
  // Grid cell range [*i0, *i1] × [*j0, *j1] overlapping the box [lo, hi] (clamped); false if none.
  bool CellRange(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int* i0, int* j0, int* i1,
                 int* j1) const;
  double ItemDistance(std::uint32_t item, const Eigen::Vector2d& p) const;
  bool ItemTouchesPolygon(std::uint32_t item, const std::vector<Eigen::Vector2d>& polygon,
                          double orientation) const;

  // Ray-test data in flat arrays: a segment as (a.x, a.y, (b-a).x, (b-a).y); a circle as
  // (c.x, c.y, r², r).
  struct Prim {
    double x, y, u, v;
  };

  double height_;
  double cell_size_;
  std::vector<Segment2> segments_;
  std::vector<Circle2> circles_;
  std::vector<Prim> prims_;  // segments first, then circles: item i ≥ segments_.size() is a circle
  Eigen::Vector2d grid_origin_ = Eigen::Vector2d::Zero();
  int grid_w_ = 0, grid_h_ = 0;
  // Compressed rows: the items of cell c = j·grid_w_ + i are cell_items_[cell_start_[c] ..
  // cell_start_[c + 1]).
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> cell_items_;
  // Unique per constructed slice; keys the thread-local "already tested this ray" stamps.
  std::uint64_t serial_ = 0;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_WORLD_SLICE_H_
