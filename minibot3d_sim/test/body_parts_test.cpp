// Every link's collision shapes decide contact, at their own heights, in both physics backends: a
// post between a gantry's two pods lets it pass (one hull round the robot would not), a shelf at
// the height of a forward arm stops the arm while the body drives under it (a cross-section at the
// body's height would not see the shelf), a plank lower than the floor clearance passes under, and
// a step across the way stops the pods.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/simulator.h"
#include "sim_test_fixtures.h"
#include "urdf_fixtures.h"

namespace minibot3d_sim {
namespace {

using testing::Inertial;

std::string BoxLink(const std::string& name, double x, double y, double z, double sx, double sy,
                    double sz) {
  const auto n = [](double v) { return std::to_string(v); };
  return "<link name='" + name + "'><collision><origin xyz='" + n(x) + " " + n(y) + " " + n(z) +
         "'/><geometry><box size='" + n(sx) + " " + n(sy) + " " + n(sz) +
         "'/></geometry></collision>" + Inertial(1.0) + "</link><joint name='" + name +
         "_joint' type='fixed'><parent link='base_link'/><child link='" + name + "'/></joint>";
}

// A holonomic gantry: two pods (0.4 × 0.1 m, 1–11 cm above the floor, inner faces at y = ±0.15)
// joined by a plate 30–32 cm up, and an arm reaching 0.3 m ahead of the root 35–45 cm up.
std::string GantryUrdf() {
  return "<?xml version='1.0'?><robot name='gantry'><link name='base_footprint'/>"
         "<link name='base_link'>" + Inertial(1.0) + "</link>"
         "<joint name='base_joint' type='fixed'><parent link='base_footprint'/><child "
         "link='base_link'/></joint>" +
         BoxLink("left_pod", 0, 0.2, 0.06, 0.4, 0.1, 0.1) +
         BoxLink("right_pod", 0, -0.2, 0.06, 0.4, 0.1, 0.1) +
         BoxLink("plate", 0, 0, 0.31, 0.4, 0.5, 0.02) +
         BoxLink("arm", 0.275, 0, 0.4, 0.05, 0.05, 0.1) +
         "<gazebo><plugin name='move' filename='libgazebo_ros_planar_move.so'>"
         "<commandTopic>cmd_vel</commandTopic><odometryTopic>odom</odometryTopic>"
         "<odometryFrame>odom</odometryFrame><robotBaseFrame>base_footprint</robotBaseFrame>"
         "</plugin></gazebo></robot>";
}

// Drives +x at 0.2 m/s for 5 s from the origin in a room with `obstacle`; the final x.
double DriveInto(const std::string& physics, const Shape& obstacle, long* collisions) {
  World world = testing::MakeRoom(3.0);
  world.shapes.push_back(obstacle);
  SimulatorOptions o;
  o.physics = physics;
  o.cmd_timeout = 1e6;
  Simulator sim(ParseRobotModel(GantryUrdf()), std::move(world), o);
  sim.Command(Twist2{0.2, 0.0, 0.0});
  for (int i = 0; i < 5000; ++i) sim.Step();
  *collisions = static_cast<long>(sim.collision_count());
  return sim.true_pose().x;
}

Shape Floating(const std::string& name, double x, double y, double z, double sx, double sy,
               double sz) {
  Shape s = testing::Box(name, x, y, sx, sy, sz);
  s.pose.translation().z() = z;
  return s;
}

class BodyPartsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BodyPartsTest, APostBetweenThePodsPassesUnderThePlate) {
  Shape post;
  post.type = ShapeType::kCylinder;
  post.name = "post";
  post.size = Eigen::Vector3d(0.03, 0.03, 0.2);
  post.pose.translation() = Eigen::Vector3d(0.6, 0.0, 0.1);
  long collisions = 0;
  EXPECT_NEAR(DriveInto(GetParam(), post, &collisions), 1.0, 0.01);
  EXPECT_EQ(collisions, 0);
}

TEST_P(BodyPartsTest, AShelfAtTheArmsHeightStopsTheArm) {
  // 38–42 cm up, its near face at x = 0.8: the arm's front (0.3 m ahead of the root) meets it
  // with the root at x = 0.5; pods and plate would pass under.
  long collisions = 0;
  EXPECT_NEAR(DriveInto(GetParam(), Floating("shelf", 0.9, 0.0, 0.4, 0.2, 1.0, 0.04), &collisions),
              0.5, 0.01);
  EXPECT_GE(collisions, 1);
}

TEST_P(BodyPartsTest, APlankBelowTheFloorClearancePassesAndABoxStopsAPod) {
  long collisions = 0;
  // 4 mm thick: under the 5 mm a robot without wheels clears.
  EXPECT_NEAR(DriveInto(GetParam(), testing::Box("plank", 0.8, 0.2, 0.2, 0.2, 0.004), &collisions),
              1.0, 0.01);
  EXPECT_EQ(collisions, 0);
  // A 5 cm step across the way, its near face at x = 0.7: the pods (0.2 m ahead of the root) meet
  // it with the root at x = 0.5.
  EXPECT_NEAR(DriveInto(GetParam(), testing::Box("step", 0.8, 0.0, 0.2, 1.0, 0.05), &collisions),
              0.5, 0.01);
  EXPECT_GE(collisions, 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, BodyPartsTest, ::testing::Values("kinematic", "bullet"));

TEST(BodyPartsTest, EveryCollisionShapeIsAPartAboveTheFloorClearance) {
  const RobotModel robot = ParseRobotModel(GantryUrdf());
  const std::vector<BodyPart> parts = BodyParts(robot);
  ASSERT_EQ(parts.size(), 4u);
  EXPECT_DOUBLE_EQ(FloorClearance(robot), 0.005);
  for (const BodyPart& p : parts) {
    if (p.link == "left_pod") {
      EXPECT_NEAR(p.z_min, 0.01, 1e-9);
      EXPECT_NEAR(p.z_max, 0.11, 1e-9);
    }
    if (p.link == "arm") {
      EXPECT_NEAR(p.z_min, 0.35, 1e-9);
    }
  }
  // A wheel's band starts at a quarter of its radius (the diff-drive fixture's 0.033 m wheels).
  const RobotModel diff = ParseRobotModel(testing::DiffDriveUrdf());
  EXPECT_NEAR(FloorClearance(diff), 0.25 * 0.033, 1e-12);
  for (const BodyPart& p : BodyParts(diff)) EXPECT_GE(p.z_min, 0.25 * 0.033 - 1e-12);
}

}  // namespace
}  // namespace minibot3d_sim
