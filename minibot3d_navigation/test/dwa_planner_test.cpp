// DWA local planner on small synthetic scenes.  Costmaps are built inline
// (boxes of lethal cells, inflated here with costmap_2d's formula), and the
// closed-loop tests drive a unicycle that follows each command within the
// acceleration limits, integrated at 1 ms, with the planner at
// controller_frequency.  The real footprint cost is checked at every
// integration step.
#include "minibot3d_navigation/dwa/dwa_planner.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/dwa/critics.h"
#include "minibot3d_navigation/dwa/map_grid.h"
#include "minibot3d_navigation/dwa/trajectory.h"
#include "dwa_test_scenes.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

using testing::AddBox;
using testing::kFootprint;
using testing::ShippedOptions;
constexpr double kInscribed = 0.125;
constexpr double kInflation = 0.55;
constexpr double kCostScaling = 10.0;

// --- scene helpers ---

Costmap2D EmptyMap(double width, double height, double res = 0.05) {
  return Costmap2D(static_cast<int>(std::lround(width / res)),
                   static_cast<int>(std::lround(height / res)), res, 0.0, 0.0);
}

// A room `width` x `height` m with 0.1 m walls on its four sides.
Costmap2D WalledRoom(double width, double height) {
  Costmap2D map = EmptyMap(width, height);
  AddBox(&map, 0.0, 0.0, width, 0.1);
  AddBox(&map, 0.0, height - 0.1, width, height);
  AddBox(&map, 0.0, 0.0, 0.1, height);
  AddBox(&map, width - 0.1, 0.0, width, height);
  return map;
}

// The inflation of the scenes: inscribed 0.125 m, inflation 0.55 m, scaling 10.
void Inflate(Costmap2D* map) { testing::Inflate(map, kInscribed, kInflation, kCostScaling); }

// Straight segments through the waypoints, a pose every 5 cm, yaw along
// the path; the last pose gets `goal_yaw`.
Path PolylinePlan(const std::vector<Point2>& pts, double goal_yaw) {
  Path plan;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double dx = pts[i + 1].x - pts[i].x, dy = pts[i + 1].y - pts[i].y;
    const int n = std::max(1, static_cast<int>(std::ceil(std::hypot(dx, dy) / 0.05)));
    const double yaw = std::atan2(dy, dx);
    for (int k = 0; k < n; ++k) {
      plan.push_back({pts[i].x + dx * k / n, pts[i].y + dy * k / n, yaw});
    }
  }
  plan.push_back({pts.back().x, pts.back().y, goal_yaw});
  return plan;
}

// --- closed loop ---

struct SimResult {
  bool reached = false;
  bool control_error = false;
  std::string error;
  int max_cost = 0;        // worst real footprint cost seen (-1 -> 255)
  double max_speed = 0.0;  // |vx|
  double time = 0.0;
  Pose2 pose;
  Twist2 velocity;
  std::vector<Pose2> track;
  std::vector<double> speeds;  // |vx| at each track pose
  std::vector<Twist2> commands;
};

double Approach(double v, double target, double dv) {
  return target > v ? std::min(target, v + dv) : std::max(target, v - dv);
}

// Runs the planner at options.controller_frequency for up to `duration`
// seconds.  On ControlError the robot is commanded to stop and, after one
// more second of braking, the run ends.
SimResult Simulate(DwaPlanner* planner, const Costmap2D& map, Pose2 pose,
                   const Path& plan, double duration) {
  const DwaOptions& o = planner->options();
  const double period = 1.0 / o.controller_frequency;
  const int substeps = static_cast<int>(std::lround(period / 0.001));
  const double dt = period / substeps;
  SimResult r;
  Twist2 vel;
  double stop_at = duration;
  for (double t = 0.0; t < stop_at; t += period) {
    Twist2 cmd;
    if (!r.control_error) {
      if (planner->IsGoalReached(pose, vel, plan)) {
        r.reached = true;
        break;
      }
      try {
        cmd = planner->ComputeVelocity(pose, vel, plan, map);
      } catch (const ControlError& e) {
        r.control_error = true;
        r.error = e.what();
        cmd = Twist2();
        stop_at = std::min(duration, t + 1.0);
      }
    }
    r.commands.push_back(cmd);
    for (int i = 0; i < substeps; ++i) {
      const double v1 = Approach(vel.vx, cmd.vx, o.acc_lim_x * dt);
      const double w1 = Approach(vel.wz, cmd.wz, o.acc_lim_theta * dt);
      pose = TrajectoryGenerator::Step(pose, 0.5 * (vel.vx + v1),
                                       0.5 * (vel.wz + w1), dt);
      vel.vx = v1;
      vel.wz = w1;
      int c = FootprintCost(map, kFootprint, pose);
      if (c < 0) c = 255;
      r.max_cost = std::max(r.max_cost, c);
      r.max_speed = std::max(r.max_speed, std::fabs(vel.vx));
    }
    r.track.push_back(pose);
    r.speeds.push_back(std::fabs(vel.vx));
    r.time = t + period;
  }
  r.pose = pose;
  r.velocity = vel;
  return r;
}

DwaOptions FastOptions() {
  DwaOptions o;
  o.max_vel_x = 1.0;
  o.min_vel_x = 0.1;
  o.acc_lim_x = 2.5;
  o.acc_lim_theta = 3.2;
  o.vx_samples = 10;
  o.vtheta_samples = 20;
  o.sim_time = 1.0;
  return o;
}

// --- trajectory generation ---

TEST(TrajectoryGeneratorTest, WindowIsReachableInOnePeriod) {
  DwaOptions o = FastOptions();
  const TrajectoryGenerator gen(o);
  Twist2 v0;
  v0.vx = 0.5;
  v0.wz = 0.2;
  const VelocityWindow w = gen.Window(v0);
  EXPECT_NEAR(w.min_vx, 0.5 - 2.5 * 0.05, 1e-12);
  EXPECT_NEAR(w.max_vx, 0.5 + 2.5 * 0.05, 1e-12);
  EXPECT_NEAR(w.min_vth, 0.2 - 3.2 * 0.05, 1e-12);
  EXPECT_NEAR(w.max_vth, 0.2 + 3.2 * 0.05, 1e-12);
  // Clamped to the limits; min_vel_x floors the window.
  const VelocityWindow still = gen.Window(Twist2());
  EXPECT_NEAR(still.min_vx, 0.1, 1e-12);
  EXPECT_NEAR(still.max_vx, 0.125, 1e-12);
  // Rollout length must cover the stopping distance: v <= 2 a sim_time.
  o.sim_time = 0.1;
  o.max_vel_x = 2.0;
  o.controller_frequency = 20.0;
  Twist2 fast;
  fast.vx = 2.0;
  const VelocityWindow capped = TrajectoryGenerator(o).Window(fast);
  EXPECT_NEAR(capped.max_vx, 2.0 * 2.5 * 0.1, 1e-12);
}

TEST(TrajectoryGeneratorTest, RolloutRampsThenHoldsAndTailBrakes) {
  const DwaOptions o = FastOptions();
  const TrajectoryGenerator gen(o);
  Twist2 v0;
  v0.vx = 1.0;
  Twist2 cmd;
  cmd.vx = 1.0;
  Trajectory t;
  gen.Generate({0, 0, 0}, v0, cmd, TrajectoryKind::kSampled, &t);
  EXPECT_NEAR(t.end().x, 1.0, 1e-9);  // 1 m/s for sim_time 1 s
  EXPECT_NEAR(t.end().y, 0.0, 1e-12);
  // Poses at most sim_granularity apart.
  for (size_t i = 1; i < t.poses.size(); ++i) {
    EXPECT_LE(t.poses[i].x - t.poses[i - 1].x, o.sim_granularity + 1e-9);
  }
  // Tail: 0.05 m in the first period, then v^2 / 2a = 0.2 m of braking.
  EXPECT_NEAR(t.braking_poses.front().x, 0.05, 1e-9);
  EXPECT_NEAR(t.braking_poses.back().x, 0.25, 1e-9);
  EXPECT_NEAR(t.braking_start_distance, 0.05, 1e-9);

  // A turn: exact-ish arc (radius v/w).
  cmd.wz = 0.5;
  v0.wz = 0.5;
  gen.Generate({0, 0, 0}, v0, cmd, TrajectoryKind::kSampled, &t);
  EXPECT_NEAR(t.end().x, 2.0 * std::sin(0.5), 1e-3);
  EXPECT_NEAR(t.end().y, 2.0 * (1.0 - std::cos(0.5)), 1e-3);
  EXPECT_NEAR(t.end().yaw, 0.5, 1e-9);
}

TEST(TrajectoryGeneratorTest, BrakingTailRejectsCommandsThatCannotStop) {
  // 5 Hz, 0.25 s rollouts, robot at 1 m/s: a rollout covers 0.25 m, but the
  // robot travels 0.2 m before the next cycle and needs 0.2 m more to stop.
  DwaOptions o = FastOptions();
  o.controller_frequency = 5.0;
  o.sim_time = 0.25;
  Costmap2D map = EmptyMap(4.0, 2.0);
  // Robot front at 1.13; wall face 0.45 m ahead of it: clear of the rollouts
  // (0.25 m + 0.125 m inscribed band) but not of the braking tail.
  AddBox(&map, 1.58, 0.0, 2.0, 2.0);
  Inflate(&map);
  Twist2 v0;
  v0.vx = 1.0;
  const TrajectoryGenerator gen(o);
  Trajectory t;
  Twist2 hold;
  hold.vx = 1.0;
  gen.Generate({1.0, 1.0, 0.0}, v0, hold, TrajectoryKind::kSampled, &t);
  ObstacleCostCritic critic(kFootprint);
  critic.SetCostmap(map);
  Trajectory rollout_only = t;
  rollout_only.braking_poses.clear();
  EXPECT_GE(critic.Score(rollout_only), 0.0) << "the rollout alone looks fine";
  EXPECT_LT(critic.Score(t), 0.0) << "but the robot could not stop";
  // The collision is beyond the rollout, on the way to a standstill.
  EXPECT_GT(critic.nearest_collision_distance(), 0.25);
  EXPECT_LT(critic.nearest_collision_distance(), 0.2 + 0.2 + 1e-9);
  // So the planner slows down to a speed it can still stop from.
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{1.0, 1.0}, {3.5, 1.0}}, 0.0);
  const Twist2 cmd = planner.ComputeVelocity({1.0, 1.0, 0.0}, v0, plan, map);
  EXPECT_LT(cmd.vx, 0.9);
  critic.SetCostmap(map);
  EXPECT_GE(critic.Score(planner.last_trajectory()), 0.0);
  EXPECT_FALSE(planner.last_trajectory().braking_poses.empty());
}

TEST(DwaCriticsTest, RequiredClearanceGrowsWithSpeedFromCreepingToFullMargin) {
  Costmap2D map = EmptyMap(4.0, 2.0);
  AddBox(&map, 2.0, 0.0, 2.2, 2.0);
  Inflate(&map);
  ObstacleCostCritic critic(kFootprint);
  critic.SetCostmap(map);
  critic.set_tight_speed(0.1);
  critic.set_full_margin_speed(0.5);
  const double band = critic.RequiredClearance(10.0);
  // The band's width, read from the costmap: one inscribed radius, to a cell.
  EXPECT_NEAR(band, kInscribed, 0.05);
  EXPECT_EQ(critic.RequiredClearance(0.0), 0.0);
  EXPECT_EQ(critic.RequiredClearance(0.1), 0.0);  // creeping: lethal cells only
  EXPECT_NEAR(critic.RequiredClearance(0.3), 0.5 * band, 1e-12);
  EXPECT_NEAR(critic.RequiredClearance(0.5), band, 1e-12);
  EXPECT_NEAR(critic.RequiredClearance(0.8), band, 1e-12);
  // A full-margin speed at or below creeping: the whole band above it (the
  // rule before full_margin_vel).
  critic.set_full_margin_speed(0.1);
  EXPECT_EQ(critic.RequiredClearance(0.1), 0.0);
  EXPECT_NEAR(critic.RequiredClearance(0.11), band, 1e-12);
}

// --- map grid ---

TEST(MapGridTest, BreadthFirstDistancesAvoidObstacles) {
  Costmap2D map = EmptyMap(1.0, 1.0, 0.1);  // 10 x 10
  for (int my = 0; my < 8; ++my) map.set_cost(5, my, kLethalObstacle);
  MapGrid grid;
  ASSERT_TRUE(grid.SetTargetCell(map, 2, 0, {}));
  EXPECT_EQ(grid.distance(2, 0), 0.0f);
  EXPECT_EQ(grid.distance(2, 3), 3.0f);
  EXPECT_EQ(grid.distance(5, 0), grid.obstacle_distance());
  // Around the wall through row 8: 2->... (2,0) to (7,0) = 8 up + 5 + 8 down.
  EXPECT_EQ(grid.distance(7, 0), 21.0f);
  // Enclose a cell: unreachable.
  map.set_cost(5, 8, kLethalObstacle);
  map.set_cost(5, 9, kLethalObstacle);
  grid.SetTargetCell(map, 2, 0, {});
  EXPECT_EQ(grid.distance(7, 0), grid.unreachable_distance());
  EXPECT_FALSE(grid.Reachable(7, 0));
  // The robot's own cells may be crossed.
  grid.SetTargetCell(map, 2, 0, {map.Index(5, 4)});
  EXPECT_TRUE(grid.Reachable(7, 0));
}

TEST(MapGridTest, LocalGoalStopsBeforeABlockingObstacle) {
  Costmap2D map = EmptyMap(4.0, 1.0, 0.05);
  AddBox(&map, 2.5, 0.0, 2.6, 1.0);
  const Path plan = PolylinePlan({{0.2, 0.5}, {3.8, 0.5}}, 0.0);
  int gx, gy;
  bool in_obstacle = true;
  ASSERT_TRUE(MapGrid::FindLocalGoal(map, plan, &gx, &gy, &in_obstacle));
  EXPECT_FALSE(in_obstacle);
  double wx, wy;
  map.MapToWorld(gx, gy, &wx, &wy);
  EXPECT_LT(wx, 2.5);
  EXPECT_GT(wx, 2.3);
}

// --- planner, open loop ---

TEST(DwaPlannerTest, ConstructorValidatesOptionsAndFootprint) {
  DwaOptions o;
  o.holonomic_robot = true;
  try {
    DwaPlanner p(o, kFootprint);
    FAIL() << "holonomic_robot accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("holonomic_robot"), std::string::npos);
  }
  EXPECT_THROW(DwaPlanner(DwaOptions(), Footprint{{0, 0}, {1, 0}}),
               std::invalid_argument);
  DwaOptions no_margin;
  no_margin.full_margin_vel = 0.0;
  try {
    DwaPlanner p(no_margin, kFootprint);
    FAIL() << "full_margin_vel 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("full_margin_vel"), std::string::npos) << e.what();
  }
}

TEST(DwaPlannerTest, ErrorsSayWhy) {
  DwaPlanner planner(DwaOptions(), kFootprint);
  Costmap2D map = EmptyMap(4.0, 4.0);
  try {
    planner.ComputeVelocity({1, 1, 0}, Twist2(), Path(), map);
    FAIL();
  } catch (const ControlError& e) {
    EXPECT_NE(std::string(e.what()).find("plan is empty"), std::string::npos);
  }
  const Path plan = PolylinePlan({{1, 1}, {3, 1}}, 0.0);
  try {
    planner.ComputeVelocity({9, 1, 0}, Twist2(), plan, map);
    FAIL();
  } catch (const ControlError& e) {
    EXPECT_NE(std::string(e.what()).find("off the local costmap"),
              std::string::npos)
        << e.what();
  }
  // Wedged: in a slot 0.30 m wide (too narrow to turn in), the front half a
  // centimetre from its end, a wall touching the rear.  Every pose after the
  // start touches a lethal cell, backing up hits the wall.
  Costmap2D slot = EmptyMap(4.0, 2.0);
  AddBox(&slot, 0.0, 0.0, 4.0, 0.85);
  AddBox(&slot, 0.0, 1.15, 4.0, 2.0);
  AddBox(&slot, 2.5, 0.0, 2.6, 2.0);
  AddBox(&slot, 2.1, 0.0, 2.23, 2.0);
  Inflate(&slot);
  const Path plan2 = PolylinePlan({{2.3, 1.0}, {3.5, 1.0}}, 0.0);
  try {
    planner.ComputeVelocity({2.365, 1.0, 0.0}, Twist2(), plan2, slot);
    FAIL() << "wedged robot got a command";
  } catch (const ControlError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("trajectories rejected"), std::string::npos) << msg;
    EXPECT_NE(msg.find("collide or cannot stop in time"), std::string::npos) << msg;
    EXPECT_NE(msg.find("nearest obstacle"), std::string::npos) << msg;
    EXPECT_NE(msg.find("escape_vel -0.10 m/s collides too"), std::string::npos)
        << msg;
  }
  // At the goal in a slot too narrow to turn in: 0.30 m, wider than the
  // robot (0.25 m) but narrower than the circle its corners sweep (0.36 m).
  Costmap2D narrow = EmptyMap(4.0, 2.0);
  AddBox(&narrow, 0.0, 0.0, 4.0, 0.85);
  AddBox(&narrow, 0.0, 1.15, 4.0, 2.0);
  Inflate(&narrow);
  const Path plan3 = PolylinePlan({{1.0, 1.0}, {2.0, 1.0}}, kPi / 2);
  try {
    planner.ComputeVelocity({2.0, 1.0, 0.0}, Twist2(), plan3, narrow);
    FAIL() << "turned in a slot";
  } catch (const ControlError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cannot rotate in place to the goal yaw 90.0 deg"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("nearest obstacle"), std::string::npos) << msg;
  }
}

TEST(DwaPlannerTest, RotatesInPlaceWhenFacingAwayFromThePath) {
  DwaPlanner planner(DwaOptions(), kFootprint);
  Costmap2D map = EmptyMap(4.0, 4.0);
  const Path plan = PolylinePlan({{1, 2}, {3.5, 2}}, 0.0);
  const Twist2 cmd = planner.ComputeVelocity({1, 2, kPi}, Twist2(), plan, map);
  EXPECT_EQ(cmd.vx, 0.0);
  EXPECT_GE(std::fabs(cmd.wz), planner.options().min_in_place_vel_theta);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kRotateToPath);
}

TEST(DwaPlannerTest, GoalReachedNeedsPositionYawAndStandstill) {
  DwaPlanner planner(DwaOptions(), kFootprint);
  Costmap2D map = EmptyMap(4.0, 4.0);
  const Path plan = PolylinePlan({{1, 2}, {2, 2}}, 0.0);
  Twist2 moving;
  moving.vx = 0.3;
  EXPECT_FALSE(planner.IsGoalReached({2.05, 2, 0.02}, moving, plan));
  EXPECT_TRUE(planner.IsGoalReached({2.05, 2, 0.02}, Twist2(), plan));
  EXPECT_FALSE(planner.IsGoalReached({2.2, 2, 0.0}, Twist2(), plan));
  EXPECT_FALSE(planner.IsGoalReached({2.0, 2, 0.2}, Twist2(), plan));
  // At the goal: zero command.
  const Twist2 cmd = planner.ComputeVelocity({2.0, 2.0, 0.01}, Twist2(), plan, map);
  EXPECT_EQ(cmd.vx, 0.0);
  EXPECT_EQ(cmd.wz, 0.0);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kAtGoal);
}

TEST(DwaPlannerTest, LatchedGoalToleranceKeepsRotating) {
  DwaOptions o;
  o.latch_xy_goal_tolerance = true;
  DwaPlanner planner(o, kFootprint);
  Costmap2D map = EmptyMap(4.0, 4.0);
  const Path plan = PolylinePlan({{1, 2}, {2, 2}}, kPi / 2);
  planner.ComputeVelocity({2.0, 2.0, 0.0}, Twist2(), plan, map);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kRotateToGoal);
  // Drifted out of the xy tolerance: still only rotating.
  const Twist2 cmd = planner.ComputeVelocity({2.2, 2.0, 0.5}, Twist2(), plan, map);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kRotateToGoal);
  EXPECT_EQ(cmd.vx, 0.0);
  EXPECT_TRUE(planner.IsGoalReached({2.2, 2.0, kPi / 2}, Twist2(), plan));
  // A new goal clears the latch.
  planner.Reset();
  EXPECT_FALSE(planner.IsGoalReached({2.2, 2.0, kPi / 2}, Twist2(), plan));
}

TEST(DwaPlannerTest, EscapesBackwardsWhenNothingForwardIsLegal) {
  // Dead-end slot 0.30 m wide (the robot is 0.25 m: it fits, but cannot turn
  // in it), the robot's front half a centimetre from the end wall; the plan
  // goes on through the wall (made before the wall was seen).  Every forward
  // or turning pose touches a lethal cell; backing up does not.
  Costmap2D map = EmptyMap(4.0, 2.0);
  AddBox(&map, 0.0, 0.0, 4.0, 0.85);
  AddBox(&map, 0.0, 1.15, 4.0, 2.0);
  AddBox(&map, 2.5, 0.0, 2.6, 2.0);
  Inflate(&map);
  const Path plan = PolylinePlan({{2.0, 1.0}, {3.5, 1.0}}, 0.0);
  const Pose2 pose{2.365, 1.0, 0.0};
  ASSERT_LT(FootprintCost(map, kFootprint, pose), kLethalObstacle);
  DwaPlanner planner(DwaOptions(), kFootprint);
  const Twist2 back = planner.ComputeVelocity(pose, Twist2(), plan, map);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kEscape);
  EXPECT_LT(back.vx, 0.0);
  EXPECT_GE(back.vx, -0.1 - 1e-9);
  EXPECT_EQ(back.wz, 0.0);
}

TEST(DwaPlannerTest, CentripetalLimitKeepsFastArcsWide) {
  // Fast, on a plan curving left on a 0.6 m radius: without a limit the
  // planner follows it at speed (0.9 m/s needs 1.5 rad/s, 1.35 m/s^2); with
  // max_centripetal_acc it keeps |vx * vtheta| within it.
  DwaOptions o;
  o.max_vel_x = 1.0;
  o.max_vel_theta = 2.5;
  o.min_vel_theta = -2.5;
  o.acc_lim_theta = 20.0;
  o.sim_time = 1.0;
  o.path_distance_bias = 1.2;
  o.meter_scoring = true;
  Costmap2D map = EmptyMap(4.0, 4.0);
  std::vector<Point2> arc;
  for (int i = 0; i <= 30; ++i) {
    const double a = kPi * i / 30.0;  // half a circle around (1.0, 1.6)
    arc.push_back({1.0 + 0.6 * std::sin(a), 1.6 - 0.6 * std::cos(a)});
  }
  const Path plan = PolylinePlan(arc, kPi);
  Twist2 v;
  v.vx = 0.9;
  v.wz = 1.2;
  {
    DwaPlanner unlimited(o, kFootprint);
    const Twist2 cmd = unlimited.ComputeVelocity({1.0, 1.0, 0.0}, v, plan, map);
    ASSERT_GT(std::fabs(cmd.vx * cmd.wz), 1.2) << cmd.vx << " " << cmd.wz;
  }
  o.max_centripetal_acc = 1.0;
  DwaPlanner limited(o, kFootprint);
  const Twist2 cmd = limited.ComputeVelocity({1.0, 1.0, 0.0}, v, plan, map);
  EXPECT_EQ(limited.last_stats().mode, DwaPlanner::Mode::kFollowPath);
  EXPECT_LE(std::fabs(cmd.vx * cmd.wz), 1.0 + 1e-9) << cmd.vx << " " << cmd.wz;
  EXPECT_GT(cmd.wz, 0.0);  // still turning towards the plan
}

TEST(DwaPlannerTest, FastRobotCarriedIntoTheBandBrakes) {
  // Moving at 0.8 m/s towards a wall 0.23 m to the left, at 20 degrees, the
  // front corner 7 cm from it, deep in the inscribed band (slip, a late
  // costmap): no command keeps the margin a fast robot needs, so the first
  // pass fails.  The way out is for creeping robots; a fast one brakes.
  Costmap2D map = EmptyMap(6.0, 3.0);
  AddBox(&map, 0.0, 1.5, 6.0, 3.0);
  Inflate(&map);
  DwaOptions o;
  o.max_vel_x = 1.0;
  o.sim_time = 1.5;
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{1.0, 1.24}, {5.0, 1.24}}, 0.0);
  Twist2 v;
  v.vx = 0.8;
  const Twist2 cmd = planner.ComputeVelocity({1.0, 1.27, 0.35}, v, plan, map);
  EXPECT_LT(cmd.vx, v.vx);
  EXPECT_NEAR(cmd.vx, v.vx - o.acc_lim_x / o.controller_frequency, 1e-9);
  EXPECT_EQ(cmd.wz, 0.0);
  // Slow, the same pose gets the way out instead of only braking.
  Twist2 slow;
  slow.vx = 0.05;
  DwaPlanner creeping(o, kFootprint);
  const Twist2 way_out = creeping.ComputeVelocity({1.0, 1.27, 0.35}, slow, plan, map);
  EXPECT_TRUE(way_out.wz < 0.0 || way_out.vx < 0.0)
      << "turns or backs away from the wall: " << way_out.vx << " " << way_out.wz;
}

TEST(DwaPlannerTest, SlowRobotTurnsOnTheSpotAtAQuarterOfTheAngle) {
  // The plan 30 degrees off the heading: a moving robot follows it on an
  // arc, a stopped one turns on the spot first (rotate_to_path_angle is 90).
  Costmap2D map = EmptyMap(4.0, 4.0);
  const Path plan = PolylinePlan({{1.0, 1.0}, {1.0 + std::sqrt(3.0), 2.0}}, kPi / 6);
  DwaPlanner stopped(DwaOptions(), kFootprint);
  const Twist2 turn = stopped.ComputeVelocity({1.0, 1.0, 0.0}, Twist2(), plan, map);
  EXPECT_EQ(stopped.last_stats().mode, DwaPlanner::Mode::kRotateToPath);
  EXPECT_EQ(turn.vx, 0.0);
  EXPECT_GT(turn.wz, 0.0);
  Twist2 v;
  v.vx = 0.4;
  DwaPlanner moving(DwaOptions(), kFootprint);
  moving.ComputeVelocity({1.0, 1.0, 0.0}, v, plan, map);
  EXPECT_EQ(moving.last_stats().mode, DwaPlanner::Mode::kFollowPath);
}

TEST(DwaPlannerTest, TiesGoToTheFasterTrajectory) {
  // Three speeds whose rollouts all end in the robot's own cell score the
  // same (costs move in whole cells); the fastest is taken, not the first
  // sampled (which used to leave a robot crawling at min_vel_x).
  DwaOptions o;
  o.min_vel_x = 0.005;
  o.max_vel_x = 0.015;
  o.escape_vel = -0.01;
  o.vx_samples = 3;
  o.sim_time = 1.0;
  DwaPlanner planner(o, kFootprint);
  Costmap2D map = EmptyMap(4.0, 2.0);
  const Path plan = PolylinePlan({{1.025, 1.025}, {3.5, 1.025}}, 0.0);
  const Twist2 cmd = planner.ComputeVelocity({1.025, 1.025, 0.0}, Twist2(), plan, map);
  EXPECT_EQ(planner.last_stats().mode, DwaPlanner::Mode::kFollowPath);
  EXPECT_NEAR(cmd.vx, 0.015, 1e-9);
  EXPECT_EQ(cmd.wz, 0.0);
}

TEST(OscillationCriticTest, ForbidsFlippingBackUntilMoved) {
  OscillationCritic critic(0.05);
  Costmap2D map = EmptyMap(1.0, 1.0);
  Trajectory left, right, forward, backward;
  left.command.wz = 0.5;
  right.command.wz = -0.5;
  forward.command.vx = 0.2;
  backward.command.vx = -0.1;
  critic.Prepare({0.5, 0.5, 0}, Twist2(), Path(), map);
  EXPECT_EQ(critic.Score(left), 0.0);
  critic.Debrief(left);
  critic.Prepare({0.5, 0.5, 0.1}, Twist2(), Path(), map);
  EXPECT_EQ(critic.Score(right), 0.0);
  critic.Debrief(right);  // flipped: turning left is now forbidden
  critic.Prepare({0.5, 0.5, 0.0}, Twist2(), Path(), map);
  EXPECT_LT(critic.Score(left), 0.0);
  EXPECT_EQ(critic.Score(right), 0.0);
  EXPECT_EQ(critic.Score(forward), 0.0);
  // Forward then backward (an escape) keeps forward allowed: driving on
  // after backing out is progress.  Backward then forward forbids backing up
  // again.
  critic.Debrief(forward);
  critic.Debrief(backward);
  EXPECT_EQ(critic.Score(forward), 0.0);
  critic.Debrief(forward);
  EXPECT_LT(critic.Score(backward), 0.0);
  // Moving oscillation_reset_dist clears everything.
  critic.Prepare({0.58, 0.5, 0.0}, Twist2(), Path(), map);
  EXPECT_EQ(critic.Score(left), 0.0);
  EXPECT_EQ(critic.Score(backward), 0.0);
}

TEST(DwaPlannerTest, MeterScoringScalesTheCostsByTheResolution) {
  Costmap2D map = EmptyMap(4.0, 3.0);
  AddBox(&map, 2.0, 0.0, 2.4, 1.0);
  Inflate(&map);
  const Path plan = PolylinePlan({{0.5, 1.5}, {3.5, 1.5}}, 0.0);
  DwaOptions o;
  DwaPlanner cells(o, kFootprint);
  o.meter_scoring = true;
  DwaPlanner metres(o, kFootprint);
  Twist2 v0;
  v0.vx = 0.3;
  const Twist2 a = cells.ComputeVelocity({0.8, 1.5, 0.0}, v0, plan, map);
  const Twist2 b = metres.ComputeVelocity({0.8, 1.5, 0.0}, v0, plan, map);
  EXPECT_DOUBLE_EQ(a.vx, b.vx);
  EXPECT_DOUBLE_EQ(a.wz, b.wz);
  EXPECT_NEAR(metres.last_trajectory().cost,
              cells.last_trajectory().cost * map.resolution(), 1e-9);
}

// --- planner, closed loop ---

TEST(DwaClosedLoopTest, FollowsAStraightCorridor) {
  Costmap2D map = EmptyMap(8.0, 3.0);
  AddBox(&map, 0.0, 0.0, 8.0, 0.5);
  AddBox(&map, 0.0, 2.5, 8.0, 3.0);
  Inflate(&map);
  DwaOptions o;
  o.vx_samples = 10;
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{0.5, 1.5}, {7.0, 1.5}}, 0.0);
  const SimResult r = Simulate(&planner, map, {0.5, 1.5, 0.0}, plan, 40.0);
  EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
  EXPECT_LT(r.max_cost, kInscribedInflatedObstacle);
  double worst_offset = 0.0;
  for (const Pose2& p : r.track) worst_offset = std::max(worst_offset, std::fabs(p.y - 1.5));
  EXPECT_LT(worst_offset, 0.05);
  EXPECT_NEAR(r.max_speed, o.max_vel_x, 0.02);
  EXPECT_LT(r.time, 20.0);  // 6.5 m at 0.5 m/s plus ramps
}

// The plan goes straight into a wall across the corridor; the robot is fast
// (1 m/s) and the obstacle is only seen as it is: it must brake, never touch.
void ExpectStopsInFrontOfWall(const DwaOptions& o, const char* label) {
  Costmap2D map = EmptyMap(8.0, 3.0);
  AddBox(&map, 0.0, 0.0, 8.0, 0.3);
  AddBox(&map, 0.0, 2.7, 8.0, 3.0);
  AddBox(&map, 5.0, 0.0, 5.2, 3.0);  // the wall: its cells start at x = 5.0
  Inflate(&map);
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{0.5, 1.5}, {7.0, 1.5}}, 0.0);
  const SimResult r = Simulate(&planner, map, {0.5, 1.5, 0.0}, plan, 15.0);
  SCOPED_TRACE(label);
  EXPECT_FALSE(r.reached);
  EXPECT_LT(r.max_cost, kLethalObstacle) << "the footprint touched the wall";
  EXPECT_GT(r.max_speed, 0.9) << "never got fast, the test proves nothing";
  // The outline never enters a wall cell; faster than creeping it keeps a
  // margin growing linearly from 0 at min_vel_x to the whole inscribed band
  // (0.125 m) at full_margin_vel.  The rule measures between cell centres
  // (the outline's cell, the wall's cell, whose centre is 0.025 m inside the
  // wall): up to a cell (0.05 m) more than the geometric gap checked here.
  double closest = 0.0;
  for (size_t i = 0; i < r.track.size(); ++i) {
    const Pose2& p = r.track[i];
    EXPECT_LT(p.x + 0.13, 5.0);
    if (r.speeds[i] > o.min_vel_x + 1e-6) {
      const double full = std::min(o.full_margin_vel, o.max_vel_x);
      const double margin =
          kInscribed * std::min(1.0, (r.speeds[i] - o.min_vel_x) / (full - o.min_vel_x));
      EXPECT_LT(p.x + 0.13, 5.0 - margin + 0.05) << "at " << r.speeds[i] << " m/s";
    }
    closest = std::max(closest, p.x + 0.13);
  }
  // It went up to the wall (not stopping miles before it).  Then either it
  // says why it cannot go on, or it turns away along the wall (the second,
  // way-out pass); what it may never do is touch the wall.
  EXPECT_GT(closest, 5.0 - 0.4);
  if (r.control_error) {
    EXPECT_NE(r.error.find("no admissible command"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("nearest obstacle"), std::string::npos) << r.error;
  }
}

TEST(DwaClosedLoopTest, WallAheadAtOneMetrePerSecondBrakesInTime) {
  ExpectStopsInFrontOfWall(FastOptions(), "20 Hz, sim_time 1.0");
}

TEST(DwaClosedLoopTest, WallAheadWithSlowControllerAndShortRollouts) {
  // Rollouts shorter than the stopping distance plus one period of travel:
  // only the braking tail keeps the robot off the wall.
  DwaOptions o = FastOptions();
  o.controller_frequency = 5.0;
  o.sim_time = 0.25;
  ExpectStopsInFrontOfWall(o, "5 Hz, sim_time 0.25");
  o.acc_lim_x = 1.2;  // stopping distance 0.42 m at 1 m/s
  o.sim_time = 0.45;
  ExpectStopsInFrontOfWall(o, "5 Hz, acc_lim_x 1.2");
}

TEST(DwaClosedLoopTest, TurnsThroughADoorway) {
  // Room 6 x 6 m, a wall across y = 3 with a 0.8 m door at x in [2.6, 3.4].
  Costmap2D map = WalledRoom(6.0, 6.0);
  AddBox(&map, 0.0, 2.95, 2.6, 3.05);
  AddBox(&map, 3.4, 2.95, 6.0, 3.05);
  Inflate(&map);
  DwaOptions o;
  o.vx_samples = 10;
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{1.0, 1.5}, {3.0, 1.5}, {3.0, 4.8}}, kPi / 2);
  const SimResult r = Simulate(&planner, map, {1.0, 1.5, 0.0}, plan, 60.0);
  EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y
                         << ", " << r.pose.yaw << ")";
  EXPECT_LT(r.max_cost, kLethalObstacle);
  bool passed_door = false;
  for (const Pose2& p : r.track) passed_door = passed_door || p.y > 3.5;
  EXPECT_TRUE(passed_door);
  EXPECT_NEAR(r.pose.x, 3.0, 0.1);
  EXPECT_NEAR(r.pose.y, 4.8, 0.1);
}


// A tight scene: the robot (0.26 m x 0.25 m with padding) must get through
// and reach the plan's end at every max_vel_x in 0.1-1.0, its outline never
// on a lethal cell.
void ExpectGetsThrough(const Costmap2D& map, const Pose2& start, const Path& plan,
                       const char* scene) {
  for (double v : {0.1, 0.25, 0.5, 1.0}) {
    SCOPED_TRACE(std::string(scene) + ", max_vel_x " + std::to_string(v));
    DwaPlanner planner(ShippedOptions(v), kFootprint);
    const SimResult r = Simulate(&planner, map, start, plan, 120.0);
    EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ", "
                           << r.pose.yaw << ") after " << r.time << " s";
    EXPECT_LT(r.max_cost, kLethalObstacle) << "the footprint touched an obstacle";
  }
}

TEST(DwaTightSpacesTest, ThroughADoorFortyCentimetresWide) {
  // Two rooms, a wall across y = 3 with a door of 0.40 m at x in [2.8, 3.2].
  Costmap2D map = WalledRoom(6.0, 6.0);
  AddBox(&map, 0.0, 2.9, 2.8, 3.1);
  AddBox(&map, 3.2, 2.9, 6.0, 3.1);
  Inflate(&map);
  ExpectGetsThrough(map, {1.5, 1.5, 0.0},
                    PolylinePlan({{1.5, 1.5}, {3.0, 1.8}, {3.0, 4.2}, {4.5, 4.8}}, 0.0),
                    "0.40 m door");
}

TEST(DwaTightSpacesTest, IntoAHalfMetreGapBetweenAShelfAndAWall) {
  // A wall at x = 0.1, a shelf 0.5 m from it (x in [0.6, 1.4], y in [2, 4]):
  // the goal is inside the gap, facing along it.
  Costmap2D map = WalledRoom(5.0, 5.0);
  AddBox(&map, 0.6, 2.0, 1.4, 4.0);
  Inflate(&map);
  ExpectGetsThrough(map, {2.5, 1.0, kPi},
                    PolylinePlan({{2.5, 1.0}, {0.35, 1.5}, {0.35, 3.0}}, kPi / 2),
                    "0.50 m gap beside a shelf");
}

TEST(DwaTightSpacesTest, BetweenTableLegsFortyTwoCentimetresApart) {
  // A table 0.52 m x 0.70 m on four legs (0.05 m square); the legs 0.42 m
  // apart along x (0.40 m between their cells); the robot drives under it.
  Costmap2D map = EmptyMap(6.0, 6.0);
  for (double y : {2.5, 3.2}) {
    AddBox(&map, 2.75, y, 2.8, y + 0.05);
    AddBox(&map, 3.2, y, 3.25, y + 0.05);
  }
  Inflate(&map);
  ExpectGetsThrough(map, {3.0, 1.0, kPi / 2},
                    PolylinePlan({{3.0, 1.0}, {3.0, 4.8}}, kPi / 2),
                    "table legs 0.42 m apart");
}

// A table on four legs whose faces stand 0.45 m apart on every side, centred on (3.025, 3.025),
// as a costmap sees it: each leg a cell, reaching up to a cell inside its faces (the cell of a
// face's laser hits), 0.35 m apart (x and y in [2.80, 2.85] and [3.20, 3.25]).
Costmap2D UnderATable() {
  Costmap2D map = EmptyMap(6.0, 6.0);
  for (double x : {2.825, 3.225}) {
    for (double y : {2.825, 3.225}) AddBox(&map, x - 0.01, y - 0.01, x + 0.01, y + 0.01);
  }
  Inflate(&map);
  return map;
}

TEST(DwaTightSpacesTest, UnderATableFacingTheWayItCame) {
  // The goal is under the table's centre, facing back the way the robot drives in. Within
  // xy_goal_tolerance (0.15 m) of it the robot is still between two legs, where turning on the
  // spot sweeps its corners into them: it stopped there, 0.14 m short, and gave up ("cannot
  // rotate in place to the goal yaw ... nearest obstacle 0.03 m"). It must go on to where the
  // turn is possible.
  const Costmap2D map = UnderATable();
  for (double v : {0.1, 0.25, 0.5, 1.0}) {
    SCOPED_TRACE("max_vel_x " + std::to_string(v));
    const DwaOptions o = ShippedOptions(v);
    DwaPlanner planner(o, kFootprint);
    const Path plan = PolylinePlan({{3.025, 1.0}, {3.025, 3.025}}, -kPi / 2);
    const SimResult r = Simulate(&planner, map, {3.025, 1.0, kPi / 2}, plan, 60.0);
    EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ", "
                           << r.pose.yaw << ") after " << r.time << " s";
    EXPECT_LT(r.max_cost, kLethalObstacle) << "the footprint touched a leg";
    EXPECT_LE(std::hypot(r.pose.x - 3.025, r.pose.y - 3.025), o.xy_goal_tolerance);
    EXPECT_LE(std::fabs(AngleDiff(r.pose.yaw, -kPi / 2)), o.yaw_goal_tolerance);
  }
}

TEST(DwaTightSpacesTest, ThroughAGapBetweenPostsFasterThanCreeping) {
  // A row of thin posts (0.05 m cells) across y = 3 with a 0.40 m gap at
  // x in [2.80, 3.20]: narrower than the robot (0.25 m) plus two inscribed
  // radii, so the outline has to enter the inscribed band.  It used to cross
  // at creeping speed (0.1 m/s) only; now its margin shrinks with speed and
  // it crosses at the speed the gap allows, never nearer a post than that
  // speed's margin (linear from 0 at min_vel_x to 0.125 m at
  // min(full_margin_vel, max_vel_x)).
  // The rule reads distances between cell centres (the outline's cells, the
  // posts' cells): up to half a cell plus half a diagonal (0.06 m) more than
  // the geometric clearance checked here.
  Costmap2D map = EmptyMap(6.0, 6.0);
  for (double x = 0.2; x < 2.8; x += 0.4) AddBox(&map, x, 2.95, x + 0.05, 3.0);
  AddBox(&map, 2.75, 2.95, 2.80, 3.0);
  AddBox(&map, 3.20, 2.95, 3.25, 3.0);
  for (double x = 3.6; x < 5.9; x += 0.4) AddBox(&map, x, 2.95, x + 0.05, 3.0);
  Inflate(&map);
  const DwaOptions o = ShippedOptions(0.5);
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{3.0, 1.0}, {3.0, 5.0}}, kPi / 2);
  const SimResult r = Simulate(&planner, map, {3.0, 1.0, kPi / 2}, plan, 60.0);
  ASSERT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ")";
  EXPECT_LT(r.max_cost, kLethalObstacle);
  double crossing_speed = 1e9;
  for (size_t i = 0; i < r.track.size(); ++i) {
    const Pose2& p = r.track[i];
    if (std::fabs(p.y - 2.975) > 0.15) continue;  // the outline is level with the posts
    crossing_speed = std::min(crossing_speed, r.speeds[i]);
    // Outline to the nearer post cell, sideways (the robot drives along y).
    const double clearance = std::min(p.x - 0.125 - 2.80, 3.20 - (p.x + 0.125));
    const double full = std::min(o.full_margin_vel, o.max_vel_x);
    const double margin =
        kInscribed * std::clamp((r.speeds[i] - o.min_vel_x) / (full - o.min_vel_x), 0.0, 1.0);
    EXPECT_GT(clearance, margin - 0.06) << "at " << r.speeds[i] << " m/s, x " << p.x;
  }
  ASSERT_LT(crossing_speed, 1e9) << "never between the posts";
  EXPECT_GT(crossing_speed, 0.15) << "crept through a gap it has room to drive through";
}

TEST(DwaPlannerTest, ARobotTouchingAWallSlidesAwayInsteadOfFreezing) {
  // Localization error has put the robot's right side on a wall cell, parallel
  // to the wall; the plan runs along it.  Every move touches a wall cell in
  // the grid, but sliding along (or edging away) gets no closer: it may.
  Costmap2D map = EmptyMap(8.0, 3.0);
  AddBox(&map, 0.0, 0.0, 8.0, 0.5);
  Inflate(&map);
  const Pose2 start{1.0, 0.62, 0.0};
  ASSERT_EQ(FootprintCost(map, kFootprint, start), kLethalObstacle);
  const Path plan = PolylinePlan({{1.0, 0.62}, {4.0, 0.9}, {7.0, 0.9}}, 0.0);
  DwaPlanner planner(ShippedOptions(0.5), kFootprint);
  Twist2 cmd;
  ASSERT_NO_THROW(cmd = planner.ComputeVelocity(start, Twist2(), plan, map));
  EXPECT_GE(cmd.vx, 0.0);
  EXPECT_GE(cmd.wz, 0.0) << "turned its nose into the wall";
  EXPECT_GT(std::fabs(cmd.vx) + std::fabs(cmd.wz), 0.0);
  const SimResult r = Simulate(&planner, map, start, plan, 60.0);
  EXPECT_TRUE(r.reached) << r.error << " at (" << r.pose.x << ", " << r.pose.y << ", "
                         << r.pose.yaw << ") after " << r.time << " s";
  double lowest = 1e9;
  for (const Pose2& p : r.track) lowest = std::min(lowest, p.y);
  // Turning away swings the rear corner towards the wall by at most a quarter
  // cell; the outline never reaches a wall cell's centre (y = 0.475).
  EXPECT_GE(lowest - 0.125, 0.475) << "got closer to the wall than allowed";
}

TEST(DwaPlannerTest, ARobotWithinAQuarterCellOfAWallStillMovesAway) {
  // As above, but 1 cm from the wall cells' centres (under the quarter cell
  // the rule keeps as a floor): every first step away is still nearer than a
  // quarter cell, and the robot used to freeze there ("first collision after
  // 0.00 m", backing up too), as in a clutter world where it crept up to a
  // post.  Now it may go as near as half its distance, and drives on along
  // the plan, edging no nearer.
  Costmap2D map = EmptyMap(8.0, 3.0);
  AddBox(&map, 0.0, 0.0, 8.0, 0.5);
  Inflate(&map);
  const Pose2 start{1.0, 0.61, 0.0};
  ASSERT_EQ(FootprintCost(map, kFootprint, start), kLethalObstacle);
  const Path plan = PolylinePlan({{1.0, 0.61}, {4.0, 0.9}, {7.0, 0.9}}, 0.0);
  DwaPlanner planner(ShippedOptions(0.5), kFootprint);
  const SimResult r = Simulate(&planner, map, start, plan, 20.0);
  EXPECT_FALSE(r.control_error) << r.error;
  EXPECT_GT(r.pose.x - start.x, 1.0) << "froze beside the wall";
  EXPECT_GE(r.pose.y, start.y) << "ended nearer the wall";
  double lowest = 1e9;
  for (const Pose2& p : r.track) lowest = std::min(lowest, p.y);
  EXPECT_GE(lowest - 0.125, 0.475 + 0.005 - 1e-6) << "got closer to the wall than allowed";
}

void ExpectRotatesToGoalYaw(double controller_frequency) {
  Costmap2D map = EmptyMap(4.0, 4.0);
  DwaOptions o;
  o.controller_frequency = controller_frequency;
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{1.0, 2.0}, {2.0, 2.0}}, kPi / 2);
  const SimResult r = Simulate(&planner, map, {2.02, 2.0, 0.0}, plan, 10.0);
  ASSERT_TRUE(r.reached) << r.error;
  EXPECT_NEAR(AngleDiff(r.pose.yaw, kPi / 2), 0.0, o.yaw_goal_tolerance);
  for (const Twist2& c : r.commands) {
    EXPECT_EQ(c.vx, 0.0);
    EXPECT_GE(c.wz, 0.0) << "turned the long way or overshot";
    EXPECT_LE(c.wz, o.max_vel_theta);
  }
  // Reached within a few seconds (pi/2 at <= 1 rad/s).
  EXPECT_LT(r.time, 4.0);
}

TEST(DwaClosedLoopTest, RotatesToTheGoalYawAtTheGoal) {
  ExpectRotatesToGoalYaw(20.0);
  ExpectRotatesToGoalYaw(5.0);  // coarse control: must not overshoot
}

TEST(DwaClosedLoopTest, DrivesToGoalAndStops) {
  Costmap2D map = EmptyMap(5.0, 5.0);
  AddBox(&map, 2.2, 2.2, 2.8, 2.8);  // a pillar beside the straight line
  Inflate(&map);
  DwaOptions o = FastOptions();
  DwaPlanner planner(o, kFootprint);
  const Path plan = PolylinePlan({{0.5, 1.5}, {4.5, 1.5}}, 0.0);
  const SimResult r = Simulate(&planner, map, {0.5, 1.5, 0.0}, plan, 30.0);
  ASSERT_TRUE(r.reached) << r.error;
  EXPECT_LT(r.max_cost, kLethalObstacle);
  EXPECT_LE(std::hypot(r.pose.x - 4.5, r.pose.y - 1.5), o.xy_goal_tolerance);
  EXPECT_TRUE(planner.IsGoalReached(r.pose, r.velocity, plan));
}

}  // namespace
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
