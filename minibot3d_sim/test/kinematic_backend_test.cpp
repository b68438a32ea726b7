// Tests of the kinematic backend: exact no-slip motion and wall blocking.
#include "../src/kinematic_backend.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/body_collider.h"
#include "minibot3d_sim/drive.h"
#include "minibot3d_sim/physics_backend.h"
#include "sim_test_fixtures.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {
namespace {

constexpr double kRadius = 0.04;
constexpr double kSeparation = 0.2;
constexpr double kBodyHeight = 0.06;  // centre of the body box above the floor

RobotModel MakeRobot() { return testing::MakePhysicsRobot(); }
World MakeWorld(double wall_x) { return testing::MakeWallWorld(wall_x); }

void Drive(PhysicsBackend* b, double v, double w, double dt, int steps,
         std::vector<Contact>* contacts = nullptr) {
  b->SetTargets(testing::SkidTargets(v, w));
  for (int i = 0; i < steps; ++i) b->Step(dt, contacts);
}

// The backend moves at the no-slip twist the drive asks for and turns the wheels as told.
TEST(KinematicBackendTest, MovesAtTheTargetsBodyTwist) {
  KinematicBackend b(MakeRobot(), MakeWorld(50.0));
  for (double v : {-0.4, 0.0, 0.25}) {
    for (double w : {-1.5, 0.0, 0.7}) {
      const DriveTargets targets = testing::SkidTargets(v, w);
      b.SetPose(Pose2{});
      b.SetTargets(targets);
      b.Step(0.001, nullptr);
      EXPECT_NEAR(b.twist().vx, v, 1e-12);
      EXPECT_NEAR(b.twist().vy, 0.0, 1e-12);
      EXPECT_NEAR(b.twist().wz, (v == 0.0 && w == 0.0) ? 0.0 : w, 1e-12);
      for (int i = 0; i < 4; ++i) {
        EXPECT_DOUBLE_EQ(b.wheel_velocities()[i], targets.wheel_speeds[i]);
      }
    }
  }
}

// A holonomic base moves sideways exactly: 1 s at 0.3 m/s along y from a heading of 90 deg.
TEST(KinematicBackendTest, HolonomicBodyVelocity) {
  KinematicBackend b(MakeRobot(), MakeWorld(50.0));
  b.SetPose(Pose2{0.0, 0.0, M_PI / 2});
  DriveTargets targets;
  targets.wheel_speeds.assign(4, 0.0);
  targets.body_velocity = true;
  targets.body_twist = Twist2{0.0, 0.3, 0.0};
  b.SetTargets(targets);
  for (int i = 0; i < 1000; ++i) b.Step(0.001, nullptr);
  EXPECT_NEAR(b.pose().x, -0.3, 1e-9);
  EXPECT_NEAR(b.pose().y, 0.0, 1e-9);
  EXPECT_NEAR(b.pose().yaw, M_PI / 2, 1e-12);
}

TEST(KinematicBackendTest, DrivesStraightOneMetre) {
  KinematicBackend b(MakeRobot(), MakeWorld(50.0));
  const Pose2 start{1.0, 2.0, 0.3};
  b.SetPose(start);
  Drive(&b, 0.5, 0.0, 0.001, 2000);  // 0.5 m/s for 2 s
  EXPECT_NEAR(b.pose().x, 1.0 + std::cos(0.3), 1e-9);
  EXPECT_NEAR(b.pose().y, 2.0 + std::sin(0.3), 1e-9);
  EXPECT_NEAR(b.pose().yaw, 0.3, 1e-12);
  // Every wheel turned 1 m / r.
  for (double a : b.wheel_positions()) EXPECT_NEAR(a, 1.0 / kRadius, 1e-9);
}

TEST(KinematicBackendTest, DrivesArcExactly) {
  KinematicBackend b(MakeRobot(), MakeWorld(50.0));
  const double radius = 0.5, w = 0.4, duration = 5.0;
  b.SetPose(Pose2{});
  Drive(&b, radius * w, w, 0.001, 5000);
  EXPECT_NEAR(b.pose().x, radius * std::sin(w * duration), 1e-6);
  EXPECT_NEAR(b.pose().y, radius * (1 - std::cos(w * duration)), 1e-6);
  EXPECT_NEAR(b.pose().yaw, w * duration, 1e-9);
  // A coarse step integrates the same arc exactly too (constant twist per step).
  b.SetPose(Pose2{});
  Drive(&b, radius * w, w, 0.05, 100);
  EXPECT_NEAR(b.pose().x, radius * std::sin(w * duration), 1e-6);
  EXPECT_NEAR(b.pose().y, radius * (1 - std::cos(w * duration)), 1e-6);
}

TEST(KinematicBackendTest, TurnsInPlace) {
  KinematicBackend b(MakeRobot(), MakeWorld(50.0));
  b.SetPose(Pose2{0.5, -0.5, 0.0});
  Drive(&b, 0.0, -1.0, 0.001, 2500);  // -2.5 rad
  EXPECT_NEAR(b.pose().x, 0.5, 1e-9);
  EXPECT_NEAR(b.pose().y, -0.5, 1e-9);
  EXPECT_NEAR(b.pose().yaw, -2.5, 1e-9);
  EXPECT_NEAR(b.twist().wz, -1.0, 1e-12);
  // Left wheels forward, right wheels backward.
  EXPECT_GT(b.wheel_positions()[0], 0.0);  // left front
  EXPECT_LT(b.wheel_positions()[1], 0.0);  // right front
}

TEST(KinematicBackendTest, StopsAtWallWithContactAndNoPenetration) {
  const double wall_x = 1.0;
  const World world = MakeWorld(wall_x);
  const RobotModel robot = MakeRobot();
  KinematicBackend b(robot, world);
  b.SetPose(Pose2{0.0, 0.0, 0.0});
  std::vector<Contact> contacts;
  b.SetTargets(testing::SkidTargets(1.0, 0.0));
  int first_contact_step = -1;
  for (int i = 0; i < 2000; ++i) {
    contacts.clear();
    b.Step(0.001, &contacts);
    if (!contacts.empty() && first_contact_step < 0) first_contact_step = i;
  }
  ASSERT_GE(first_contact_step, 0) << "no contact reported";
  // The nose (x + 0.12) stopped within one step (1 mm) of the wall face, never past it.
  const double nose = b.pose().x + 0.12;
  EXPECT_LE(nose, wall_x);
  EXPECT_GT(nose, wall_x - 0.0015);
  EXPECT_NEAR(b.pose().y, 0.0, 1e-12);
  ASSERT_FALSE(contacts.empty());
  EXPECT_EQ(contacts[0].shape, 1);
  EXPECT_NEAR(contacts[0].point.x(), wall_x, 1e-9);
  EXPECT_NEAR(contacts[0].normal.x(), -1.0, 1e-9);
  EXPECT_DOUBLE_EQ(contacts[0].depth, 0.0);
  EXPECT_EQ(b.twist().vx, 0.0);
  for (double w : b.wheel_velocities()) EXPECT_EQ(w, 0.0);
  // The footprint does not overlap the wall (checked against an independent slice).
  const WorldSlice slice(world, kBodyHeight);
  std::vector<Eigen::Vector2d> poly;
  for (const auto& v : robot.footprint) poly.push_back(TransformPoint(b.pose(), v));
  EXPECT_FALSE(slice.PolygonCollides(poly));

  // Backing off is always possible, and the contact goes away.
  contacts.clear();
  Drive(&b, -0.5, 0.0, 0.001, 200, &contacts);
  EXPECT_TRUE(contacts.empty());
  EXPECT_NEAR(b.pose().x + 0.12, nose - 0.1, 1e-9);
}

TEST(KinematicBackendTest, TurningNextToWallIsBlockedWhenTheCornerWouldHit) {
  // The robot stands side-on 1 mm from the wall; turning in place swings a corner into it.
  const World world = MakeWorld(1.0);
  KinematicBackend b(MakeRobot(), world);
  b.SetPose(Pose2{1.0 - 0.116, 0.0, M_PI / 2});  // side (y extent 0.115) 1 mm from the wall
  std::vector<Contact> contacts;
  Drive(&b, 0.0, 1.0, 0.001, 100, &contacts);
  EXPECT_FALSE(contacts.empty());
  // The corner (0.12, 0.115) reaches the wall when 0.115 cos(a) + 0.12 sin(a) = 0.116.
  double lo = 0.0, hi = 0.5;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.115 * std::cos(mid) + 0.12 * std::sin(mid) < 0.116 ? lo : hi) = mid;
  }
  const double turned = b.pose().yaw - M_PI / 2;
  EXPECT_LE(turned, lo);
  EXPECT_GT(turned, lo - 0.001);  // within one 1 ms step at 1 rad/s
  EXPECT_EQ(b.twist().wz, 0.0);
  // Driving along the wall (forward = +y, heading slightly away from it) is fine.
  contacts.clear();
  Drive(&b, 0.3, 0.0, 0.001, 1000, &contacts);
  EXPECT_TRUE(contacts.empty());
  EXPECT_NEAR(b.pose().y, 0.3 * std::cos(turned), 1e-9);
}

TEST(KinematicBackendTest, DistanceCacheSkipsChecksInOpenSpaceButNotNearWalls) {
  KinematicBackend b(MakeRobot(), MakeWorld(3.0));
  b.SetPose(Pose2{});
  const long before = b.collision_checks();
  Drive(&b, 0.5, 0.0, 0.001, 1000);  // 0.5 m, far from everything (> 2 m to the wall)
  EXPECT_LT(b.collision_checks() - before, 5);
  // Closer to the wall the polygon test runs often, and still stops the robot in time.
  std::vector<Contact> contacts;
  Drive(&b, 1.0, 0.0, 0.001, 3000, &contacts);
  EXPECT_FALSE(contacts.empty());
  EXPECT_LE(b.pose().x + 0.12, 3.0);
  EXPECT_GT(b.pose().x + 0.12, 3.0 - 0.0015);
}

// A body grown by a margin is clear exactly when nothing is within the margin (up to the corners,
// which grow a little more): the fixture's side is 2 cm from the wall.
TEST(KinematicBackendTest, BodyColliderClearHonoursTheMargin) {
  const World world = MakeWorld(1.0);
  SliceCache cache(&world);
  const BodyCollider body(MakeRobot(), world, &cache);
  const Pose2 beside{1.0 - 0.135, 0.0, M_PI / 2};
  ASSERT_FALSE(body.Collides(beside, nullptr));
  EXPECT_TRUE(body.Clear(beside, 0.019));
  EXPECT_FALSE(body.Clear(beside, 0.021));
  // A margin never hides a contact: at the wall no margin is clear.
  EXPECT_FALSE(body.Clear(Pose2{1.0 - 0.115, 0.0, M_PI / 2}, 1e-6));
}

// Beside a wall the body margin keeps most steps untested; pushing against the wall repeats the
// refused step without testing it again.
TEST(KinematicBackendTest, BodyMarginCacheBesideAWallAndRefusedStepsUntested) {
  const World world = MakeWorld(1.0);
  KinematicBackend b(MakeRobot(), world);
  b.SetPose(Pose2{1.0 - 0.135, 0.0, M_PI / 2});  // side 2 cm from the wall, facing along it
  std::vector<Contact> contacts;
  long before = b.collision_checks();
  Drive(&b, 0.3, 0.0, 0.001, 1000, &contacts);  // 0.3 m along the wall
  EXPECT_TRUE(contacts.empty());
  EXPECT_NEAR(b.pose().y, 0.3, 1e-9);
  EXPECT_LT(b.collision_checks() - before, 50);
  // Turn to face the wall (clear of it) and push into it.
  b.SetPose(Pose2{0.5, 0.0, 0.0});
  Drive(&b, 1.0, 0.0, 0.001, 600, &contacts);
  ASSERT_FALSE(contacts.empty());
  const Pose2 stopped = b.pose();
  before = b.collision_checks();
  contacts.clear();
  Drive(&b, 1.0, 0.0, 0.001, 500, &contacts);
  EXPECT_EQ(contacts.size(), 500u);  // every refused step reports its contact
  EXPECT_EQ(b.collision_checks() - before, 0);
  EXPECT_EQ(b.pose().x, stopped.x);
}

// Whatever the caches skip, the backend goes exactly where a robot tested at every step goes:
// random arcs among posts and walls, blocked steps included.
TEST(KinematicBackendTest, CachesAgreeWithTestingEveryStep) {
  World world = testing::MakeRoom(1.5);
  world.shapes.push_back(testing::Box("post_a", 0.4, 0.3, 0.2, 0.2));
  world.shapes.push_back(testing::Box("post_b", -0.5, -0.6, 0.3, 0.1));
  const RobotModel robot = MakeRobot();
  KinematicBackend b(robot, world);
  SliceCache cache(&world);
  const BodyCollider reference(robot, world, &cache);
  Pose2 expected{-0.8, 0.6, 0.3};
  b.SetPose(expected);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> v(-0.3, 0.6), w(-1.5, 1.5);
  long steps = 0, blocked = 0;
  for (int leg = 0; leg < 100; ++leg) {
    // Mostly arcs, every third leg straight on: into the walls head-on as well as glancing.
    const DriveTargets targets = testing::SkidTargets(v(rng), leg % 3 == 0 ? 0.0 : w(rng));
    b.SetTargets(targets);
    for (int i = 0; i < 1000; ++i, ++steps) {
      b.Step(0.001, nullptr);
      const Pose2 end = IntegrateTwist(expected, targets.body_twist, 0.001);
      if (reference.Collides(end, nullptr)) ++blocked;
      else expected = end;
      ASSERT_EQ(b.pose().x, expected.x) << "step " << steps;
      ASSERT_EQ(b.pose().y, expected.y) << "step " << steps;
      ASSERT_EQ(b.pose().yaw, expected.yaw) << "step " << steps;
    }
  }
  EXPECT_GT(blocked, 100);                       // it met the walls and posts
  EXPECT_LT(b.collision_checks(), steps / 4);    // and mostly skipped the polygon test
}

TEST(KinematicBackendTest, RobotPlacedInsideObstacleCanDriveOut) {
  const World world = MakeWorld(1.0);
  KinematicBackend b(MakeRobot(), world);
  b.SetPose(Pose2{1.0, 0.0, M_PI});  // half inside the wall, facing away from it
  std::vector<Contact> contacts;
  Drive(&b, 0.5, 0.0, 0.001, 1000, &contacts);
  EXPECT_FALSE(contacts.empty());  // while still overlapping
  EXPECT_NEAR(b.pose().x, 0.5, 1e-9);
  contacts.clear();
  Drive(&b, 0.5, 0.0, 0.001, 10, &contacts);
  EXPECT_TRUE(contacts.empty());
}

TEST(KinematicBackendTest, FactoryMakesEveryBackendAndNamesUnknownOnes) {
  const RobotModel robot = MakeRobot();
  const World world = MakeWorld(50.0);
  for (const std::string name : {"kinematic", "bullet"}) {
    EXPECT_EQ(MakePhysicsBackend(name, robot, world)->name(), name);
  }
  try {
    MakePhysicsBackend("ode", robot, world);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ode"), std::string::npos) << what;
    EXPECT_NE(what.find("bullet"), std::string::npos) << what;
    EXPECT_NE(what.find("kinematic"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace minibot3d_sim
