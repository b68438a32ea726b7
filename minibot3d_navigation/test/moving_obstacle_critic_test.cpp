// The DWA local planner among moving obstacles (moving_obstacle_critic.h): the critic's rules,
// and closed loops in which people walk across or straight at the robot's path while the
// planner gets their positions and velocities each cycle, as the tracker gives them.
#include "minibot3d_navigation/dwa/moving_obstacle_critic.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dwa_test_scenes.h"
#include "minibot3d_common/geometry2d.h"
#include "minibot3d_navigation/dwa/dwa_planner.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

using testing::kFootprint;

// The shipped planner settings (config/trajectory_planner.yaml).
DwaOptions Options() { return testing::ShippedOptions(0.5); }

// A moving obstacle seen as a disc (no outline).
MovingObstacle Disc(const Point2& position, const Point2& velocity, double radius) {
  MovingObstacle o;
  o.position = position;
  o.velocity = velocity;
  o.radius = radius;
  return o;
}

Costmap2D OpenFloor() { return Costmap2D(240, 160, 0.05, -2.0, -4.0); }  // 12 m x 8 m, free

Path StraightPlan(double x0, double x1) {
  Path plan;
  for (double x = x0; x < x1; x += 0.05) plan.push_back({x, 0.0, 0.0});
  plan.push_back({x1, 0.0, 0.0});
  return plan;
}

struct Person {
  Point2 start;
  Point2 velocity;
  double radius = 0.25;
  // The share of its velocity the planner is told (a tracker's estimate lagging behind a person
  // who speeds up: < 1).
  double told = 1.0;
  Point2 At(double t) const { return {start.x + velocity.x * t, start.y + velocity.y * t}; }
};

double Gap(const Pose2& pose, const Person& p, double t) {
  const Point2 c = p.At(t);
  const double dx = c.x - pose.x, dy = c.y - pose.y;
  const double cs = std::cos(pose.yaw), sn = std::sin(pose.yaw);
  return minibot3d_common::PointPolygonDistance(kFootprint, cs * dx + sn * dy,
                                                -sn * dx + cs * dy) - p.radius;
}

struct DriveResult {
  bool reached = false;
  std::string error;
  double time = 0.0;
  double closest = 1e9;           // footprint to a person, m
  int contacts_moving = 0;        // contacts begun with the robot moving (robot at fault)
  int yields = 0;                 // cycles in Mode::kYield
  Pose2 pose;
};

// The robot from (0, 0) facing +x to (goal_x, 0) on an open floor; each cycle the planner gets
// the people's true positions and velocities (with `see_people`; else none).
DriveResult Drive(const std::vector<Person>& people, double goal_x, bool see_people,
                  double duration = 40.0, const DwaOptions& o = Options()) {
  DwaPlanner planner(o, kFootprint);
  const Costmap2D map = OpenFloor();
  const Path plan = StraightPlan(0.0, goal_x);
  const double period = 1.0 / o.controller_frequency;
  const int substeps = 100;
  const double dt = period / substeps;
  Pose2 pose{0.0, 0.0, 0.0};
  Twist2 vel;
  DriveResult r;
  std::vector<bool> touching(people.size(), false);
  for (double t = 0.0; t < duration; t += period) {
    if (planner.IsGoalReached(pose, vel, plan)) {
      r.reached = true;
      break;
    }
    std::vector<MovingObstacle> seen;
    if (see_people) {
      for (const Person& p : people) {
        seen.push_back(Disc(p.At(t), {p.told * p.velocity.x, p.told * p.velocity.y}, p.radius));
      }
    }
    planner.SetMovingObstacles(seen);
    Twist2 cmd;
    try {
      cmd = planner.ComputeVelocity(pose, vel, plan, map);
      if (planner.last_stats().mode == DwaPlanner::Mode::kYield) ++r.yields;
    } catch (const ControlError& e) {
      r.error = e.what();
    }
    for (int i = 0; i < substeps; ++i) {
      const double ts = t + i * dt;
      auto approach = [](double v, double target, double dv) {
        return target > v ? std::min(target, v + dv) : std::max(target, v - dv);
      };
      const double v1 = approach(vel.vx, cmd.vx, o.acc_lim_x * dt);
      const double w1 = approach(vel.wz, cmd.wz, o.acc_lim_theta * dt);
      pose = TrajectoryGenerator::Step(pose, 0.5 * (vel.vx + v1), 0.5 * (vel.wz + w1), dt);
      vel.vx = v1;
      vel.wz = w1;
      const bool moving = std::fabs(vel.vx) > 0.02 || std::fabs(vel.wz) > 0.05;
      for (size_t k = 0; k < people.size(); ++k) {
        const double g = Gap(pose, people[k], ts + dt);
        r.closest = std::min(r.closest, g);
        if (g <= 0.0 && !touching[k] && moving) ++r.contacts_moving;
        touching[k] = g <= 0.0;
      }
    }
    r.time = t + period;
  }
  r.pose = pose;
  return r;
}

TEST(MovingObstacleCriticTest, MovingWhenAContactIsPredictedIsIllegalStoppingIsNot) {
  MovingObstacleCritic critic(kFootprint, 2.0, 0.05, 0.0, 0.45);
  const Costmap2D map = OpenFloor();
  critic.Prepare({0, 0, 0}, Twist2(), StraightPlan(0, 5), map);
  // A person 0.55 m ahead (0.18 m from the footprint) walking towards the robot at 1 m/s.
  critic.SetObstacles({Disc({0.55, 0.0}, {-1.0, 0.0}, 0.25)});
  TrajectoryGenerator gen(Options());
  Trajectory forward, stop, turn;
  gen.Generate({0, 0, 0}, {0.3, 0.0, 0.0}, {0.5, 0.0, 0.0}, TrajectoryKind::kSampled, &forward);
  gen.Generate({0, 0, 0}, Twist2(), Twist2(), TrajectoryKind::kStop, &stop);
  gen.Generate({0, 0, 0}, Twist2(), {0.0, 0.0, 2.0}, TrajectoryKind::kInPlace, &turn);
  EXPECT_LT(critic.Score(forward), 0.0) << "driving on cannot stop short of the person";
  EXPECT_GE(critic.Score(stop), 0.0) << "the person walking into a standing robot";
  EXPECT_GT(critic.Score(stop), 0.0) << "but it costs: the person comes near";
  EXPECT_LT(critic.Score(turn), 0.0) << "turning on the spot as the person arrives: the robot "
                                       "would be moving at the contact";
  // Farther off, driving on can still stop short: legal, but it costs.
  critic.SetObstacles({Disc({1.5, 0.0}, {-1.0, 0.0}, 0.25)});
  EXPECT_GT(critic.Score(forward), 0.0);
  // Nobody near: nothing costs.
  critic.SetObstacles({Disc({-5.0, 3.0}, {0.0, 1.0}, 0.25)});
  EXPECT_EQ(critic.Score(forward), 0.0);
}

TEST(MovingObstacleCriticTest, BackingOutOfAStandoffOnlyAfterTheWait) {
  MovingObstacleCritic critic(kFootprint, 2.0, 0.05, 0.0, 0.45);
  const Costmap2D map = OpenFloor();
  critic.Prepare({0, 0, 0}, Twist2(), StraightPlan(0, 5), map);
  TrajectoryGenerator gen(Options());
  Trajectory back, forward;
  gen.Generate({0, 0, 0}, Twist2(), {-0.1, 0.0, 0.0}, TrajectoryKind::kEscape, &back);
  gen.Generate({0, 0, 0}, Twist2(), {0.1, 0.0, 0.0}, TrajectoryKind::kSampled, &forward);
  // A person standing 0.03 m in front of the footprint (a standoff).
  critic.SetObstacles({Disc({0.13 + 0.03 + 0.25, 0.0}, {0.0, 0.0}, 0.25)});
  EXPECT_LT(critic.Score(back), 0.0) << "before the wait the robot stands";
  critic.set_backing_out(true);
  EXPECT_GE(critic.Score(back), 0.0) << "after it, it may back away";
  EXPECT_LT(critic.Score(forward), 0.0) << "never towards the person";
  // The same person walking at the robot: it stands for the contact, wait or not.
  critic.SetObstacles({Disc({0.13 + 0.03 + 0.25, 0.0}, {-0.5, 0.0}, 0.25)});
  EXPECT_LT(critic.Score(back), 0.0);
}

TEST(MovingObstacleCriticTest, TheMarginGrowsWithTimeAtTheDeviationSpeed) {
  const Costmap2D map = OpenFloor();
  TrajectoryGenerator gen(Options());
  Trajectory turn;
  gen.Generate({0, 0, 0}, Twist2(), {0.0, 0.0, 1.0}, TrajectoryKind::kInPlace, &turn);
  // A person standing 0.12 m in front of the footprint.
  const MovingObstacle person = Disc({0.13 + 0.12 + 0.25, 0.0}, {0.0, 0.0}, 0.25);
  MovingObstacleCritic exact(kFootprint, 2.0, 0.05, 0.0, 0.45);
  exact.Prepare({0, 0, 0}, Twist2(), StraightPlan(0, 5), map);
  exact.SetObstacles({person});
  EXPECT_GE(exact.Score(turn), 0.0) << "were people to do as predicted, turning would be safe";
  MovingObstacleCritic straying(kFootprint, 2.0, 0.05, 0.5, 0.45);
  straying.Prepare({0, 0, 0}, Twist2(), StraightPlan(0, 5), map);
  straying.SetObstacles({person});
  EXPECT_LT(straying.Score(turn), 0.0)
      << "in the time the turn takes to stop, a person may step 0.12 m";
  // Far enough that no stray within the way to a stop reaches the robot.
  straying.SetObstacles({Disc({0.13 + 0.4 + 0.25, 0.0}, {0.0, 0.0}, 0.25)});
  EXPECT_GE(straying.Score(turn), 0.0);
}

TEST(MovingObstacleCriticTest, TimesOfTheRolloutAndTheBrakingTail) {
  TrajectoryGenerator gen(Options());
  Trajectory traj;
  gen.Generate({0, 0, 0}, {0.5, 0.0, 0.0}, {0.5, 0.0, 0.0}, TrajectoryKind::kSampled, &traj);
  ASSERT_GT(traj.poses.size(), 2u);
  // At constant speed pose i is i * dt * 0.5 m ahead.
  const size_t i = traj.poses.size() / 2;
  EXPECT_NEAR(traj.poses[i].x, 0.5 * i * traj.dt, 1e-9);
  EXPECT_NEAR(traj.poses.size() - 1, std::lround(1.5 / traj.dt), 0);
  // The tail starts one control period in and brakes at acc_lim_x to a standstill.
  EXPECT_NEAR(traj.braking_t0, 0.1, 1e-12);
  EXPECT_NEAR(traj.braking_poses.front().x, 0.05, 1e-9);
  const double t_end = traj.braking_t0 + (traj.braking_poses.size() - 1) * traj.braking_dt;
  EXPECT_NEAR(t_end, 0.1 + 0.5 / 2.5, 1e-9);
}

TEST(MovingObstacleClosedLoopTest, APersonCrossingAheadIsLetPastWithoutContact) {
  // The person crosses the robot's line at x = 2.5 at 1.0 m/s, timed to be there when a robot
  // driving at 0.5 m/s would be.
  const std::vector<Person> people = {{{2.5, -5.0}, {0.0, 1.0}}};
  const DriveResult blind = Drive(people, 6.0, false);
  EXPECT_GT(blind.contacts_moving, 0) << "without predictions the robot drives into the person "
                                         "(the scene tests nothing otherwise)";
  const DriveResult r = Drive(people, 6.0, true);
  EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
  EXPECT_EQ(r.contacts_moving, 0) << "closest " << r.closest << " m";
  EXPECT_GT(r.closest, 0.02);
  EXPECT_LT(r.time, 20.0);
}

TEST(MovingObstacleClosedLoopTest, PeopleCrossingFromBothSidesAtWalkingSpeeds) {
  for (double speed : {0.5, 1.0, 1.5}) {
    SCOPED_TRACE("speed " + std::to_string(speed));
    const double meet = 2.0 / 0.5;  // s for the robot to reach x = 2
    const std::vector<Person> people = {{{2.0, -speed * meet}, {0.0, speed}},
                                        {{4.0, speed * (meet + 4.0)}, {0.0, -speed}}};
    const DriveResult r = Drive(people, 6.0, true);
    EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
    EXPECT_EQ(r.contacts_moving, 0) << "closest " << r.closest << " m";
  }
}

TEST(MovingObstacleClosedLoopTest, APersonWalkingStraightAtTheRobotIsNeverDrivenInto) {
  // Head-on along the robot's line at 0.8 m/s; the person does not give way. The robot may only
  // be touched standing (the person walks into it), never while it moves.
  const std::vector<Person> people = {{{5.0, 0.0}, {-0.8, 0.0}}};
  const DriveResult blind = Drive(people, 6.0, false, 15.0);
  EXPECT_GT(blind.contacts_moving, 0);
  const DriveResult r = Drive(people, 6.0, true, 30.0);
  EXPECT_EQ(r.contacts_moving, 0) << "closest " << r.closest << " m";
  EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
}

TEST(MovingObstacleClosedLoopTest, APersonFasterThanTheEstimateIsNotDrivenIntoEither) {
  // Head-on at 1.2 m/s, on the robot's line or 0.3 m beside it, while the planner is told a
  // quarter or half of that speed (a track lagging behind a person who sped up). Trusting the
  // prediction (moving_obstacle_deviation 0, the default) the robot is moving at some contact;
  // allowing for 0.5 m/s of deviation it stands at every one.
  const DwaOptions exact = Options();
  ASSERT_EQ(exact.moving_obstacle_deviation, 0.0);
  DwaOptions straying = Options();
  straying.moving_obstacle_deviation = 0.5;
  int trusting_contacts = 0;
  for (double told : {0.25, 0.5}) {
    for (double y : {0.0, 0.3}) {
      SCOPED_TRACE("told " + std::to_string(told) + ", y " + std::to_string(y));
      std::vector<Person> people = {{{5.0, y}, {-1.2, 0.0}}};
      people[0].told = told;
      trusting_contacts += Drive(people, 6.0, true, 30.0, exact).contacts_moving;
      const DriveResult r = Drive(people, 6.0, true, 30.0, straying);
      EXPECT_EQ(r.contacts_moving, 0) << "closest " << r.closest << " m";
      EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
    }
  }
  EXPECT_GT(trusting_contacts, 0) << "the scenes test nothing otherwise";
}

}  // namespace
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
