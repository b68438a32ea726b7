// Several robots in one simulation: each sees the others in its laser and depth camera where they
// are, robots stop each other (the one that drives into another is held; both report the contact
// with the other's name), a head-on meeting leaves both standing apart, and bad line-ups (two
// robots with one name, several unnamed, bodies overlapping at spawn) are refused naming them.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/simulator.h"
#include "sim_test_fixtures.h"
#include "urdf_fixtures.h"

namespace minibot3d_sim {
namespace {

RobotEntry Robot(const std::string& name, double x, double y, double yaw) {
  RobotEntry e;
  e.model = ParseRobotModel(testing::SensingDiffDriveUrdf());
  e.options.name = name;
  e.options.spawn = Pose2{x, y, yaw};
  return e;
}

SimulatorOptions Options(const std::string& physics) {
  SimulatorOptions o;
  o.physics = physics;
  o.cmd_timeout = 1e6;
  return o;
}

class MultiRobotTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MultiRobotTest, RobotsSeeEachOtherInTheLaserAndTheCamera) {
  // a at the origin facing +x; b 2 m ahead, turned sideways: a's middle beam meets b's side, 0.1 m
  // nearer than b's centre (the body is 0.2 m wide).
  std::vector<RobotEntry> robots;
  robots.push_back(Robot("a", 0.0, 0.0, 0.0));
  robots.push_back(Robot("b", 2.0, 0.0, M_PI / 2));
  Simulator sim(std::move(robots), testing::MakeRoom(4.0), Options(GetParam()));
  std::vector<float> ranges;
  sim.at(0).TakeScan(0, &ranges);
  ASSERT_EQ(ranges.size(), 181u);
  EXPECT_NEAR(ranges[90], 2.0 - 0.1, 1e-3);
  // Beams 30° off the axis pass b and end on the room's walls, 4 m / cos(30°) away.
  EXPECT_NEAR(ranges[60], 4.0 / std::cos(M_PI / 6), 1e-2);
  // The camera's middle pixel (at x = 0.16 m) sees b's side at 2 - 0.1 - 0.16 m.
  DepthFrame frame;
  sim.at(0).TakeFrame(0, &frame);
  EXPECT_NEAR(frame.depth[15 * 41 + 20], 2.0 - 0.1 - 0.16, 1e-3);
  // Where b goes, the beam follows: b 1 m farther.
  sim.at(1).SetPose(Pose2{3.0, 0.0, M_PI / 2});
  sim.at(0).TakeScan(0, &ranges);
  EXPECT_NEAR(ranges[90], 3.0 - 0.1, 1e-3);
}

TEST_P(MultiRobotTest, ARobotDrivingIntoAnotherIsHeldAndBothReportIt) {
  std::vector<RobotEntry> robots;
  robots.push_back(Robot("a", 0.0, 0.0, 0.0));
  robots.push_back(Robot("b", 1.0, 0.0, 0.0));
  Simulator sim(std::move(robots), testing::MakeRoom(4.0), Options(GetParam()));
  sim.at(0).Command(Twist2{0.3, 0.0, 0.0});
  for (int i = 0; i < 5000; ++i) sim.Step();
  // a's front (0.15 m ahead of its root) meets b's back (0.15 m behind b's root, at x = 0.85).
  EXPECT_NEAR(sim.at(0).true_pose().x, 0.7, 0.01);
  EXPECT_NEAR(sim.at(1).true_pose().x, 1.0, 1e-9);  // b is not pushed
  EXPECT_EQ(sim.at(0).collision_count(), 1u);
  EXPECT_EQ(sim.at(1).collision_count(), 1u);
  const std::vector<CollisionEvent> ea = sim.at(0).TakeCollisionEvents();
  const std::vector<CollisionEvent> eb = sim.at(1).TakeCollisionEvents();
  ASSERT_EQ(ea.size(), 1u);
  ASSERT_EQ(eb.size(), 1u);
  EXPECT_EQ(ea[0].shape_name, "robot b");
  EXPECT_EQ(eb[0].shape_name, "robot a");
  EXPECT_LT(ea[0].contact.normal.x(), -0.9);  // a is pushed back, towards -x
  // b's spot is taken: a cannot be teleported there.
  std::string what;
  EXPECT_TRUE(sim.at(0).PoseCollides(Pose2{1.05, 0.0, 0.0}, &what));
  EXPECT_EQ(what, "robot b");
  EXPECT_FALSE(sim.at(0).PoseCollides(Pose2{0.0, 1.0, 0.0}, &what));
}

TEST_P(MultiRobotTest, AHeadOnMeetingLeavesBothStandingApart) {
  std::vector<RobotEntry> robots;
  robots.push_back(Robot("a", -1.0, 0.0, 0.0));
  robots.push_back(Robot("b", 1.0, 0.0, M_PI));
  Simulator sim(std::move(robots), testing::MakeRoom(4.0), Options(GetParam()));
  sim.at(0).Command(Twist2{0.3, 0.0, 0.0});
  sim.at(1).Command(Twist2{0.3, 0.0, 0.0});
  for (int i = 0; i < 8000; ++i) {
    sim.Step();
    ASSERT_FALSE(BodyOverlap(sim.at(0).collider(), sim.at(0).true_pose(), sim.at(1).collider(),
                             sim.at(1).true_pose()))
        << "at " << sim.time() << " s";
  }
  // They meet in the middle, their fronts (0.15 m ahead) touching.
  EXPECT_NEAR(sim.at(0).true_pose().x, -0.15, 0.01);
  EXPECT_NEAR(sim.at(1).true_pose().x, 0.15, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Backends, MultiRobotTest, ::testing::Values("kinematic", "bullet"));

std::string Refusal(std::vector<RobotEntry> robots) {
  try {
    Simulator sim(std::move(robots), testing::MakeRoom(4.0), Options("kinematic"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(MultiRobotSetupTest, BadLineUpsAreRefusedNamingTheRobots) {
  std::vector<RobotEntry> twins;
  twins.push_back(Robot("r1", 0.0, 0.0, 0.0));
  twins.push_back(Robot("r1", 2.0, 0.0, 0.0));
  EXPECT_EQ(Refusal(std::move(twins)), "two robots are named 'r1'");
  std::vector<RobotEntry> unnamed;
  unnamed.push_back(Robot("r1", 0.0, 0.0, 0.0));
  unnamed.push_back(Robot("", 2.0, 0.0, 0.0));
  EXPECT_EQ(Refusal(std::move(unnamed)),
            "robot 2 of 2 has no name: several robots need one each");
  std::vector<RobotEntry> overlapping;
  overlapping.push_back(Robot("r1", 0.0, 0.0, 0.0));
  overlapping.push_back(Robot("r2", 0.25, 0.0, 0.0));
  EXPECT_EQ(Refusal(std::move(overlapping)), "robots 'r1' and 'r2' overlap where they spawn");
  // One robot alone needs no name; robots of different names may stand close.
  std::vector<RobotEntry> close;
  close.push_back(Robot("r1", 0.0, 0.0, 0.0));
  close.push_back(Robot("r2", 0.35, 0.0, 0.0));
  EXPECT_EQ(Refusal(std::move(close)), "accepted");
}

}  // namespace
}  // namespace minibot3d_sim
