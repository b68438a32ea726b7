#include "minibot3d_sim/lidar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sim_test_fixtures.h"

namespace minibot3d_sim {
namespace {

using testing::MakeRobot;

// A single box whose near face is at x = 1.5 in the world, and nothing else.
World OneBox() {
  World w;
  w.shapes.push_back(testing::Box("box", 2.0, 0.0, 1.0, 4.0));
  return w;
}

TEST(LidarTest, RangesToABoxAtAKnownDistance) {
  const World world = OneBox();
  LaserSpec spec = MakeRobot().lasers[0];
  spec.pose_in_root = Eigen::Isometry3d::Identity();
  spec.pose_in_root.translation() = Eigen::Vector3d(0.0, 0.0, 0.2);
  spec.samples = 5;
  spec.min_angle = -M_PI / 2;
  spec.max_angle = M_PI / 2;  // beams at -90, -45, 0, 45, 90 degrees
  const WorldSlice slice(world, 0.2);
  Lidar lidar(spec, &slice, 1);
  EXPECT_NEAR(lidar.angle_increment(), M_PI / 4, 1e-12);
  std::vector<float> r;
  lidar.Scan(Pose2{0.5, 0.0, 0.0}, &r);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_NEAR(r[2], 1.0, 1e-6);                 // straight ahead: 1.5 - 0.5
  EXPECT_NEAR(r[1], 1.0 * std::sqrt(2.0), 1e-5);  // 45 degrees right
  EXPECT_NEAR(r[3], 1.0 * std::sqrt(2.0), 1e-5);
  EXPECT_TRUE(std::isinf(r[0]) && r[0] > 0);    // nothing to the sides: +inf (REP 117)
  EXPECT_TRUE(std::isinf(r[4]) && r[4] > 0);
}

TEST(LidarTest, SensorMountedBackwardsSeesBehind) {
  const World world = OneBox();
  LaserSpec spec = MakeRobot().lasers[0];
  spec.samples = 1;
  spec.min_angle = spec.max_angle = 0.0;
  spec.pose_in_root = Eigen::Isometry3d::Identity();
  spec.pose_in_root.translation() = Eigen::Vector3d(0.02, 0.0, 0.2);
  spec.pose_in_root.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const WorldSlice slice(world, 0.2);
  Lidar lidar(spec, &slice, 1);
  std::vector<float> r;
  lidar.Scan(Pose2{0.5, 0.0, M_PI}, &r);  // robot faces -x, sensor faces +x
  // The sensor is 0.02 m ahead of the root along the robot's x (which points to -x): x = 0.48.
  EXPECT_NEAR(r[0], 1.5 - 0.48, 1e-6);
}

TEST(LidarTest, TooCloseIsMinusInfAndNoiseHasItsSigma) {
  const World world = OneBox();
  LaserSpec spec = MakeRobot().lasers[0];
  spec.pose_in_root = Eigen::Isometry3d::Identity();
  spec.pose_in_root.translation().z() = 0.2;
  spec.samples = 1;
  spec.min_angle = spec.max_angle = 0.0;
  spec.min_range = 0.15;
  const WorldSlice slice(world, 0.2);
  {
    Lidar lidar(spec, &slice, 1);
    std::vector<float> r;
    lidar.Scan(Pose2{1.4, 0.0, 0.0}, &r);
    EXPECT_TRUE(std::isinf(r[0]) && r[0] < 0) << r[0];
  }
  spec.noise_stddev = 0.01;
  Lidar lidar(spec, &slice, 7);
  std::vector<float> r;
  double sum = 0, sum2 = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    lidar.Scan(Pose2{0.0, 0.0, 0.0}, &r);
    sum += r[0] - 1.5;
    sum2 += (r[0] - 1.5) * (r[0] - 1.5);
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.001);
  EXPECT_NEAR(sd, 0.01, 0.001);
}

TEST(LidarTest, ResolutionQuantisesAndMaxRangeIsInf) {
  const World world = OneBox();
  LaserSpec spec = MakeRobot().lasers[0];
  spec.pose_in_root = Eigen::Isometry3d::Identity();
  spec.pose_in_root.translation().z() = 0.2;
  spec.samples = 1;
  spec.min_angle = spec.max_angle = 0.0;
  spec.resolution = 0.05;
  spec.max_range = 1.0;
  const WorldSlice slice(world, 0.2);
  Lidar lidar(spec, &slice, 1);
  std::vector<float> r;
  lidar.Scan(Pose2{0.7234, 0.0, 0.0}, &r);  // true range 0.7766
  EXPECT_NEAR(r[0], 0.80, 1e-6);
  lidar.Scan(Pose2{0.0, 0.0, 0.0}, &r);     // true range 1.5 > max_range
  EXPECT_TRUE(std::isinf(r[0]) && r[0] > 0);
}

// Moving bodies are culled by their angular extent, by the world's returns and by each other; the
// ranges are those of every beam tested against every body, fans wrapping round at +-pi included.
TEST(LidarTest, BodiesGiveTheRangesOfABruteForceCast) {
  World world = OneBox();
  world.shapes.push_back(testing::Box("wall", -1.0, 2.5, 6.0, 0.2));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-4.0, 4.0), yaw(-M_PI, M_PI), size(0.03, 0.4);
  // Convex outlines: squares, hexagons and 32-gons of random sizes, at random poses.
  std::vector<std::vector<Eigen::Vector2d>> outlines;
  for (int sides : {4, 6, 32}) {
    for (int k = 0; k < 10; ++k) {
      const double r = size(rng);
      outlines.emplace_back();
      for (int i = 0; i < sides; ++i) {
        const double a = 2.0 * M_PI * i / sides;
        outlines.back().emplace_back(r * std::cos(a), r * std::sin(a));
      }
    }
  }
  for (const auto& fan : {std::make_pair(-M_PI, M_PI), std::make_pair(-2.0, 2.5)}) {
    LaserSpec spec = MakeRobot().lasers[0];
    spec.pose_in_root = Eigen::Isometry3d::Identity();
    spec.pose_in_root.translation() = Eigen::Vector3d(0.0, 0.0, 0.2);
    spec.samples = 360;
    spec.min_angle = fan.first;
    spec.max_angle = fan.second;
    spec.max_range = 6.0;
    spec.min_range = 0.0;
    spec.noise_stddev = 0.0;
    spec.noise_mean = 0.0;
    spec.resolution = 0.0;
    const WorldSlice slice(world, 0.2);
    Lidar lidar(spec, &slice, 1);
    for (int trial = 0; trial < 20; ++trial) {
      const Pose2 robot{pos(rng) * 0.3, pos(rng) * 0.3, yaw(rng)};
      std::vector<BodyOutline> bodies;
      for (const auto& outline : outlines) {
        BodyOutline b;
        b.outline = &outline;
        b.pose = Pose2{pos(rng), pos(rng), yaw(rng)};
        b.centre = Eigen::Vector2d(b.pose.x, b.pose.y);
        b.radius = outline[0].norm();
        bodies.push_back(b);
      }
      std::vector<float> walls, seen;
      lidar.Scan(robot, &walls);
      lidar.Scan(robot, &seen, &bodies);
      int hidden_by_bodies = 0;
      for (int i = 0; i < spec.samples; ++i) {
        const double a = robot.yaw + spec.min_angle + i * lidar.angle_increment();
        const Eigen::Vector2d o(robot.x, robot.y), d(std::cos(a), std::sin(a));
        double best = std::isfinite(walls[i]) ? walls[i] : std::numeric_limits<double>::infinity();
        for (const BodyOutline& b : bodies) {
          const auto& poly = *b.outline;
          for (size_t k = 0; k < poly.size(); ++k) {
            const Eigen::Vector2d p = TransformPoint(b.pose, poly[k]);
            const Eigen::Vector2d e = TransformPoint(b.pose, poly[(k + 1) % poly.size()]) - p;
            const double den = d.x() * e.y() - d.y() * e.x();
            if (std::abs(den) < 1e-15) continue;
            const Eigen::Vector2d w = p - o;
            const double t = (w.x() * e.y() - w.y() * e.x()) / den;
            const double u = (w.x() * d.y() - w.y() * d.x()) / den;
            if (t >= 0.0 && u >= 0.0 && u <= 1.0 && t <= spec.max_range) best = std::min(best, t);
          }
        }
        if (best < walls[i]) ++hidden_by_bodies;
        if (std::isinf(best)) {
          EXPECT_TRUE(std::isinf(seen[i])) << "beam " << i << " trial " << trial;
        } else {
          EXPECT_NEAR(seen[i], best, 1e-5) << "beam " << i << " trial " << trial;
        }
      }
      EXPECT_GT(hidden_by_bodies, 0) << "trial " << trial << ": no body in view";
    }
  }
}

}  // namespace
}  // namespace minibot3d_sim
