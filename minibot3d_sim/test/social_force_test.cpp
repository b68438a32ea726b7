// The social force model: a lone pedestrian relaxes to its desired speed as v0 (1 - exp(-t/tau))
// and covers v0 (t - tau (1 - exp(-t/tau))); two walking head-on swerve and pass each other, their
// bodies at most brushing (the body force holds them within 5 cm of touching), and two on one line
// down a corridor step aside and pass without stopping; one walking beside
// a wall keeps off it; one passes a standing robot, at most brushing it;
// goals are visited in turn; the same crowd replays bit for bit; bad settings are refused by name.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/social_force.h"

namespace minibot3d_sim {
namespace {

SocialForceAgent Walker(double x, double y, std::vector<Eigen::Vector2d> goals,
                        double speed = 1.2) {
  SocialForceAgent a;
  a.position = Eigen::Vector2d(x, y);
  a.radius = 0.25;
  a.options.goals = std::move(goals);
  a.options.desired_speed = speed;
  return a;
}

// Without the fluctuation force, for motion worked out by hand.
SocialForceParams Calm() {
  SocialForceParams p;
  p.fluctuation = 0.0;
  return p;
}

double NoWalls(const Eigen::Vector2d&, double, Eigen::Vector2d*) {
  return std::numeric_limits<double>::infinity();
}

// A corridor between walls at y = -1 and y = +1.
double Corridor(const Eigen::Vector2d& p, double, Eigen::Vector2d* away) {
  *away = Eigen::Vector2d(0.0, p.y() > 0 ? -1.0 : 1.0);
  return 1.0 - std::abs(p.y());
}

TEST(SocialForceTest, ALonePedestrianRelaxesToItsDesiredSpeed) {
  SocialForceCrowd crowd({Walker(0, 0, {Eigen::Vector2d(100, 0)})}, Calm(), NoWalls);
  for (int i = 0; i < 100; ++i) crowd.Step({});  // 1 s
  const double tau = 0.5, v0 = 1.2;
  EXPECT_NEAR(crowd.agents()[0].velocity.x(), v0 * (1 - std::exp(-1.0 / tau)), 0.01);
  for (int i = 0; i < 400; ++i) crowd.Step({});  // 5 s in all
  EXPECT_NEAR(crowd.agents()[0].velocity.x(), v0, 1e-3);
  EXPECT_NEAR(crowd.agents()[0].position.x(), v0 * (5.0 - tau * (1 - std::exp(-5.0 / tau))),
              0.02);
  EXPECT_NEAR(crowd.agents()[0].position.y(), 0.0, 1e-12);
}

TEST(SocialForceTest, TwoWalkingHeadOnSwerveAndPassEachOther) {
  SocialForceCrowd crowd({Walker(-5, 0.0, {Eigen::Vector2d(5, 0)}),
                          Walker(5, 0.1, {Eigen::Vector2d(-5, 0.1)})},
                         SocialForceParams(), NoWalls);
  double closest = 1e9;
  for (int i = 0; i < 1500; ++i) {
    crowd.Step({});
    closest = std::min(closest, (crowd.agents()[0].position - crowd.agents()[1].position).norm());
  }
  EXPECT_GT(closest, 0.5 - 0.05);  // two radii, less a brush of the shoulders
  // Both got past each other and to their goals' neighbourhood (15 s for 10 m at 1.2 m/s).
  EXPECT_GT(crowd.agents()[0].position.x(), 4.0);
  EXPECT_LT(crowd.agents()[1].position.x(), -4.0);
}

TEST(SocialForceTest, TwoMeetingDeadAheadInACorridorStepAsideAndPass) {
  // On one line down a corridor 2 m wide, 10 m apart, at 1 m/s: they step aside (to their right
  // unless the fluctuation tips them the other way) and pass without stopping, in every seed,
  // about when walking straight through would have them meet (5 s).
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    SocialForceCrowd crowd({Walker(-5, 0.0, {Eigen::Vector2d(20, 0)}, 1.0),
                            Walker(5, 0.0, {Eigen::Vector2d(-20, 0)}, 1.0)},
                           SocialForceParams(), Corridor, seed);
    double passed = -1.0, slowest = 1e9, closest = 1e9;
    for (int i = 1; i <= 1200 && passed < 0.0; ++i) {
      crowd.Step({});
      const auto& a = crowd.agents();
      if (i > 200) slowest = std::min(slowest, a[0].velocity.norm());
      closest = std::min(closest, (a[0].position - a[1].position).norm());
      if (a[0].position.x() > a[1].position.x()) {
        passed = i * 0.01;
        EXPECT_GT(std::abs(a[0].position.y() - a[1].position.y()), 0.5 - 0.05) << "side by side";
      }
    }
    EXPECT_GT(passed, 0.0) << "they never got past each other";
    EXPECT_LT(passed, 7.0);
    EXPECT_GT(slowest, 0.5) << "m/s: they slow, but never stand";
    EXPECT_GT(closest, 0.5 - 0.05);
  }
}

TEST(SocialForceTest, APedestrianBesideAWallKeepsOffIt) {
  SocialForceCrowd crowd({Walker(-5, 0.7, {Eigen::Vector2d(5, 0.7)})}, SocialForceParams(),
                         Corridor);
  double nearest_wall = 1e9;
  for (int i = 0; i < 800; ++i) {
    crowd.Step({});
    nearest_wall = std::min(nearest_wall, 1.0 - std::abs(crowd.agents()[0].position.y()));
  }
  EXPECT_GT(nearest_wall, 0.25);  // its radius
  EXPECT_GT(crowd.agents()[0].position.x(), 3.0);
}

TEST(SocialForceTest, APedestrianWalksRoundAStandingRobot) {
  SocialForceCrowd crowd({Walker(-3, 0.05, {Eigen::Vector2d(3, 0.05)})}, SocialForceParams(),
                         NoWalls);
  const std::vector<SocialForceObstacle> robot = {{Eigen::Vector2d(0, 0), 0.2}};
  double closest = 1e9;
  for (int i = 0; i < 800; ++i) {
    crowd.Step(robot);
    closest = std::min(closest, crowd.agents()[0].position.norm());
  }
  EXPECT_GT(closest, 0.45 - 0.05);  // the two radii, less a brush
  EXPECT_GT(crowd.agents()[0].position.x(), 2.0);
}

TEST(SocialForceTest, GoalsAreVisitedInTurn) {
  SocialForceCrowd crowd({Walker(0, 0, {Eigen::Vector2d(2, 0), Eigen::Vector2d(2, 2)})},
                         SocialForceParams(), NoWalls);
  for (int i = 0; i < 300 && crowd.agents()[0].goal == 0; ++i) crowd.Step({});
  EXPECT_EQ(crowd.agents()[0].goal, 1u);
  EXPECT_LT((crowd.agents()[0].position - Eigen::Vector2d(2, 0)).norm(), 0.3 + 1e-9);
}

TEST(SocialForceTest, TheSameCrowdReplaysExactly) {
  auto run = [] {
    std::vector<SocialForceAgent> agents;
    for (int k = 0; k < 12; ++k) {
      const double a = 2 * M_PI * k / 12;
      agents.push_back(Walker(3 * std::cos(a), 3 * std::sin(a),
                              {Eigen::Vector2d(-3 * std::cos(a), -3 * std::sin(a) + 0.01 * k)}));
    }
    SocialForceCrowd crowd(agents, SocialForceParams(), Corridor);
    for (int i = 0; i < 1000; ++i) crowd.Step({{Eigen::Vector2d(0.3, 0.1), 0.2}});
    return crowd.agents();
  };
  const auto a = run(), b = run();
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].position.x(), b[k].position.x());
    EXPECT_EQ(a[k].position.y(), b[k].position.y());
  }
}

TEST(SocialForceTest, BadSettingsAreRefusedByName) {
  SocialForceAgentOptions o;
  EXPECT_THROW(ValidateSocialForceAgent(o, "actor p"), std::invalid_argument);
  o.goals = {Eigen::Vector2d(1, 1)};
  EXPECT_NO_THROW(ValidateSocialForceAgent(o, "actor p"));
  o.desired_speed = 0.0;
  try {
    ValidateSocialForceAgent(o, "actor p");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("actor p: <desired_speed>"), std::string::npos);
  }
}

}  // namespace
}  // namespace minibot3d_sim
