// Tests of the physical backends: "bullet" (planar chassis + analytic wheel contacts) and, where
// the same behaviour is expected, "bullet_naive" (wheel bodies on hinge motors).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/physics_backend.h"
#include "naive_bullet_backend.h"
#include "sim_test_fixtures.h"

namespace minibot3d_sim {
namespace {

constexpr double kRadius = 0.04;
constexpr double kSeparation = 0.2;
constexpr double kHalfWheelbase = 0.07;
constexpr double kMass = 1.5;
constexpr double kWheelInertia = 0.5 * 0.1 * kRadius * kRadius;
constexpr double kGravity = 9.81;
constexpr double kDt = 0.001;
constexpr double kDeg = M_PI / 180.0;

using testing::MakeWallWorld;
using RobotParams = testing::PhysicsRobotParams;

RobotModel MakeRobot(const RobotParams& p = RobotParams()) { return testing::MakePhysicsRobot(p); }
World MakeWorld(double wall_x = 50.0) { return MakeWallWorld(wall_x); }

// "bullet" from the factory; "bullet_naive", the yardstick, from the bench library.
std::unique_ptr<PhysicsBackend> MakeBackend(const std::string& name, const RobotModel& robot,
                                            const World& world) {
  if (name == "bullet_naive") return std::make_unique<NaiveBulletBackend>(robot, world);
  return MakePhysicsBackend(name, robot, world);
}


void Drive(PhysicsBackend* b, double v, double w, double seconds,
           std::vector<Contact>* contacts = nullptr) {
  b->SetTargets(testing::SkidTargets(v, w));
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < steps; ++i) {
    if (contacts != nullptr) contacts->clear();
    b->Step(kDt, contacts);
  }
}

// Speed reached after `seconds` of a 0.3 m/s command from rest.
double SpeedAfter(const std::string& backend, const RobotParams& params, double seconds) {
  const World world = MakeWorld();
  auto b = MakeBackend(backend, MakeRobot(params), world);
  b->SetPose(Pose2{});
  Drive(b.get(), 0.3, 0.0, seconds);
  return b->twist().vx;
}

class PhysicalBackendTest : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<PhysicsBackend> Make(const World& world, const RobotParams& p = RobotParams()) {
    auto b = MakeBackend(GetParam(), MakeRobot(p), world);
    EXPECT_EQ(b->name(), GetParam());
    b->SetPose(Pose2{});
    return b;
  }
};

TEST_P(PhysicalBackendTest, DrivesStraight) {
  const World world = MakeWorld();
  auto b = Make(world);
  Drive(b.get(), 0.3, 0.0, 2.0);
  const Pose2 p = b->pose();
  EXPECT_NEAR(p.x, 0.6, 0.6 * 0.05);
  EXPECT_LT(std::abs(p.y), 0.02);
  EXPECT_LT(std::abs(p.yaw), 2 * kDeg);
  EXPECT_NEAR(b->twist().vx, 0.3, 0.01);
  // No slip when cruising straight: the wheels turn at the commanded speed.
  for (double w : b->wheel_velocities()) EXPECT_NEAR(w, 0.3 / kRadius, 0.2);
  for (double a : b->wheel_positions()) EXPECT_NEAR(a, p.x / kRadius, 0.05 * p.x / kRadius);
}

TEST_P(PhysicalBackendTest, TurnsInPlaceWithSlip) {
  const World world = MakeWorld();
  for (double dir : {1.0, -1.0}) {
    auto b = Make(world);
    const double w_cmd = 1.0 * dir;
    Drive(b.get(), 0.0, w_cmd, 1.0);
    const double yaw1 = b->pose().yaw;
    Drive(b.get(), 0.0, w_cmd, 1.0);
    const double rate = NormalizeAngle(b->pose().yaw - yaw1) / 1.0;
    EXPECT_GT(rate * dir, 0.2) << "turns the commanded way";
    // Lateral wheel friction resists the yaw: slower than the no-slip rate.
    EXPECT_LT(rate * dir, 0.9 * std::abs(w_cmd));
    EXPECT_LT(std::hypot(b->pose().x, b->pose().y), 0.03);
  }
}

TEST_P(PhysicalBackendTest, LowerTorqueAcceleratesSlower) {
  RobotParams weak;
  weak.torque = 0.02;
  const double strong_v = SpeedAfter(GetParam(), RobotParams(), 0.05);
  const double weak_v = SpeedAfter(GetParam(), weak, 0.05);
  EXPECT_GT(strong_v, 0.2);
  EXPECT_LT(weak_v, 0.5 * strong_v);
  EXPECT_GT(weak_v, 0.0);
}

TEST_P(PhysicalBackendTest, LowerFrictionSlipsMore) {
  RobotParams icy;
  icy.mu1 = icy.mu2 = 0.1;
  const World world = MakeWorld();
  auto grippy = Make(world);
  auto slippery = Make(world, icy);
  Drive(grippy.get(), 0.3, 0.0, 0.1);
  Drive(slippery.get(), 0.3, 0.0, 0.1);
  // Longitudinal slip: wheel rim speed minus body speed.
  auto slip = [](const PhysicsBackend& b) {
    return b.wheel_velocities()[0] * kRadius - b.twist().vx;
  };
  EXPECT_LT(slippery->twist().vx, 0.6 * grippy->twist().vx);
  EXPECT_GT(slip(*slippery), slip(*grippy) + 0.05);
}

TEST_P(PhysicalBackendTest, StopsAtWallWithContacts) {
  const double wall_x = 1.0;
  const World world = MakeWorld(wall_x);
  auto b = Make(world);
  std::vector<Contact> contacts;
  b->SetTargets(testing::SkidTargets(1.0, 0.0));
  double max_nose = -1.0;
  bool touched = false;
  for (int i = 0; i < 2000; ++i) {
    contacts.clear();
    b->Step(kDt, &contacts);
    max_nose = std::max(max_nose, b->pose().x + 0.12);
    for (const Contact& c : contacts) {
      touched = true;
      EXPECT_EQ(c.shape, 1) << "only robot-wall contacts";
      EXPECT_LT(c.depth, 0.005);
      EXPECT_LT(c.normal.x(), -0.9) << "normal points from the wall into the robot";
      EXPECT_NEAR(c.point.x(), wall_x, 0.01);
    }
  }
  EXPECT_TRUE(touched);
  EXPECT_FALSE(contacts.empty()) << "still pushing at the end";
  EXPECT_LT(max_nose, wall_x + 0.005) << "did not pass the wall";
  EXPECT_GT(b->pose().x + 0.12, wall_x - 0.01) << "stopped at the wall, not before";
  EXPECT_LT(std::abs(b->twist().vx), 0.02);
  EXPECT_LT(std::abs(b->pose().yaw), 2 * kDeg);
  // The wheels keep turning while the robot pushes (slip against the floor).
  EXPECT_GT(b->wheel_velocities()[0], 1.0);

  // Backing away frees it.
  Drive(b.get(), -0.3, 0.0, 0.5, &contacts);
  EXPECT_TRUE(contacts.empty());
  EXPECT_LT(b->pose().x + 0.12, wall_x - 0.1);
}

TEST_P(PhysicalBackendTest, SetPoseTeleportsAndZeroesVelocity) {
  const World world = MakeWorld();
  auto b = Make(world);
  Drive(b.get(), 0.3, 0.5, 1.0);
  const auto angles = b->wheel_positions();
  const Pose2 target{3.0, -2.0, 2.5};
  b->SetPose(target);
  EXPECT_NEAR(b->pose().x, target.x, 1e-5);
  EXPECT_NEAR(b->pose().y, target.y, 1e-5);
  EXPECT_NEAR(b->pose().yaw, target.yaw, 1e-5);
  EXPECT_NEAR(b->twist().vx, 0.0, 1e-9);
  EXPECT_NEAR(b->twist().vy, 0.0, 1e-9);
  EXPECT_NEAR(b->twist().wz, 0.0, 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(b->wheel_velocities()[i], 0.0, 1e-9);
    EXPECT_NEAR(b->wheel_positions()[i], angles[i], 1e-9) << "wheel angles are kept";
  }
  // At rest with no command it stays there.
  Drive(b.get(), 0.0, 0.0, 0.5);
  EXPECT_NEAR(b->pose().x, target.x, 2e-3);
  EXPECT_NEAR(b->pose().y, target.y, 2e-3);
  EXPECT_NEAR(b->pose().yaw, target.yaw, 1 * kDeg);
}

TEST_P(PhysicalBackendTest, IsDeterministic) {
  const World world = MakeWorld(1.0);
  auto a = Make(world);
  auto b = Make(world);
  std::vector<Contact> contacts;
  for (auto* backend : {a.get(), b.get()}) {
    // Asking for contacts (a) or not (b) must not change the simulation.
    std::vector<Contact>* out = backend == a.get() ? &contacts : nullptr;
    Drive(backend, 0.4, 0.8, 1.0, out);
    Drive(backend, 0.0, -2.0, 0.7, out);
    Drive(backend, 1.0, 0.1, 1.5, out);  // into the wall
  }
  EXPECT_FALSE(contacts.empty());
  EXPECT_EQ(a->pose().x, b->pose().x);
  EXPECT_EQ(a->pose().y, b->pose().y);
  EXPECT_EQ(a->pose().yaw, b->pose().yaw);
  EXPECT_EQ(a->wheel_positions(), b->wheel_positions());
  // And it really did something.
  EXPECT_GT(a->pose().x, 0.3);
}

INSTANTIATE_TEST_SUITE_P(Backends, PhysicalBackendTest,
                         ::testing::Values(std::string("bullet"), std::string("bullet_naive")),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

// Quantitative checks of "bullet"'s wheel–ground model against closed-form answers.

TEST(BulletBackendTest, InPlaceTurnRateIsTheCoulombFrictionBalance) {
  // Turning in place with wheel rim speed s, every wheel at (±a, ±b) slides; Coulomb friction
  // opposite to each slip velocity balances in yaw when Ω (a² + b²) = b s, i.e. the yaw rate is
  // b² / (a² + b²) of the no-slip rate s / b, whatever mu (isotropic) and the load.
  const double a = kHalfWheelbase, bh = kSeparation / 2;
  for (double mu : {0.3, 1.0}) {
    RobotParams p;
    p.mu1 = p.mu2 = mu;
    const World world = MakeWorld();
    auto b = MakeBackend("bullet", MakeRobot(p), world);
    b->SetPose(Pose2{});
    Drive(b.get(), 0.0, 1.5, 1.0);
    EXPECT_NEAR(b->twist().wz, 1.5 * bh * bh / (a * a + bh * bh), 0.01) << "mu " << mu;
  }
}

TEST(BulletBackendTest, LowerLateralFrictionTurnsCloserToNoSlip) {
  RobotParams loose;
  loose.mu2 = 0.3;
  const World world = MakeWorld();
  auto stiff = MakeBackend("bullet", MakeRobot(), world);
  auto soft = MakeBackend("bullet", MakeRobot(loose), world);
  stiff->SetPose(Pose2{});
  soft->SetPose(Pose2{});
  Drive(stiff.get(), 0.0, 1.0, 1.0);
  Drive(soft.get(), 0.0, 1.0, 1.0);
  EXPECT_GT(soft->twist().wz, stiff->twist().wz + 0.1);
  EXPECT_LT(soft->twist().wz, 1.0);
}

TEST(BulletBackendTest, TorqueLimitedAcceleration) {
  // Motors at their limit, no slip: 4 τ / r = (M + 4 I / r²) a.
  RobotParams weak;
  weak.torque = 0.02;
  const double expected =
      4 * weak.torque / kRadius / (kMass + 4 * kWheelInertia / (kRadius * kRadius));
  const double v = SpeedAfter("bullet", weak, 0.1);
  EXPECT_NEAR(v / 0.1, expected, 0.02 * expected);
}

TEST(BulletBackendTest, FrictionLimitedAcceleration) {
  // Strong motors on a slippery floor: the wheels spin and the floor pushes with mu1 m g.
  RobotParams icy;
  icy.mu1 = 0.1;
  const double v = SpeedAfter("bullet", icy, 0.1);
  EXPECT_NEAR(v / 0.1, icy.mu1 * kGravity, 0.02 * icy.mu1 * kGravity);
}

TEST(BulletBackendTest, ArcIsWiderThanCommandedBecauseOfSlip) {
  const World world = MakeWorld();
  auto b = MakeBackend("bullet", MakeRobot(), world);
  b->SetPose(Pose2{});
  Drive(b.get(), 0.3, 0.5, 2.0);
  const Twist2 t = b->twist();
  EXPECT_NEAR(t.vx, 0.3, 0.01);
  EXPECT_GT(t.wz, 0.1);
  EXPECT_LT(t.wz, 0.5);
  // Sideways skid is small and outward is not required; it must just be bounded.
  EXPECT_LT(std::abs(t.vy), 0.02);
}

TEST(BulletBackendTest, AgreesWithTheFullBulletModel) {
  // The reduced model (analytic wheel contacts) against wheel bodies rolling on a plane: steady
  // speeds and slipping yaw rates for arcs and turning in place.
  struct Command {
    double v, w;
  };
  const World world = MakeWorld();
  for (const Command c : {Command{0.2, 0.6}, Command{0.0, 2.0}, Command{0.5, -1.0}}) {
    auto reduced = MakeBackend("bullet", MakeRobot(), world);
    auto full = MakeBackend("bullet_naive", MakeRobot(), world);
    for (auto* b : {reduced.get(), full.get()}) {
      b->SetPose(Pose2{});
      Drive(b, c.v, c.w, 2.0);
    }
    EXPECT_NEAR(reduced->twist().vx, full->twist().vx, 0.05 * std::abs(c.v) + 0.005)
        << c.v << " " << c.w;
    EXPECT_NEAR(reduced->twist().wz, full->twist().wz, 0.1 * std::abs(full->twist().wz))
        << c.v << " " << c.w;
    // Both slip: well below the commanded (no-slip) yaw rate.
    EXPECT_LT(std::abs(reduced->twist().wz), 0.8 * std::abs(c.w));
  }
}

TEST(BulletBackendTest, PrecisionDoesNotDependOnDistanceFromOrigin) {
  // Bullet stores transforms in single precision; the backend's pose must not inherit the
  // ~1e-7 x |position| rounding per step (that would be 2 % of the distance at 0.05 m/s, 40 m out).
  const World world;
  double distance[2];
  for (int k = 0; k < 2; ++k) {
    const double x0 = k == 0 ? 0.0 : 40.0;
    auto b = MakeBackend("bullet", MakeRobot(), world);
    b->SetPose(Pose2{x0, x0, 0.7});
    Drive(b.get(), 0.05, 0.0, 10.0);
    distance[k] = std::hypot(b->pose().x - x0, b->pose().y - x0);
    EXPECT_NEAR(b->pose().yaw, 0.7, 1e-6);
  }
  EXPECT_NEAR(distance[0], 0.5, 0.001);
  EXPECT_NEAR(distance[1], distance[0], 1e-6);
}

TEST(BulletBackendTest, DoesNotTunnelThroughThinWallAtLargeSteps) {
  // A 2 cm wall, 1 m/s, 10 ms steps (1 cm per step).
  World world;
  world.shapes.push_back(
      testing::Box("thin", 1.01, 0, 0.02, 4, 0.5));
  auto b = MakeBackend("bullet", MakeRobot(), world);
  b->SetPose(Pose2{});
  b->SetTargets(testing::SkidTargets(1.0, 0.0));
  for (int i = 0; i < 300; ++i) b->Step(0.01, nullptr);
  EXPECT_LT(b->pose().x + 0.12, 1.005);
  EXPECT_GT(b->pose().x + 0.12, 0.98);
}

}  // namespace
}  // namespace minibot3d_sim
