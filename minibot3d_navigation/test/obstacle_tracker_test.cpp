#include "minibot3d_navigation/tracking/obstacle_tracker.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_navigation {
namespace nav {
namespace {

// What a planar laser at `origin` sees of a cylinder of `radius` at `centre`: the arc facing it,
// a point every `step` rad of bearing, with Gaussian range noise.
std::vector<Point2> SeenCylinder(const Point2& origin, const Point2& centre, double radius,
                                 std::mt19937* rng, double noise = 0.01, double step = 0.0175) {
  std::vector<Point2> out;
  const double dx = centre.x - origin.x, dy = centre.y - origin.y;
  const double d = std::hypot(dx, dy);
  const double half = std::asin(std::min(1.0, radius / d));
  const double bearing = std::atan2(dy, dx);
  std::normal_distribution<double> n(0.0, noise);
  for (double a = bearing - half + step / 2; a < bearing + half; a += step) {
    // Nearest intersection of the ray with the circle.
    const double ux = std::cos(a), uy = std::sin(a);
    const double b = ux * dx + uy * dy;
    const double c = dx * dx + dy * dy - radius * radius;
    const double disc = b * b - c;
    if (disc < 0.0) continue;
    const double r = b - std::sqrt(disc) + n(*rng);
    out.push_back({origin.x + r * ux, origin.y + r * uy});
  }
  return out;
}

// A straight wall from a to b, a point every 2 cm.
std::vector<Point2> Wall(const Point2& a, const Point2& b) {
  std::vector<Point2> out;
  const int n = static_cast<int>(std::hypot(b.x - a.x, b.y - a.y) / 0.02);
  for (int i = 0; i <= n; ++i) {
    out.push_back({a.x + (b.x - a.x) * i / n, a.y + (b.y - a.y) * i / n});
  }
  return out;
}

TEST(ObstacleTrackerTest, ClustersKeepSmallObjectsAndDropWalls) {
  ObstacleTracker tracker{ObstacleTrackerOptions()};
  std::mt19937 rng(1);
  std::vector<Point2> pts = Wall({-3.0, 2.0}, {3.0, 2.0});
  const std::vector<Point2> person = SeenCylinder({0, 0}, {1.5, 0.0}, 0.25, &rng);
  const std::vector<Point2> leg = SeenCylinder({0, 0}, {0.0, -1.0}, 0.025, &rng, 0.0, 0.005);
  pts.insert(pts.end(), person.begin(), person.end());
  pts.insert(pts.end(), leg.begin(), leg.end());
  pts.push_back({9.0, 0.0});  // out of range
  const auto clusters = tracker.Clusters({0, 0}, pts);
  ASSERT_EQ(clusters.size(), 2u) << "the person and the leg; not the 6 m wall";
  bool saw_person = false, saw_leg = false;
  for (const auto& c : clusters) {
    if (std::hypot(c.centre.x - 1.5, c.centre.y) < 0.3) saw_person = true;
    if (std::hypot(c.centre.x, c.centre.y + 1.0) < 0.05) saw_leg = true;
  }
  EXPECT_TRUE(saw_person);
  EXPECT_TRUE(saw_leg);
}

TEST(ObstacleTrackerTest, APersonWalkingIsTrackedAtItsVelocity) {
  ObstacleTracker tracker{ObstacleTrackerOptions()};
  std::mt19937 rng(2);
  // From (1, 2) towards (1, -2) at 1.2 m/s, seen at 10 Hz from the origin beside a wall.
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    std::vector<Point2> pts = Wall({-2.0, -2.5}, {4.0, -2.5});
    const std::vector<Point2> p = SeenCylinder({0, 0}, {2.0, 2.0 - 1.2 * t}, 0.25, &rng);
    pts.insert(pts.end(), p.begin(), p.end());
    ASSERT_TRUE(tracker.Update(t, {0, 0}, pts));
  }
  const std::vector<TrackedObstacle> moving = tracker.MovingAt(2.0);
  ASSERT_EQ(moving.size(), 1u);
  EXPECT_NEAR(moving[0].velocity.x, 0.0, 0.15);
  EXPECT_NEAR(moving[0].velocity.y, -1.2, 0.15);
  // The centroid of the arc the laser sees lies a little in front of the centre.
  EXPECT_NEAR(moving[0].position.x, 2.0, 0.25);
  EXPECT_NEAR(moving[0].position.y, -0.4, 0.2);
  // Predicted on at constant velocity.
  const std::vector<TrackedObstacle> later = tracker.MovingAt(2.5);
  ASSERT_EQ(later.size(), 1u);
  EXPECT_NEAR(later[0].position.y - moving[0].position.y, 0.5 * moving[0].velocity.y, 1e-9);
}

TEST(ObstacleTrackerTest, StandingThingsAreNotMoving) {
  ObstacleTracker tracker{ObstacleTrackerOptions()};
  std::mt19937 rng(3);
  for (int k = 0; k <= 30; ++k) {
    std::vector<Point2> pts = SeenCylinder({0, 0}, {1.0, 1.0}, 0.25, &rng);
    const std::vector<Point2> leg = SeenCylinder({0, 0}, {-1.0, 0.5}, 0.03, &rng, 0.01, 0.005);
    pts.insert(pts.end(), leg.begin(), leg.end());
    tracker.Update(0.1 * k, {0, 0}, pts);
  }
  EXPECT_EQ(tracker.tracks().size(), 2u);
  EXPECT_TRUE(tracker.MovingAt(3.0).empty());
}

TEST(ObstacleTrackerTest, TwoPeopleCrossingKeepTheirTracks) {
  ObstacleTracker tracker{ObstacleTrackerOptions()};
  std::mt19937 rng(4);
  // One walks +x along y = 1.2, the other -x along y = -1.2 (2.4 m apart as they pass).
  std::vector<int> ids;
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.1 * k;
    std::vector<Point2> pts = SeenCylinder({0, 0}, {-1.5 + t, 1.2}, 0.25, &rng);
    const std::vector<Point2> q = SeenCylinder({0, 0}, {1.5 - t, -1.2}, 0.25, &rng);
    pts.insert(pts.end(), q.begin(), q.end());
    tracker.Update(t, {0, 0}, pts);
    if (k == 5) {
      for (const auto& m : tracker.MovingAt(t)) ids.push_back(m.id);
    }
  }
  ASSERT_EQ(ids.size(), 2u);
  const std::vector<TrackedObstacle> moving = tracker.MovingAt(3.0);
  ASSERT_EQ(moving.size(), 2u);
  for (const auto& m : moving) {
    EXPECT_TRUE(m.id == ids[0] || m.id == ids[1]) << "track " << m.id << " was restarted";
    const double expected_vx = m.position.y > 0 ? 1.0 : -1.0;
    EXPECT_NEAR(m.velocity.x, expected_vx, 0.15);
  }
}

TEST(ObstacleTrackerTest, APersonWhoStopsStaysAMovingObstacle) {
  ObstacleTracker tracker{ObstacleTrackerOptions()};
  std::mt19937 rng(6);
  // Walks 1 m in 1 s, then stands for 2 s.
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.1 * k;
    tracker.Update(t, {0, 0}, SeenCylinder({0, 0}, {2.0, -1.0 + std::min(t, 1.0)}, 0.25, &rng));
  }
  const std::vector<TrackedObstacle> moving = tracker.MovingAt(3.0);
  ASSERT_EQ(moving.size(), 1u);
  EXPECT_LT(std::hypot(moving[0].velocity.x, moving[0].velocity.y), 0.1);
}

TEST(ObstacleTrackerTest, AWallSeenGrowingIsNotAMovingObstacle) {
  // The visible end of a wall grows by 2.5 cm per scan: its centroid runs at 0.125 m/s... and
  // 0.25 m/s in the second half, but goes less than min_travel from where it was first seen.
  for (double min_travel : {0.0, 0.4}) {
    ObstacleTrackerOptions o;
    o.min_travel = min_travel;
    ObstacleTracker tracker(o);
    for (int k = 0; k <= 30; ++k) {
      const double grow = k < 15 ? 0.025 * k : 0.375 + 0.05 * (k - 15);
      tracker.Update(0.1 * k, {0, 0}, Wall({1.0, 1.0}, {1.1 + std::min(grow, 0.7), 1.0}));
    }
    if (min_travel == 0.0) {
      EXPECT_EQ(tracker.MovingAt(3.0).size(), 1u) << "with speed alone it would be";
    } else {
      EXPECT_TRUE(tracker.MovingAt(3.0).empty());
    }
  }
}

TEST(ObstacleTrackerTest, UnseenTracksAreDroppedAndOldObservationsIgnored) {
  ObstacleTrackerOptions o;
  o.max_missed_time = 0.3;
  ObstacleTracker tracker(o);
  std::mt19937 rng(5);
  for (int k = 0; k <= 5; ++k) {
    tracker.Update(0.1 * k, {0, 0}, SeenCylinder({0, 0}, {1.0 + 0.2 * k, 0.0}, 0.25, &rng));
  }
  EXPECT_EQ(tracker.MovingAt(0.5).size(), 1u);
  EXPECT_FALSE(tracker.Update(0.2, {0, 0}, {})) << "an observation older than the last";
  tracker.Update(0.7, {0, 0}, {});
  EXPECT_EQ(tracker.tracks().size(), 1u) << "unseen for 0.2 s: kept";
  tracker.Update(0.9, {0, 0}, {});
  EXPECT_TRUE(tracker.tracks().empty()) << "unseen for 0.4 s: dropped";
}

TEST(ObstacleTrackerTest, BadOptionsAreNamed) {
  ObstacleTrackerOptions o;
  o.cluster_tolerance = 0.0;
  o.min_points = 0;
  o.max_missed_time = -1.0;
  try {
    ObstacleTracker tracker(o);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("obstacle_tracker"), std::string::npos) << what;
    EXPECT_NE(what.find("cluster_tolerance"), std::string::npos) << what;
    EXPECT_NE(what.find("min_points"), std::string::npos) << what;
    EXPECT_NE(what.find("max_missed_time"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
