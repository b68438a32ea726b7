// The odometry error against motion worked out by hand: the scale errors on a straight line and a
// turn on the spot, the heading drift's arc, the random errors' growth with the square root of
// the motion over many seeds, the same error for the same seed, bad options named; and the
// simulator reporting it for any drive.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/odometry_error.h"
#include "minibot3d_sim/simulator.h"
#include "sim_test_fixtures.h"
#include "urdf_fixtures.h"

namespace minibot3d_sim {
namespace {

// Drives the error model along a straight line of `metres` in 1 mm steps.
OdometryError Straight(const OdometryErrorOptions& o, double metres, unsigned seed = 1) {
  OdometryError e(o, seed);
  const int steps = static_cast<int>(std::lround(metres / 0.001));
  for (int i = 1; i <= steps; ++i) e.Update(Pose2{0.001 * i, 0.0, 0.0}, Twist2{0.5, 0.0, 0.0});
  return e;
}

// Turns on the spot through `radians` (a whole number of mrad) in 1 mrad steps; returns the
// reported rotation, unwrapped.
double TurnOnTheSpot(OdometryError* e, double radians) {
  const int steps = static_cast<int>(std::lround(radians / 0.001));
  double turned = 0.0;
  Pose2 last = e->pose();
  for (int i = 1; i <= steps; ++i) {
    e->Update(Pose2{0.0, 0.0, minibot3d_common::NormalizeAngle(0.001 * i)}, Twist2{});
    turned += minibot3d_common::AngleDiff(e->pose().yaw, last.yaw);
    last = e->pose();
  }
  return turned;
}

TEST(OdometryErrorTest, NoErrorIsTheDrivesOdometry) {
  OdometryErrorOptions none;
  EXPECT_FALSE(none.enabled());
  OdometryError e(none, 7);
  Pose2 p;
  for (int i = 0; i < 1000; ++i) {
    p = minibot3d_common::Compose(p, Pose2{0.002, 0.0005 * std::sin(i), 0.003 * std::cos(0.1 * i)});
    e.Update(p, Twist2{0.2, 0.0, 0.3});
  }
  EXPECT_NEAR(e.pose().x, p.x, 1e-12);
  EXPECT_NEAR(e.pose().y, p.y, 1e-12);
  EXPECT_NEAR(e.pose().yaw, p.yaw, 1e-12);
  EXPECT_DOUBLE_EQ(e.twist().wz, 0.3);
}

TEST(OdometryErrorTest, ScaleErrorsStretchDistanceAndRotation) {
  OdometryErrorOptions o;
  o.scale = 0.02;
  o.turn_scale = -0.02;
  // 10 m straight: 10.2 m reported, no rotation.
  OdometryError e = Straight(o, 10.0);
  EXPECT_NEAR(e.pose().x, 10.2, 1e-9);
  EXPECT_NEAR(e.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(e.twist().vx, 0.51, 1e-12);
  // About a full turn on the spot (6.283 rad): 0.98 of it reported.
  OdometryError t(o, 1);
  EXPECT_NEAR(TurnOnTheSpot(&t, 6.283), 0.98 * 6.283, 1e-9);
}

TEST(OdometryErrorTest, HeadingDriftBendsAStraightLineIntoAnArc) {
  OdometryErrorOptions o;
  o.heading_drift = 0.0175;  // 1 deg/m
  OdometryError e = Straight(o, 10.0);
  // An arc of curvature k = 0.0175 / m over 10 m: heading 0.175 rad, chord end at
  // (sin(0.175) / k, (1 - cos(0.175)) / k).
  const double k = 0.0175, th = k * 10.0;
  EXPECT_NEAR(e.pose().yaw, th, 1e-9);
  EXPECT_NEAR(e.pose().x, std::sin(th) / k, 1e-4);
  EXPECT_NEAR(e.pose().y, (1.0 - std::cos(th)) / k, 1e-4);
  EXPECT_NEAR(e.twist().wz, 0.0175 * 0.5, 1e-12);
  // Backing up curves the other way round (the same wheels, turning backwards).
  OdometryError back(o, 1);
  for (int i = 1; i <= 1000; ++i) back.Update(Pose2{-0.001 * i, 0.0, 0.0}, Twist2{});
  EXPECT_NEAR(back.pose().yaw, -0.0175, 1e-9);
}

// Sample standard deviation of x over seeds 1..n.
template <typename F>
double StdOverSeeds(int n, F f) {
  double sum = 0.0, sum2 = 0.0;
  for (int seed = 1; seed <= n; ++seed) {
    const double v = f(static_cast<unsigned>(seed));
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  return std::sqrt((sum2 - n * mean * mean) / (n - 1));
}

TEST(OdometryErrorTest, RandomErrorsGrowWithTheSquareRootOfTheMotion) {
  // 400 seeds: a sample standard deviation within ~3.5 % (1 sigma) of the true one; 12 % is
  // more than 3 sigma.
  OdometryErrorOptions o;
  o.distance_noise = 0.05;
  o.heading_noise = 0.02;
  const int n = 400;
  // After 4 m: distance std 0.05 x 2 = 0.1 m; heading std 0.02 x 2 = 0.04 rad.
  std::vector<OdometryError> runs;
  for (int seed = 1; seed <= n; ++seed) {
    OdometryError e(o, static_cast<unsigned>(seed));
    for (int i = 1; i <= 400; ++i) e.Update(Pose2{0.01 * i, 0.0, 0.0}, Twist2{});
    runs.push_back(e);
  }
  // The distance along the path: the heading error turns the path, so take its length as the
  // distance from the origin (the bend shortens it by ~1e-3 m only).
  const double d_std = StdOverSeeds(n, [&](unsigned s) {
    return std::hypot(runs[s - 1].pose().x, runs[s - 1].pose().y);
  });
  const double h_std = StdOverSeeds(n, [&](unsigned s) { return runs[s - 1].pose().yaw; });
  EXPECT_NEAR(d_std, 0.1, 0.012);
  EXPECT_NEAR(h_std, 0.04, 0.0048);
  // About a full turn on the spot (6.283 rad) with turn_noise 0.1: std 0.1 x sqrt(6.283).
  OdometryErrorOptions t;
  t.turn_noise = 0.1;
  const double t_std = StdOverSeeds(n, [&](unsigned s) {
    OdometryError e(t, s);
    return TurnOnTheSpot(&e, 6.283) - 6.283;
  });
  EXPECT_NEAR(t_std, 0.1 * std::sqrt(6.283), 0.12 * 0.1 * std::sqrt(6.283));
}

TEST(OdometryErrorTest, TheSameSeedGivesTheSameError) {
  OdometryErrorOptions o;
  o.distance_noise = 0.05;
  o.turn_noise = 0.05;
  o.heading_noise = 0.02;
  const Pose2 a = Straight(o, 2.0, 5).pose(), b = Straight(o, 2.0, 5).pose();
  const Pose2 c = Straight(o, 2.0, 6).pose();
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.yaw, b.yaw);
  EXPECT_NE(a.x, c.x);
}

TEST(OdometryErrorTest, BadOptionsAreNamed) {
  const auto message = [](OdometryErrorOptions o) {
    try {
      ValidateOdometryError(o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  OdometryErrorOptions o;
  o.scale = -1.0;
  EXPECT_NE(message(o).find("odom_error_scale=-1 must be > -1"), std::string::npos) << message(o);
  o = OdometryErrorOptions();
  o.turn_noise = -0.1;
  EXPECT_NE(message(o).find("odom_error_turn_noise"), std::string::npos) << message(o);
  o = OdometryErrorOptions();
  o.heading_drift = std::nan("");
  EXPECT_NE(message(o).find("odom_error_heading_drift"), std::string::npos) << message(o);
}

// Any drive's odometry carries it: the diff-drive plugin's world odometry (the true pose without
// error) reports 2 % too far, and a reset zeroes it.
TEST(OdometryErrorTest, TheSimulatorReportsItForAnyDrive) {
  SimulatorOptions o;
  o.physics = "kinematic";
  o.cmd_timeout = 1e6;
  o.odom_error.scale = 0.02;
  Simulator sim(ParseRobotModel(testing::DiffDriveUrdf("<updateRate>0</updateRate>")),
                testing::MakeRoom(5.0), o);
  sim.Command(Twist2{0.3, 0.0, 0.0});
  for (int i = 0; i < 2000; ++i) sim.Step();
  EXPECT_NEAR(sim.true_pose().x, 0.6, 1e-9);
  EXPECT_NEAR(sim.odom_pose().x, 0.612, 1e-9);
  EXPECT_NEAR(sim.odom_twist().vx, 0.306, 1e-9);
  sim.Reset();
  EXPECT_EQ(sim.odom_pose().x, 0.0);
  o.odom_error.scale = -1.5;
  EXPECT_THROW(Simulator(ParseRobotModel(testing::DiffDriveUrdf("")), testing::MakeRoom(5.0), o),
               std::invalid_argument);
}

}  // namespace
}  // namespace minibot3d_sim
