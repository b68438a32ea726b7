#include "minibot3d_sim/lidar.h"

#include <cmath>

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

}  // namespace
}  // namespace minibot3d_sim
