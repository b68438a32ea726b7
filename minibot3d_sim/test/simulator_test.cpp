// The simulator core: clock, command timeout, odometry, scan schedule, collision events, reset.
#include "minibot3d_sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/world_loader.h"
#include "sim_test_fixtures.h"

namespace minibot3d_sim {
namespace {

using testing::MakeRobot;
using testing::MakeRoom;

SimulatorOptions Options(const std::string& physics) {
  SimulatorOptions o;
  o.physics = physics;
  o.physics_step = 0.001;
  return o;
}

void Drive(Simulator* sim, double seconds, double v, double w) {
  const int n = static_cast<int>(std::lround(seconds / sim->physics_step()));
  for (int i = 0; i < n; ++i) {
    // cmd_vel arrives at 10 Hz, as from a controller.
    if (i % 100 == 0) sim->SetCommand(v, w);
    sim->Step();
  }
}

TEST(SimulatorTest, ClockIsStepsTimesStep) {
  Simulator sim(MakeRobot(), MakeRoom(), Options("kinematic"));
  for (int i = 0; i < 12345; ++i) sim.Step();
  EXPECT_EQ(sim.steps(), 12345u);
  EXPECT_DOUBLE_EQ(sim.time(), 12.345);
}

TEST(SimulatorTest, KinematicOdometryMatchesTruthAndTimeoutStops) {
  Simulator sim(MakeRobot(), MakeRoom(), Options("kinematic"));
  Drive(&sim, 2.0, 0.3, 0.2);
  const Pose2 t = sim.true_pose(), o = sim.odom_pose();
  // No slip in the kinematic backend: odometry equals the truth (spawn at the origin).
  EXPECT_NEAR(o.x, t.x, 1e-9);
  EXPECT_NEAR(o.y, t.y, 1e-9);
  EXPECT_NEAR(o.yaw, t.yaw, 1e-9);
  // Exact arc: R = v / w = 1.5 m, angle 0.4 rad.
  EXPECT_NEAR(t.x, 1.5 * std::sin(0.4), 1e-6);
  EXPECT_NEAR(t.y, 1.5 * (1 - std::cos(0.4)), 1e-6);
  // Without new commands the robot stops once cmd_timeout (0.5 s) has passed.
  for (int i = 0; i < 600; ++i) sim.Step();
  const Pose2 before = sim.true_pose();
  for (int i = 0; i < 500; ++i) sim.Step();
  EXPECT_NEAR(sim.true_pose().x, before.x, 1e-12);
  EXPECT_DOUBLE_EQ(sim.odom_twist().vx, 0.0);
}

TEST(SimulatorTest, ScansAtTheSensorRate) {
  Simulator sim(MakeRobot(), MakeRoom(), Options("kinematic"));
  int scans = 0;
  std::vector<float> ranges;
  for (int i = 0; i < 2000; ++i) {
    if (sim.ScanDue(0)) {
      sim.TakeScan(0, &ranges);
      ++scans;
    }
    sim.Step();
  }
  EXPECT_EQ(scans, 20);  // t = 0.0, 0.1, ..., 1.9
  ASSERT_EQ(ranges.size(), 360u);
  // From the centre of a 4 m room every beam hits a wall between 2 and 2√2 m.
  for (float r : ranges) {
    EXPECT_GE(r, 1.97f);
    EXPECT_LE(r, 2.0f * std::sqrt(2.0f) + 0.03f);
  }
}

TEST(SimulatorTest, WallStopsTheRobotWithOneCollisionEvent) {
  for (const char* physics : {"kinematic", "bullet"}) {
    SCOPED_TRACE(physics);
    Simulator sim(MakeRobot(), MakeRoom(1.0), Options(physics));
    Drive(&sim, 6.0, 0.5, 0.0);  // 1 m to the wall, then keep pushing for seconds
    const auto events = sim.TakeCollisionEvents();
    ASSERT_GE(events.size(), 1u);
    EXPECT_EQ(events[0].shape_name, "east");
    EXPECT_EQ(sim.collision_count(), 1u) << "pushing against a wall is one collision, not many";
    EXPECT_LT(sim.true_pose().x, 1.0 - 0.12 + 0.01) << "the front face went into the wall";
    EXPECT_GT(sim.true_pose().x, 0.7);
    EXPECT_TRUE(sim.in_contact());
  }
}

// A triangle-mesh cube ahead: Bullet meets it as boxes along its cross-section (MeshBand), the
// lidar as its exact cut; both must agree that it is there.
TEST(SimulatorTest, MeshObstacleStopsTheRobotAndIsSeen) {
  World world = MakeRoom(3.0);
  auto cube = std::make_shared<TriangleMesh>();
  for (int i = 0; i < 8; ++i) {
    cube->vertices.emplace_back((i & 1) ? 0.2f : -0.2f, (i & 2) ? 0.2f : -0.2f,
                                (i & 4) ? 0.5f : 0.0f);
  }
  const std::uint32_t faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5},
                                      {0, 5, 1}, {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4},
                                      {1, 5, 7}, {1, 7, 3}};
  for (const auto& f : faces) cube->triangles.push_back({f[0], f[1], f[2]});
  Shape mesh;
  mesh.type = ShapeType::kMesh;
  mesh.name = "cube::link::collision";
  mesh.pose.translation() = Eigen::Vector3d(1.5, 0.0, 0.0);  // near face at x = 1.3
  mesh.mesh = cube;
  world.shapes.push_back(mesh);
  Simulator sim(MakeRobot(), world, Options("bullet"));
  std::vector<float> ranges;
  sim.TakeScan(0, &ranges);
  // Beam 180 of 360 over [-π, π] points straight ahead; the lidar sits 0.02 m ahead of the root.
  EXPECT_NEAR(ranges[180], 1.3 - 0.02, 0.01);
  Drive(&sim, 8.0, 0.4, 0.0);
  const auto events = sim.TakeCollisionEvents();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].shape_name, "cube::link::collision");
  EXPECT_LT(sim.true_pose().x, 1.3 - 0.12 + 0.01);
  EXPECT_GT(sim.true_pose().x, 1.0);
}

TEST(SimulatorTest, BulletTurnInPlaceSlipsSoOdometryDrifts) {
  Simulator sim(MakeRobot(), MakeRoom(), Options("bullet"));
  Drive(&sim, 3.0, 0.0, 1.0);
  const double true_yaw = sim.true_pose().yaw, odom_yaw = sim.odom_pose().yaw;
  EXPECT_GT(true_yaw, 0.3) << "the robot did not turn";
  // Skid-steering slips: the wheels turn more than the body does.
  EXPECT_GT(std::abs(NormalizeAngle(odom_yaw - true_yaw)), 0.05);
  EXPECT_LT(std::hypot(sim.true_pose().x, sim.true_pose().y), 0.05);
}

TEST(SimulatorTest, CalibratedTrackCorrectsTurnInPlaceOdometry) {
  // Wheels at (±0.075, ±0.1): turning in place, the body turns b²/(a² + b²) of the no-slip rate.
  SimulatorOptions o = Options("bullet");
  o.odom_wheel_separation_multiplier = (0.075 * 0.075 + 0.1 * 0.1) / (0.1 * 0.1);
  Simulator sim(MakeRobot(), MakeRoom(), o);
  Drive(&sim, 3.0, 0.0, 1.0);
  EXPECT_NEAR(NormalizeAngle(sim.odom_pose().yaw - sim.true_pose().yaw), 0.0, 0.03);
}

TEST(SimulatorTest, CalibratedCommandTrackAchievesCommandedYawRate) {
  // With the same multiplier on the command side the body turns at the commanded rate
  // (what a local planner predicting arcs assumes), within the slip model's accuracy.
  const double m = (0.075 * 0.075 + 0.1 * 0.1) / (0.1 * 0.1);
  SimulatorOptions o = Options("bullet");
  o.cmd_wheel_separation_multiplier = m;
  Simulator sim(MakeRobot(), MakeRoom(), o);
  Drive(&sim, 0.5, 0.0, 1.0);  // spin up
  const double yaw0 = sim.true_pose().yaw;
  Drive(&sim, 1.0, 0.0, 1.0);
  EXPECT_NEAR(NormalizeAngle(sim.true_pose().yaw - yaw0), 1.0, 0.1);
  o.cmd_wheel_separation_multiplier = 0.0;
  EXPECT_THROW(ValidateOptions(o), std::invalid_argument);
}

TEST(SimulatorTest, ResetAndTeleport) {
  SimulatorOptions o = Options("kinematic");
  o.spawn = Pose2{0.5, -0.5, 1.0};
  Simulator sim(MakeRobot(), MakeRoom(), o);
  Drive(&sim, 1.0, 0.3, 0.0);
  EXPECT_GT(std::abs(sim.odom_pose().x), 0.2);
  sim.Reset();
  EXPECT_DOUBLE_EQ(sim.true_pose().x, 0.5);
  EXPECT_DOUBLE_EQ(sim.true_pose().yaw, 1.0);
  EXPECT_DOUBLE_EQ(sim.odom_pose().x, 0.0);
  std::string what;
  EXPECT_TRUE(sim.PoseCollides(Pose2{1.95, 0.0, 0.0}, &what));
  EXPECT_EQ(what, "east");
  EXPECT_FALSE(sim.PoseCollides(Pose2{1.0, 1.0, 0.3}, &what));
  sim.SetPose(Pose2{1.0, 1.0, 0.3});
  EXPECT_DOUBLE_EQ(sim.true_pose().y, 1.0);
  EXPECT_DOUBLE_EQ(sim.odom_pose().x, 0.0);  // odometry is not told about a kidnapping
}

TEST(SimulatorTest, InvalidOptionsAreRejectedWithTheirValues) {
  SimulatorOptions o = Options("kinematic");
  o.physics_step = 0.0;
  try {
    Simulator sim(MakeRobot(), MakeRoom(), o);
    FAIL() << "physics_step 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("physics_step"), std::string::npos);
  }
  o = Options("warp_drive");
  try {
    Simulator sim(MakeRobot(), MakeRoom(), o);
    FAIL() << "unknown physics accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("warp_drive"), std::string::npos);
  }
}

#ifdef MINIBOT3D_SIM_SOURCE_DIR
// The generated clutter worlds (tools/generators/clutter_world.py): each loads without a warning,
// has its four walls and thin posts, and the robot fits at the start (0, 0) and at the goal
// (5.5, 0), and drives off the start, in both physics backends.
TEST(SimulatorTest, ClutterWorldsLoadWithStartAndGoalFree) {
  namespace fs = std::filesystem;
  std::vector<std::string> worlds;
  for (const auto& e : fs::directory_iterator(std::string(MINIBOT3D_SIM_SOURCE_DIR) +
                                              "/worlds/clutter")) {
    if (e.path().extension() == ".world") worlds.push_back(e.path().string());
  }
  std::sort(worlds.begin(), worlds.end());
  ASSERT_EQ(worlds.size(), 50u);
  WorldLoadOptions env;
  env.use_gazebo_model_path_env = false;
  for (const std::string& path : worlds) {
    SCOPED_TRACE(path);
    std::vector<std::string> warnings;
    World world = LoadWorld(path, env, &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    int boxes = 0, posts = 0;
    for (const Shape& s : world.shapes) {
      boxes += s.type == ShapeType::kBox;
      posts += s.type == ShapeType::kCylinder;
    }
    EXPECT_EQ(boxes, 4);
    EXPECT_GE(posts, 10);
    for (const char* physics : {"kinematic", "bullet"}) {
      SimulatorOptions o = Options(physics);
      o.spawn = Pose2{0.0, 0.0, 0.0};
      Simulator sim(MakeRobot(), world, o);
      std::string what;
      EXPECT_FALSE(sim.PoseCollides(Pose2{0.0, 0.0, 0.0}, &what)) << what;
      EXPECT_FALSE(sim.PoseCollides(Pose2{5.5, 0.0, 0.0}, &what)) << what;
      EXPECT_GT(sim.Clearance(), 0.5);
      Drive(&sim, 1.0, 0.3, 0.0);
      EXPECT_GT(sim.true_pose().x, 0.2) << physics;
      EXPECT_EQ(sim.collision_count(), 0u);
    }
  }
}
#endif

}  // namespace
}  // namespace minibot3d_sim
