#include "minibot3d_common/geometry2d.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_common {
namespace {

TEST(Geometry2dTest, NormalizeAngleWrapsIntoHalfOpenRange) {
  EXPECT_NEAR(NormalizeAngle(3 * kPi / 2), -kPi / 2, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-3 * kPi / 2), kPi / 2, 1e-12);
  EXPECT_NEAR(NormalizeAngle(kPi), -kPi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-kPi), -kPi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(20 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(AngleDiff(0.1, 2 * kPi - 0.1), 0.2, 1e-12);
}

TEST(Geometry2dTest, ComposeAndBetweenAreInverse) {
  const Pose2 a{1.0, -2.0, 0.7}, b{-0.5, 3.0, -2.9};
  // Worked out by hand: b at (1, 0) facing +y, seen from a at (1, 1) facing +x, is at (0, -1).
  const Pose2 rel = Between(Pose2{1, 1, 0}, Pose2{1, 0, kPi / 2});
  EXPECT_NEAR(rel.x, 0.0, 1e-12);
  EXPECT_NEAR(rel.y, -1.0, 1e-12);
  EXPECT_NEAR(rel.yaw, kPi / 2, 1e-12);
  const Pose2 back = Compose(a, Between(a, b));
  EXPECT_NEAR(back.x, b.x, 1e-12);
  EXPECT_NEAR(back.y, b.y, 1e-12);
  EXPECT_NEAR(AngleDiff(back.yaw, b.yaw), 0.0, 1e-12);
  const Pose2 turned = Compose(Pose2{0, 0, kPi / 2}, Pose2{2, 0, 0});
  EXPECT_NEAR(turned.x, 0.0, 1e-12);
  EXPECT_NEAR(turned.y, 2.0, 1e-12);
}

TEST(Geometry2dTest, TransformPointForBothPointTypes) {
  const Pose2 p{1.0, 2.0, kPi / 2};
  const Point2 q = TransformPoint(p, Point2{1.0, 0.0});
  EXPECT_NEAR(q.x, 1.0, 1e-12);
  EXPECT_NEAR(q.y, 3.0, 1e-12);
  const Eigen::Vector2d e = TransformPoint(p, Eigen::Vector2d(0.0, 1.0));
  EXPECT_NEAR(e.x(), 0.0, 1e-12);
  EXPECT_NEAR(e.y(), 2.0, 1e-12);
}

TEST(Geometry2dTest, PointSegmentDistance) {
  const Point2 a{0, 0}, b{2, 0};
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Point2{1, 3}, a, b), 3.0);   // above the middle
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Point2{5, 4}, a, b), 5.0);   // past b: to b
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Point2{-3, -4}, a, b), 5.0);  // before a: to a
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Point2{1, 0}, a, b), 0.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Point2{3, 4}, a, a), 5.0);   // a point segment
  EXPECT_DOUBLE_EQ(PointSegmentDistance(Eigen::Vector2d(1, -2), Eigen::Vector2d(0, 0),
                                        Eigen::Vector2d(2, 0)), 2.0);
}

TEST(Geometry2dTest, PointInPolygon) {
  // An L-shaped (concave) polygon, counter-clockwise.
  const std::vector<Point2> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_TRUE(PointInPolygon(l, 0.5, 0.5));
  EXPECT_TRUE(PointInPolygon(l, 0.5, 1.5));
  EXPECT_TRUE(PointInPolygon(l, 1.5, 0.5));
  EXPECT_FALSE(PointInPolygon(l, 1.5, 1.5));  // the notch
  EXPECT_FALSE(PointInPolygon(l, -0.1, 0.5));
  std::vector<Point2> reversed(l.rbegin(), l.rend());
  EXPECT_TRUE(PointInPolygon(reversed, 0.5, 1.5));
  EXPECT_FALSE(PointInPolygon(reversed, 1.5, 1.5));
  EXPECT_FALSE(PointInPolygon(std::vector<Point2>{}, 0.0, 0.0));
}

TEST(Geometry2dTest, PointPolygonDistance) {
  const std::vector<Point2> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(PointPolygonDistance(l, 0.5, 0.5), 0.0);   // inside
  EXPECT_DOUBLE_EQ(PointPolygonDistance(l, 1.5, 1.5), 0.5);   // the notch: to either inner edge
  EXPECT_DOUBLE_EQ(PointPolygonDistance(l, 3.0, 0.5), 1.0);   // beside the right edge
  EXPECT_NEAR(PointPolygonDistance(l, 3.0, 2.0), std::hypot(1.0, 1.0), 1e-12);  // off a corner
  EXPECT_DOUBLE_EQ(PointPolygonDistance(l, -0.25, 3.0), std::hypot(0.25, 1.0));
  EXPECT_TRUE(std::isinf(PointPolygonDistance(std::vector<Point2>{}, 0.0, 0.0)));
  // Signed: minus the depth inside.
  EXPECT_DOUBLE_EQ(SignedPointPolygonDistance(l, 0.5, 0.25), -0.25);
  EXPECT_DOUBLE_EQ(SignedPointPolygonDistance(l, 1.5, 1.5), 0.5);
}

}  // namespace
}  // namespace minibot3d_common
