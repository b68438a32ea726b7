// WorldSlice: cuts of each shape type, ray casts (exact ranges, misses, rays from outside the grid,
// agreement with a brute-force reference), polygon collision, distance, and a cross-check of the
// shipped default world against Bullet's btCollisionWorld::rayTest.
#include "minibot3d_sim/world_slice.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletCollisionCommon.h>
#include <gtest/gtest.h>

#include "minibot3d_sim/bullet_world.h"
#include "minibot3d_sim/world_loader.h"

namespace minibot3d_sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Isometry3d MakePose(double x, double y, double z, double roll = 0.0, double pitch = 0.0,
                           double yaw = 0.0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return p;
}

Shape Box(const Eigen::Isometry3d& pose, double sx, double sy, double sz) {
  Shape s;
  s.type = ShapeType::kBox;
  s.name = "box";
  s.pose = pose;
  s.size = Eigen::Vector3d(sx, sy, sz);
  return s;
}

Shape Cylinder(const Eigen::Isometry3d& pose, double r, double length) {
  Shape s;
  s.type = ShapeType::kCylinder;
  s.name = "cylinder";
  s.pose = pose;
  s.size = Eigen::Vector3d(r, r, length);
  return s;
}

Shape Sphere(const Eigen::Isometry3d& pose, double r) {
  Shape s;
  s.type = ShapeType::kSphere;
  s.name = "sphere";
  s.pose = pose;
  s.size = Eigen::Vector3d(r, r, r);
  return s;
}

World WorldOf(std::vector<Shape> shapes) {
  World w;
  w.source = "test";
  w.shapes = std::move(shapes);
  return w;
}

// Signed area of the closed outline formed by the slice's segments (shoelace over segments).
double OutlineArea(const WorldSlice& slice) {
  double a = 0.0;
  for (const Segment2& s : slice.segments()) a += s.a.x() * s.b.y() - s.b.x() * s.a.y();
  return 0.5 * a;
}

bool HasEndpoint(const WorldSlice& slice, const Eigen::Vector2d& p, double tol = 1e-9) {
  for (const Segment2& s : slice.segments()) {
    if ((s.a - p).norm() < tol || (s.b - p).norm() < tol) return true;
  }
  return false;
}

// Upright boxes and cylinders cut the same lines at every height they span; a sphere does not,
// nor does a box that ends between the two heights.
TEST(WorldSliceTest, SameGeometryAtHeightsWhereNothingChanges) {
  const World prisms = WorldOf({Box(MakePose(1, 0, 0.5, 0, 0, 0.3), 0.4, 0.2, 1.0),
                                Cylinder(MakePose(-1, 0.5, 0.5), 0.2, 1.0)});
  const WorldSlice low(prisms, 0.1), high(prisms, 0.8);
  EXPECT_TRUE(low.SameGeometry(high));
  EXPECT_TRUE(low.SameGeometry(low));
  const WorldSlice coarse(prisms, 0.8, 0.5);  // another grid answers in another order
  EXPECT_FALSE(low.SameGeometry(coarse));
  World round = prisms;
  round.shapes.push_back(Sphere(MakePose(0, -1, 0.5), 0.4));
  EXPECT_FALSE(WorldSlice(round, 0.3).SameGeometry(WorldSlice(round, 0.6)));
  World shelf = prisms;
  shelf.shapes.push_back(Box(MakePose(0, 1, 0.25), 0.5, 0.5, 0.5));  // up to 0.5 m
  EXPECT_FALSE(WorldSlice(shelf, 0.1).SameGeometry(WorldSlice(shelf, 0.8)));
}

TEST(WorldSliceTest, BoxCutIsItsRectangle) {
  const WorldSlice slice(WorldOf({Box(MakePose(1.0, 2.0, 0.5), 2.0, 1.0, 1.0)}), 0.11);
  ASSERT_EQ(slice.segments().size(), 4u);
  EXPECT_TRUE(slice.circles().empty());
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(0.0, 1.5), Eigen::Vector2d(2.0, 1.5),
                                   Eigen::Vector2d(2.0, 2.5), Eigen::Vector2d(0.0, 2.5)}) {
    EXPECT_TRUE(HasEndpoint(slice, c)) << c.transpose();
  }
  EXPECT_NEAR(std::abs(OutlineArea(slice)), 2.0, 1e-12);
  for (const Segment2& s : slice.segments()) EXPECT_EQ(s.shape, 0);
}

TEST(WorldSliceTest, BoxNotReachingThePlaneGivesNothing) {
  const WorldSlice slice(WorldOf({Box(MakePose(0.0, 0.0, 1.0), 1.0, 1.0, 1.0)}), 0.11);
  EXPECT_TRUE(slice.segments().empty());
  const WorldSlice below(WorldOf({Box(MakePose(0.0, 0.0, -1.0), 1.0, 1.0, 1.0)}), 0.11);
  EXPECT_TRUE(below.segments().empty());
}

TEST(WorldSliceTest, YawedBoxCutIsRotatedRectangle) {
  const WorldSlice slice(WorldOf({Box(MakePose(0.0, 0.0, 0.5, 0, 0, M_PI / 4), 2.0, 2.0, 1.0)}),
                         0.3);
  ASSERT_EQ(slice.segments().size(), 4u);
  const double d = std::sqrt(2.0);
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(d, 0), Eigen::Vector2d(0, d),
                                   Eigen::Vector2d(-d, 0), Eigen::Vector2d(0, -d)}) {
    EXPECT_TRUE(HasEndpoint(slice, c)) << c.transpose();
  }
}

TEST(WorldSliceTest, TiltedBoxCutIsStretchedRectangle) {
  // Pitched by θ and cut through its centre: the cut crosses the ±x faces, so it is b wide and
  // a / cos θ long.
  const double theta = 20.0 * M_PI / 180.0;
  const WorldSlice slice(WorldOf({Box(MakePose(0.0, 0.0, 0.5, 0, theta, 0), 1.0, 0.6, 1.0)}),
                         0.5);
  ASSERT_EQ(slice.segments().size(), 4u);
  EXPECT_NEAR(std::abs(OutlineArea(slice)), 0.6 * 1.0 / std::cos(theta), 1e-12);
  EXPECT_TRUE(HasEndpoint(slice, Eigen::Vector2d(0.5 / std::cos(theta), 0.3)));
  // Rolled by 90°: the box's z extent now lies along y.
  const WorldSlice rolled(WorldOf({Box(MakePose(0.0, 0.0, 0.5, M_PI / 2, 0, 0), 1.0, 2.0, 0.4)}),
                          0.11);
  ASSERT_EQ(rolled.segments().size(), 4u);
  EXPECT_TRUE(HasEndpoint(rolled, Eigen::Vector2d(0.5, 0.2)));
  EXPECT_NEAR(std::abs(OutlineArea(rolled)), 0.4, 1e-12);
}

TEST(WorldSliceTest, UprightCylinderIsCircle) {
  const WorldSlice slice(
      WorldOf({Cylinder(MakePose(1.0, -1.0, 0.5), 0.3, 1.0),
               Cylinder(MakePose(0.0, 0.0, 2.0), 0.3, 1.0)}),  // above the plane
      0.11);
  ASSERT_EQ(slice.circles().size(), 1u);
  EXPECT_TRUE(slice.segments().empty());
  EXPECT_DOUBLE_EQ(slice.circles()[0].radius, 0.3);
  EXPECT_TRUE(slice.circles()[0].center.isApprox(Eigen::Vector2d(1.0, -1.0)));
  EXPECT_EQ(slice.circles()[0].shape, 0);
}

TEST(WorldSliceTest, LyingCylinderIsRectangle) {
  // Axis along y, centre 0.2 m up, radius 0.2: the plane 0.09 m below the axis cuts a strip
  // 2·√(r² − d²) wide and as long as the cylinder.
  const WorldSlice slice(WorldOf({Cylinder(MakePose(0.0, 0.0, 0.2, M_PI / 2, 0, 0), 0.2, 1.0)}),
                         0.11);
  EXPECT_TRUE(slice.circles().empty());
  ASSERT_GE(slice.segments().size(), 4u);
  double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
  for (const Segment2& s : slice.segments()) {
    for (const Eigen::Vector2d& p : {s.a, s.b}) {
      xmin = std::min(xmin, p.x());
      xmax = std::max(xmax, p.x());
      ymin = std::min(ymin, p.y());
      ymax = std::max(ymax, p.y());
    }
  }
  const double half_width = std::sqrt(0.2 * 0.2 - 0.09 * 0.09);
  EXPECT_NEAR(xmax, half_width, 1e-3);
  EXPECT_NEAR(xmin, -half_width, 1e-3);
  EXPECT_NEAR(ymax, 0.5, 1e-9);
  EXPECT_NEAR(ymin, -0.5, 1e-9);
}

TEST(WorldSliceTest, SphereCutRadius) {
  const WorldSlice slice(WorldOf({Sphere(MakePose(2.0, 3.0, 0.4), 0.5)}), 0.11);
  ASSERT_EQ(slice.circles().size(), 1u);
  EXPECT_NEAR(slice.circles()[0].radius, std::sqrt(0.25 - 0.29 * 0.29), 1e-12);
  EXPECT_TRUE(slice.circles()[0].center.isApprox(Eigen::Vector2d(2.0, 3.0)));
  const WorldSlice miss(WorldOf({Sphere(MakePose(2.0, 3.0, 0.7), 0.5)}), 0.11);
  EXPECT_TRUE(miss.circles().empty());
}

TEST(WorldSliceTest, MeshTriangleCut) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(2, 0, 0), Eigen::Vector3f(0, 0, 2)};
  mesh->triangles = {{0, 1, 2}};
  Shape s;
  s.type = ShapeType::kMesh;
  s.mesh = mesh;
  s.pose = MakePose(1.0, 1.0, 0.0, 0, 0, M_PI / 2);  // the triangle's x axis now points along +y
  const WorldSlice slice(WorldOf({s}), 0.5);
  ASSERT_EQ(slice.segments().size(), 1u);
  const Segment2& seg = slice.segments()[0];
  const Eigen::Vector2d lo = seg.a.y() < seg.b.y() ? seg.a : seg.b;
  const Eigen::Vector2d hi = seg.a.y() < seg.b.y() ? seg.b : seg.a;
  EXPECT_NEAR((lo - Eigen::Vector2d(1.0, 1.0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((hi - Eigen::Vector2d(1.0, 2.5)).norm(), 0.0, 1e-6);
  // Entirely above the plane: nothing.
  EXPECT_TRUE(WorldSlice(WorldOf({s}), -0.1).segments().empty());
}

TEST(WorldSliceTest, VerticalPlaneIsSegmentAndFloorIsIgnored) {
  Shape wall;
  wall.type = ShapeType::kPlane;
  wall.pose = MakePose(2.0, 0.0, 0.0);
  wall.normal = Eigen::Vector3d::UnitX();
  wall.size = Eigen::Vector3d(4.0, 2.0, 0.0);
  Shape floor;
  floor.type = ShapeType::kPlane;
  floor.size = Eigen::Vector3d(100.0, 100.0, 0.0);
  const WorldSlice slice(WorldOf({floor, wall}), 0.11);
  ASSERT_EQ(slice.segments().size(), 1u);
  EXPECT_EQ(slice.segments()[0].shape, 1);
  EXPECT_NEAR(std::abs(slice.segments()[0].a.x() - 2.0), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(slice.segments()[0].a.y()), 1.0, 1e-12);
  EXPECT_NEAR(slice.segments()[0].a.y() + slice.segments()[0].b.y(), 0.0, 1e-12);
  EXPECT_TRUE(WorldSlice(WorldOf({floor}), 0.0).segments().empty());
}

TEST(WorldSliceTest, RayRangeToBoxIsExact) {
  const WorldSlice slice(WorldOf({Box(MakePose(3.0, 0.0, 0.5), 1.0, 1.0, 1.0),
                                  Cylinder(MakePose(3.0, 4.0, 0.5), 1.0, 1.0)}),
                         0.11);
  const RayHit hit = slice.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), 10.0);
  EXPECT_NEAR(hit.range, 2.5, 1e-12);
  EXPECT_EQ(hit.shape, 0);
  // Towards the circle centre (3, 4), 5 m away, radius 1.
  const RayHit to_circle = slice.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(0.6, 0.8), 10.0);
  EXPECT_NEAR(to_circle.range, 4.0, 1e-12);
  EXPECT_EQ(to_circle.shape, 1);
  // At 45° from (0, −0.5), along y = x − 0.5: passes above the box (y = 2 at x = 2.5) and 1.06 m
  // from the circle's centre.
  const Eigen::Vector2d diag = Eigen::Vector2d(1, 1).normalized();
  const RayHit grazing = slice.CastRay(Eigen::Vector2d(0, -0.5), diag, 10.0);
  EXPECT_TRUE(std::isinf(grazing.range));
  // From (2, −0.5) at 45°: hits the left face x = 2.5 at y = 0.
  const RayHit corner = slice.CastRay(Eigen::Vector2d(2.0, -0.5), diag, 10.0);
  EXPECT_NEAR(corner.range, 0.5 * std::sqrt(2.0), 1e-12);
}

TEST(WorldSliceTest, NothingWithinRangeIsInfinity) {
  const WorldSlice slice(WorldOf({Box(MakePose(3.0, 0.0, 0.5), 1.0, 1.0, 1.0)}), 0.11);
  const RayHit away = slice.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(-1, 0), 10.0);
  EXPECT_TRUE(std::isinf(away.range));
  EXPECT_EQ(away.shape, -1);
  const RayHit short_range = slice.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), 2.4);
  EXPECT_TRUE(std::isinf(short_range.range));
  const RayHit just_enough = slice.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), 2.5);
  EXPECT_NEAR(just_enough.range, 2.5, 1e-12);
  const WorldSlice empty(WorldOf({}), 0.11);
  EXPECT_TRUE(std::isinf(empty.CastRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), 10).range));
}

TEST(WorldSliceTest, RaysFromOutsideTheGrid) {
  const WorldSlice slice(WorldOf({Box(MakePose(3.0, 0.0, 0.5), 1.0, 1.0, 1.0)}), 0.11);
  const RayHit far = slice.CastRay(Eigen::Vector2d(-50, 0), Eigen::Vector2d(1, 0), 100.0);
  EXPECT_NEAR(far.range, 52.5, 1e-9);
  const RayHit from_above =
      slice.CastRay(Eigen::Vector2d(3.2, 40.0), Eigen::Vector2d(0, -1), 100.0);
  EXPECT_NEAR(from_above.range, 39.5, 1e-9);
  const RayHit beside = slice.CastRay(Eigen::Vector2d(-50, 5), Eigen::Vector2d(1, 0), 100.0);
  EXPECT_TRUE(std::isinf(beside.range));
  const RayHit away = slice.CastRay(Eigen::Vector2d(-50, 0), Eigen::Vector2d(-1, 0), 100.0);
  EXPECT_TRUE(std::isinf(away.range));
  // Too short to reach the grid at all.
  const RayHit short_ray = slice.CastRay(Eigen::Vector2d(-50, 0), Eigen::Vector2d(1, 0), 40.0);
  EXPECT_TRUE(std::isinf(short_ray.range));
}

// Reference ray cast: every segment and circle, no grid.
double BruteForceRay(const WorldSlice& slice, const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                     double max_range) {
  double best = kInf;
  for (const Segment2& s : slice.segments()) {
    const Eigen::Vector2d e = s.b - s.a;
    Eigen::Matrix2d m;
    m << d, -e;
    if (std::abs(m.determinant()) < 1e-15) continue;
    const Eigen::Vector2d ts = m.inverse() * (s.a - o);
    if (ts[0] >= 0.0 && ts[1] >= 0.0 && ts[1] <= 1.0) best = std::min(best, ts[0]);
  }
  for (const Circle2& c : slice.circles()) {
    const Eigen::Vector2d w = o - c.center;
    const double b = w.dot(d), cc = w.squaredNorm() - c.radius * c.radius;
    const double disc = b * b - cc;
    if (disc < 0.0) continue;
    const double t0 = -b - std::sqrt(disc), t1 = -b + std::sqrt(disc);
    if (t0 >= 0.0) {
      best = std::min(best, t0);
    } else if (t1 >= 0.0) {
      best = std::min(best, t1);
    }
  }
  return best <= max_range ? best : kInf;
}

World RandomWorld(std::mt19937* rng) {
  std::uniform_real_distribution<double> pos(-4.0, 4.0), size(0.1, 1.2), angle(-M_PI, M_PI);
  std::vector<Shape> shapes;
  for (int i = 0; i < 25; ++i) {
    shapes.push_back(Box(MakePose(pos(*rng), pos(*rng), 0.5, 0, 0, angle(*rng)), size(*rng),
                         size(*rng), 1.0));
  }
  for (int i = 0; i < 10; ++i) {
    shapes.push_back(Cylinder(MakePose(pos(*rng), pos(*rng), 0.5), 0.5 * size(*rng), 1.0));
  }
  // A long diagonal wall spanning many cells.
  shapes.push_back(Box(MakePose(0.0, 0.0, 0.5, 0, 0, 0.6), 9.0, 0.05, 1.0));
  return WorldOf(shapes);
}

TEST(WorldSliceTest, GridTraversalMatchesBruteForce) {
  std::mt19937 rng(7);
  const World world = RandomWorld(&rng);
  for (double cell : {0.1, 0.25, 1.0, 50.0}) {
    const WorldSlice slice(world, 0.11, cell);
    std::uniform_real_distribution<double> pos(-7.0, 7.0), angle(-M_PI, M_PI);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
      const Eigen::Vector2d o(pos(rng), pos(rng));
      const double a = angle(rng);
      // Include exactly axis-aligned directions, the DDA's special case.
      const Eigen::Vector2d d = (i % 10 == 0) ? Eigen::Vector2d(std::cos(std::round(a / M_PI_2) *
                                                                         M_PI_2),
                                                                std::sin(std::round(a / M_PI_2) *
                                                                         M_PI_2))
                                              : Eigen::Vector2d(std::cos(a), std::sin(a));
      const Eigen::Vector2d dir = d.normalized();
      const double max_range = (i % 3 == 0) ? 2.0 : 20.0;
      const double expected = BruteForceRay(slice, o, dir, max_range);
      const double got = slice.CastRay(o, dir, max_range).range;
      if (std::isinf(expected)) {
        EXPECT_TRUE(std::isinf(got)) << "cell " << cell << " ray " << i;
      } else {
        ++hits;
        EXPECT_NEAR(got, expected, 1e-9) << "cell " << cell << " ray " << i;
      }
    }
    EXPECT_GT(hits, 1000);
  }
}

std::vector<Eigen::Vector2d> Square(const Eigen::Vector2d& c, double half) {
  return {c + Eigen::Vector2d(-half, -half), c + Eigen::Vector2d(half, -half),
          c + Eigen::Vector2d(half, half), c + Eigen::Vector2d(-half, half)};
}

TEST(WorldSliceTest, PolygonCollides) {
  const WorldSlice slice(
      WorldOf({Box(MakePose(3.0, 0.0, 0.5), 1.0, 1.0, 1.0),
               Cylinder(MakePose(0.0, 3.0, 0.5), 0.5, 1.0),
               Box(MakePose(-3.0, 0.0, 0.5), 0.1, 0.1, 1.0)}),  // small enough to fit inside
      0.11);
  int shape = -7;
  EXPECT_FALSE(slice.PolygonCollides(Square(Eigen::Vector2d(0, 0), 0.5), &shape));
  EXPECT_EQ(shape, -7);
  // Overlapping the box's left face (x = 2.5).
  EXPECT_TRUE(slice.PolygonCollides(Square(Eigen::Vector2d(2.2, 0.3), 0.35), &shape));
  EXPECT_EQ(shape, 0);
  // Just short of it.
  EXPECT_FALSE(slice.PolygonCollides(Square(Eigen::Vector2d(2.2, 0.3), 0.29)));
  // Circle of radius 0.5 at (0, 3): the square's top edge at y = 2.49 misses it, at 2.51 touches.
  EXPECT_FALSE(slice.PolygonCollides(Square(Eigen::Vector2d(0.0, 2.2), 0.29)));
  EXPECT_TRUE(slice.PolygonCollides(Square(Eigen::Vector2d(0.0, 2.2), 0.31), &shape));
  EXPECT_EQ(shape, 1);
  // The polygon swallows the small box whole: no edge crosses, it still collides.
  EXPECT_TRUE(slice.PolygonCollides(Square(Eigen::Vector2d(-3.0, 0.0), 0.4), &shape));
  EXPECT_EQ(shape, 2);
  // Clockwise order works too.
  std::vector<Eigen::Vector2d> cw = Square(Eigen::Vector2d(-3.0, 0.0), 0.4);
  std::reverse(cw.begin(), cw.end());
  EXPECT_TRUE(slice.PolygonCollides(cw));
  // A polygon inside a large circle (no edge near the rim).
  EXPECT_TRUE(slice.PolygonCollides(Square(Eigen::Vector2d(0.0, 3.0), 0.1)));
  // Far outside the grid.
  EXPECT_FALSE(slice.PolygonCollides(Square(Eigen::Vector2d(100.0, 100.0), 1.0)));
}

TEST(WorldSliceTest, Distance) {
  const WorldSlice slice(WorldOf({Box(MakePose(3.0, 0.0, 0.5), 1.0, 1.0, 1.0),
                                  Cylinder(MakePose(0.0, 3.0, 0.5), 0.5, 1.0)}),
                         0.11, 0.25);
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(0.0, 0.0)), 2.5, 1e-12);
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(0.0, 1.5)), 1.0, 1e-12);
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(2.0, 1.0)), std::sqrt(0.25 + 0.25), 1e-12);
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(3.0, 0.2)), 0.3, 1e-12);  // inside: to the outline
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(20.0, 0.0)), 16.5, 1e-12);  // outside the grid
  EXPECT_TRUE(std::isinf(WorldSlice(WorldOf({}), 0.11).Distance(Eigen::Vector2d(0, 0))));
  // With the direction away from the nearest geometry: the gradient of the distance.
  Eigen::Vector2d away;
  EXPECT_NEAR(slice.Distance(Eigen::Vector2d(0.0, 1.5), &away), 1.0, 1e-12);
  EXPECT_NEAR((away - Eigen::Vector2d(0.0, -1.0)).norm(), 0.0, 1e-12) << "from the cylinder";
  slice.Distance(Eigen::Vector2d(2.0, 1.0), &away);
  EXPECT_NEAR((away - Eigen::Vector2d(-1.0, 1.0).normalized()).norm(), 0.0, 1e-12)
      << "from the box's corner";
  slice.Distance(Eigen::Vector2d(2.0, 0.2), &away);
  EXPECT_NEAR((away - Eigen::Vector2d(-1.0, 0.0)).norm(), 0.0, 1e-12) << "from its side";

  // Against a brute-force minimum for random points.
  std::mt19937 rng(3);
  const WorldSlice big(RandomWorld(&rng), 0.11, 0.2);
  std::uniform_real_distribution<double> pos(-6.0, 6.0);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector2d p(pos(rng), pos(rng));
    double expected = kInf;
    for (const Segment2& s : big.segments()) {
      const Eigen::Vector2d e = s.b - s.a;
      const double t = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      expected = std::min(expected, (s.a + t * e - p).norm());
    }
    for (const Circle2& c : big.circles()) {
      expected = std::min(expected, std::max(0.0, (p - c.center).norm() - c.radius));
    }
    EXPECT_NEAR(big.Distance(p), expected, 1e-12) << p.transpose();
    // The direction agrees with a central difference of the distance, off the medial axis.
    const double h = 1e-6;
    const Eigen::Vector2d diff(big.Distance(p + Eigen::Vector2d(h, 0)) -
                                   big.Distance(p - Eigen::Vector2d(h, 0)),
                               big.Distance(p + Eigen::Vector2d(0, h)) -
                                   big.Distance(p - Eigen::Vector2d(0, h)));
    Eigen::Vector2d away_p;
    big.Distance(p, &away_p);
    if (expected > 1e-3 && std::abs(diff.norm() / (2 * h) - 1.0) < 1e-4) {
      EXPECT_NEAR((away_p - diff / (2 * h)).norm(), 0.0, 1e-4) << p.transpose();
    }
  }
}

#ifdef MINIBOT3D_SIM_SOURCE_DIR
// The demo drives a 1 m square from the default world's spawn pose (−3, −1.5, yaw 0), forward
// first and turning either way: every point of both squares keeps 0.4 m from all geometry at the
// chassis' and the lidar's heights (enough for a robot 0.25 m wide with inflation, at any heading).
TEST(WorldSliceTest, DefaultWorldSpawnSquareIsFree) {
  WorldLoadOptions options;
  options.use_gazebo_model_path_env = false;
  const World world =
      LoadWorld(std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world", options, nullptr);
  const Eigen::Vector2d spawn(-3.0, -1.5);
  for (double height : {0.05, 0.11, 0.2}) {
    const WorldSlice slice(world, height);
    for (double turn : {1.0, -1.0}) {
      const std::vector<Eigen::Vector2d> corners = {
          spawn, spawn + Eigen::Vector2d(1, 0), spawn + Eigen::Vector2d(1, turn),
          spawn + Eigen::Vector2d(0, turn), spawn};
      for (std::size_t c = 0; c + 1 < corners.size(); ++c) {
        for (int k = 0; k <= 100; ++k) {
          const Eigen::Vector2d p = corners[c] + (corners[c + 1] - corners[c]) * (k / 100.0);
          EXPECT_GE(slice.Distance(p), 0.4) << "at " << p.transpose() << ", height " << height;
        }
      }
      // The robot's inflated footprint (0.5 × 0.45 m) turned every 15° at each corner.
      for (const Eigen::Vector2d& corner : corners) {
        for (int deg = 0; deg < 360; deg += 15) {
          const Eigen::Rotation2Dd rot(deg * M_PI / 180.0);
          std::vector<Eigen::Vector2d> footprint;
          for (const Eigen::Vector2d& v :
               {Eigen::Vector2d(-0.25, -0.225), Eigen::Vector2d(0.25, -0.225),
                Eigen::Vector2d(0.25, 0.225), Eigen::Vector2d(-0.25, 0.225)}) {
            footprint.push_back(corner + rot * v);
          }
          EXPECT_FALSE(slice.PolygonCollides(footprint)) << corner.transpose() << " " << deg;
        }
      }
    }
  }
}

// Unit normal of the slice outline of shape `shape` nearest to p (the surface a ray hit there).
Eigen::Vector2d OutlineNormal(const WorldSlice& slice, int shape, const Eigen::Vector2d& p) {
  double best = kInf;
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  for (const Segment2& s : slice.segments()) {
    if (s.shape != shape) continue;
    const Eigen::Vector2d e = s.b - s.a;
    const double t = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double d = (s.a + t * e - p).norm();
    if (d < best) {
      best = d;
      normal = Eigen::Vector2d(-e.y(), e.x()).normalized();
    }
  }
  for (const Circle2& c : slice.circles()) {
    if (c.shape != shape) continue;
    const double d = std::abs((p - c.center).norm() - c.radius);
    if (d < best) {
      best = d;
      normal = (p - c.center).normalized();
    }
  }
  return normal;
}

// Whether p lies within `band` of an outline vertex of shape `shape`.
bool NearVertex(const WorldSlice& slice, int shape, const Eigen::Vector2d& p, double band) {
  for (const Segment2& s : slice.segments()) {
    if (s.shape == shape && ((s.a - p).norm() < band || (s.b - p).norm() < band)) return true;
  }
  return false;
}

// The 2-D lidar must see what a 3-D ray test on the same world sees.
//
// Bullet's convex ray cast (GJK, which stops once within 1 mm of the surface) places a hit up to
// 1 mm off the surface along its normal, which at grazing incidence becomes centimetres along the
// ray; so each range must agree within 1 mm measured along the surface normal
// (|Δ|·|cos incidence|), and 95 % of the ranges within 1 mm outright. Bullet rounds box edges by
// its 2 mm margin, so hits within 3 mm of a box corner are left out. Cylinders are left out of the
// comparison: Bullet's ray cast against btCylinderShapeZ is off by 1.5 cm (sub-simplex cast) to
// 30 cm (GJK cast) near the rim, so it cannot referee them; the slice's circles are checked against
// exact intersections in the tests above.
TEST(WorldSliceTest, DefaultWorldAgreesWithBulletRayTest) {
  const std::string path = std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world";
  WorldLoadOptions options;
  options.use_gazebo_model_path_env = false;
  World world = LoadWorld(path, options, nullptr);
  const std::size_t all_shapes = world.shapes.size();
  world.shapes.erase(std::remove_if(world.shapes.begin(), world.shapes.end(),
                                    [](const Shape& s) { return s.type == ShapeType::kCylinder; }),
                     world.shapes.end());
  ASSERT_LT(world.shapes.size(), all_shapes);
  constexpr double kLidarHeight = 0.11, kMaxRange = 12.0, kTolerance = 1e-3;
  // Bullet rounds box edges by the collision margin (2 mm in BulletWorldObjects).
  constexpr double kCornerBand = 3e-3;
  const WorldSlice slice(world, kLidarHeight);

  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld collision_world(&dispatcher, &broadphase, &config);
  const BulletWorldObjects objects(world, &collision_world);
  collision_world.updateAabbs();

  // One pose per room and the corridor (two see the sculpture); 600 beams each = 3,600 rays.
  const std::vector<Eigen::Vector2d> poses = {{-3.0, -1.5}, {0.0, 0.6},  {3.0, -1.0},
                                              {0.5, 2.0},   {-2.5, 2.2}, {3.7, 2.5}};
  constexpr int kBeams = 600;
  int compared = 0, hits = 0, ground = 0, within_1mm = 0, mesh_hits = 0, at_corner = 0;
  double worst_along_normal = 0.0;
  for (const Eigen::Vector2d& p : poses) {
    for (int k = 0; k < kBeams; ++k) {
      const double a = 2.0 * M_PI * (k + 0.37) / kBeams;  // off the axes: no beam runs along a wall
      const Eigen::Vector2d dir(std::cos(a), std::sin(a));
      const btVector3 from(p.x(), p.y(), kLidarHeight);
      const btVector3 to(p.x() + kMaxRange * dir.x(), p.y() + kMaxRange * dir.y(), kLidarHeight);
      btCollisionWorld::ClosestRayResultCallback cb(from, to);
      // Bullet's default sub-simplex convex cast is off by centimetres even at normal incidence;
      // the GJK convex cast converges to within 1 mm of the surface.
      cb.m_flags |= btTriangleRaycastCallback::kF_UseGjkConvexCastRaytest;
      collision_world.rayTest(from, to, cb);
      double bullet_range = kInf;
      if (cb.hasHit()) {
        const int index = cb.m_collisionObject->getUserIndex();
        ASSERT_GE(index, 0);
        if (world.shapes[index].type == ShapeType::kPlane) {
          ++ground;
          continue;
        }
        bullet_range = cb.m_closestHitFraction * kMaxRange;
      }
      const RayHit hit = slice.CastRay(p, dir, kMaxRange);
      ++compared;
      if (std::isinf(bullet_range)) {
        EXPECT_TRUE(std::isinf(hit.range)) << "pose " << p.transpose() << " beam " << k;
        ++within_1mm;
        continue;
      }
      ASSERT_FALSE(std::isinf(hit.range)) << "pose " << p.transpose() << " beam " << k;
      if (NearVertex(slice, hit.shape, p + hit.range * dir, kCornerBand)) {
        ++at_corner;
        continue;
      }
      ++hits;
      const double diff = std::abs(hit.range - bullet_range);
      if (world.shapes[hit.shape].type == ShapeType::kMesh) ++mesh_hits;
      if (diff <= kTolerance) ++within_1mm;
      const Eigen::Vector2d normal = OutlineNormal(slice, hit.shape, p + hit.range * dir);
      const double along_normal = diff * std::abs(normal.dot(dir));
      worst_along_normal = std::max(worst_along_normal, along_normal);
      EXPECT_LE(along_normal, kTolerance)
          << "pose " << p.transpose() << " beam " << k << ": slice " << hit.range << " ("
          << world.shapes[hit.shape].name << ") vs bullet " << bullet_range << " ("
          << world.shapes[cb.m_collisionObject->getUserIndex()].name << ")";
    }
  }
  EXPECT_EQ(compared + ground, static_cast<int>(poses.size()) * kBeams);
  EXPECT_GT(mesh_hits, 0);  // the sculpture is seen, so meshes are compared too
  // Walls all round: nearly every beam hits something within 12 m; corner grazes are rare.
  EXPECT_GT(hits, compared * 9 / 10);
  EXPECT_LT(at_corner, compared / 100);
  EXPECT_GE(within_1mm, compared * 95 / 100);
  std::cout << "[ cross-check ] " << compared << " rays, " << hits << " hits (" << mesh_hits
            << " on the mesh, " << at_corner << " within 3 mm of a box corner left out), "
            << within_1mm
            << " ranges within 1 mm of Bullet, worst difference along the surface normal "
            << worst_along_normal * 1e3 << " mm\n";
}

// CastFan (the lidar's batched cast) gives what CastRay gives, beam by beam, for full circles
// (Gazebo-style, first and last beam both at ±π), partial fans and single beams, from many poses.
TEST(WorldSliceTest, FanCastMatchesRayCastInDefaultWorld) {
  WorldLoadOptions options;
  options.use_gazebo_model_path_env = false;
  const World world =
      LoadWorld(std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world", options, nullptr);
  const WorldSlice slice(world, 0.125);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(-5.5, 5.5), uy(-4.5, 4.5), ua(-M_PI, M_PI);
  struct Fan { double min_angle, max_angle; int n; double range; };
  const Fan fans[] = {{-M_PI, M_PI, 360, 12.0}, {-M_PI / 4, M_PI / 3, 97, 3.0},
                      {0.3, 0.3, 1, 12.0}, {-2.0, 2.0, 721, 30.0}};
  int compared = 0, hits = 0;
  for (int pose = 0; pose < 200; ++pose) {
    const Eigen::Vector2d o(ux(rng), uy(rng));
    const double yaw = ua(rng);
    for (const Fan& f : fans) {
      const double inc = f.n > 1 ? (f.max_angle - f.min_angle) / (f.n - 1) : 0.0;
      std::vector<double> dx(f.n), dy(f.n), fan(f.n);
      for (int k = 0; k < f.n; ++k) {
        dx[k] = std::cos(yaw + f.min_angle + k * inc);
        dy[k] = std::sin(yaw + f.min_angle + k * inc);
      }
      slice.CastFan(o, yaw + f.min_angle, inc, f.n, dx.data(), dy.data(), f.range, fan.data());
      for (int k = 0; k < f.n; ++k) {
        const double ray = slice.CastRay(o, Eigen::Vector2d(dx[k], dy[k]), f.range).range;
        ++compared;
        if (std::isinf(ray)) {
          EXPECT_TRUE(std::isinf(fan[k])) << "pose " << pose << " beam " << k << ": " << fan[k];
        } else {
          ++hits;
          EXPECT_NEAR(fan[k], ray, 1e-9) << "pose " << pose << " beam " << k;
        }
      }
    }
  }
  EXPECT_GT(hits, compared / 2);
}
#endif

}  // namespace
}  // namespace minibot3d_sim
