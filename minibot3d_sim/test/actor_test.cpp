// Actors: Gazebo's playback of <script> trajectories worked out by hand (the cardinal spline
// between waypoints, the heading along the shorter way, trajectories in sequence, loop, delay,
// auto_start), SDF loading and its bad input (no waypoint, times out of order, an unknown script
// element, a tension out of range, two actors of one name), and actors in the simulation: the laser
// and the depth camera see one where it is at that time, a robot driving into one is held and
// reports it by name, a spawn on one is refused naming it; a social-force crowd walks, keeps off
// the walls and replays exactly.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_sim/actor.h"
#include "minibot3d_sim/simulator.h"
#include "minibot3d_sim/world_loader.h"
#include "sim_test_fixtures.h"
#include "urdf_fixtures.h"

namespace minibot3d_sim {
namespace {

ActorWaypoint Wp(double t, double x, double y, double yaw = 0.0) {
  ActorWaypoint w;
  w.time = t, w.x = x, w.y = y, w.yaw = yaw;
  return w;
}

Actor Walker(std::vector<ActorWaypoint> waypoints, double tension = 0.0) {
  Actor a;
  a.name = "walker";
  ActorTrajectory tr;
  tr.tension = tension;
  tr.waypoints = std::move(waypoints);
  a.trajectories.push_back(tr);
  return a;
}

TEST(ActorTest, TwoWaypointsFollowTheHermiteCurveWithHalfSegmentTangents) {
  // p(u) = p0 + (p1 - p0)(h01 + h10/2 + h11/2) = p0 + (p1 - p0)(-u^3 + 1.5 u^2 + 0.5 u).
  const Actor a = Walker({Wp(0, 0, 0), Wp(4, 4, 0)});
  EXPECT_NEAR(ActorAt(a, 1.0).x, 4 * (-0.015625 + 0.09375 + 0.125), 1e-12);
  EXPECT_NEAR(ActorAt(a, 2.0).x, 2.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 4.0 - 1e-9).x, 4.0, 1e-6);
  // dp/dt = (p1 - p0)(-3u^2 + 3u + 0.5) / 4 s: 0.5 m/s at the ends, 1.25 m/s in the middle.
  EXPECT_NEAR(ActorAt(a, 1e-9).vx, 0.5, 1e-6);
  EXPECT_NEAR(ActorAt(a, 2.0).vx, 1.25, 1e-12);
  EXPECT_NEAR(ActorAt(a, 2.0).vy, 0.0, 1e-12);
}

TEST(ActorTest, AnInteriorWaypointsTangentIsHalfTheChordOfItsNeighbours) {
  // Segment 0 at u = 1/2: m0 = (p1 - p0) / 2 = (1, 0), m1 = (p2 - p0) / 2 = (1, 1);
  // p = (p0 + p1) / 2 + (m0 - m1) / 8 = (1, -0.125).
  const Actor a = Walker({Wp(0, 0, 0), Wp(2, 2, 0), Wp(4, 2, 2)});
  EXPECT_NEAR(ActorAt(a, 1.0).x, 1.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 1.0).y, -0.125, 1e-12);
  // Through each waypoint at its time.
  EXPECT_NEAR(ActorAt(a, 2.0).x, 2.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 2.0).y, 0.0, 1e-12);
  // Tension 1: zero tangents, so the middle of a segment is the chord's middle.
  const Actor taut = Walker({Wp(0, 0, 0), Wp(2, 2, 0), Wp(4, 2, 2)}, 1.0);
  EXPECT_NEAR(ActorAt(taut, 1.0).y, 0.0, 1e-12);
}

TEST(ActorTest, HeadingTurnsTheShorterWayAtAConstantRate) {
  const Actor a = Walker({Wp(0, 0, 0, 3.0), Wp(1, 0, 0, -3.0)});
  // From 3.0 to -3.0 rad the shorter way is through pi (0.283 rad), not through 0.
  EXPECT_NEAR(std::cos(ActorAt(a, 0.5).yaw), -1.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 0.5).wz, 2 * M_PI - 6.0, 1e-12);
}

TEST(ActorTest, TrajectoriesPlayInSequenceWithLoopAndDelay) {
  Actor a;
  a.name = "a";
  ActorTrajectory first, second;
  first.waypoints = {Wp(0, 0, 0), Wp(2, 2, 0)};
  second.waypoints = {Wp(0, 2, 0), Wp(3, 2, 3)};
  a.trajectories = {first, second};
  EXPECT_DOUBLE_EQ(ScriptLength(a), 5.0);
  EXPECT_NEAR(ActorAt(a, 1.0).x, 1.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 2.0 + 1.5).y, 1.5, 1e-12);  // the second, half-way
  // Looping (the default): 5 s later, the same.
  EXPECT_NEAR(ActorAt(a, 5.0 + 1.0).x, 1.0, 1e-12);
  // Without loop: at the end, at rest.
  a.loop = false;
  EXPECT_NEAR(ActorAt(a, 9.0).y, 3.0, 1e-12);
  EXPECT_EQ(ActorAt(a, 9.0).vy, 0.0);
  // Delayed 2 s: standing at the first waypoint until then, then the script from its start.
  a.delay_start = 2.0;
  EXPECT_NEAR(ActorAt(a, 1.0).x, 0.0, 1e-12);
  EXPECT_NEAR(ActorAt(a, 3.0).x, 1.0, 1e-12);
  // auto_start false: waits for a trigger that never comes.
  a.auto_start = false;
  EXPECT_NEAR(ActorAt(a, 3.0).x, 0.0, 1e-12);
  // No script: stands at its pose.
  Actor still;
  still.x = 1.5, still.y = -2.0;
  EXPECT_DOUBLE_EQ(ActorAt(still, 100.0).x, 1.5);
}

std::string WriteWorld(const std::string& actors) {
  const std::string path = ::testing::TempDir() + "/actor_test.world";
  std::ofstream out(path);
  out << "<?xml version='1.0'?><sdf version='1.6'><world name='w'>" << actors
      << "</world></sdf>";
  return path;
}

TEST(ActorTest, LoadsGazebosActorScript) {
  std::vector<std::string> warnings;
  const World w = LoadSdfWorld(
      WriteWorld("<actor name='walker'><skin><filename>walk.dae</filename></skin>"
                 "<script><loop>false</loop><delay_start>1.5</delay_start>"
                 "<trajectory id='0' type='walking' tension='0.2'>"
                 "<waypoint><time>0</time><pose>0 2 0 0 0 -1.57</pose></waypoint>"
                 "<waypoint><time>2</time><pose>0 -2 0 0 0 -1.57</pose></waypoint>"
                 "</trajectory><trajectory id='1' type='walking'>"
                 "<waypoint><time>0</time><pose>0 -2 0 0 0 1.57</pose></waypoint>"
                 "<waypoint><time>4.5</time><pose>0 2 0 0 0 1.57</pose></waypoint>"
                 "</trajectory></script></actor>"),
      {}, &warnings);
  ASSERT_EQ(w.actors.size(), 1u);
  const Actor& a = w.actors[0];
  EXPECT_EQ(a.name, "walker");
  EXPECT_FALSE(a.loop);
  EXPECT_DOUBLE_EQ(a.delay_start, 1.5);
  ASSERT_EQ(a.trajectories.size(), 2u);
  EXPECT_DOUBLE_EQ(a.trajectories[0].tension, 0.2);
  EXPECT_EQ(a.trajectories[1].id, 1);
  EXPECT_NEAR(a.trajectories[0].waypoints[1].yaw, -1.57, 1e-9);
  EXPECT_DOUBLE_EQ(ScriptLength(a), 6.5);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
}

void ExpectRefusal(const std::string& actors, const std::string& needle) {
  try {
    LoadSdfWorld(WriteWorld(actors), {}, nullptr);
    ADD_FAILURE() << "no error for " << actors;
  } catch (const WorldError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("actor_test.world:"), std::string::npos) << e.what();
  }
}

TEST(ActorTest, BadScriptsAreRefusedOrWarnedAboutByName) {
  ExpectRefusal("<actor name='p'><script><trajectory id='3'/></script></actor>",
                "<actor name=\"p\"> <trajectory id=\"3\"> has no <waypoint>");
  ExpectRefusal("<actor name='p'><script><trajectory id='0'>"
                "<waypoint><time>2</time><pose>0 0 0 0 0 0</pose></waypoint>"
                "<waypoint><time>1</time><pose>1 0 0 0 0 0</pose></waypoint>"
                "</trajectory></script></actor>",
                "waypoint times must increase");
  ExpectRefusal("<actor name='p'><script><trajectory id='0' tension='2'>"
                "<waypoint><time>0</time><pose>0 0 0 0 0 0</pose></waypoint>"
                "</trajectory></script></actor>",
                "tension");
  ExpectRefusal("<actor name='p'><script><trajectory id='0'>"
                "<waypoint><pose>0 0 0 0 0 0</pose></waypoint></trajectory></script></actor>",
                "has no <time>");
  ExpectRefusal("<actor name='p'/><actor name='p'/>", "two actors named 'p'");
  std::vector<std::string> warnings;
  LoadSdfWorld(WriteWorld("<actor name='p'><script><speed>2</speed><trajectory id='0'>"
                          "<waypoint><time>0</time><pose>0 0 0 0 0 0</pose></waypoint>"
                          "</trajectory></script></actor>"),
               {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("<actor name=\"p\">: ignoring unknown <script> element <speed>"),
            std::string::npos)
      << warnings[0];
}

TEST(ActorTest, LoadsASocialForcePedestrian) {
  std::vector<std::string> warnings;
  const World w = LoadSdfWorld(
      WriteWorld("<actor name='visitor'><pose>-3 1 0 0 0 0</pose>"
                 "<plugin name='walk' filename='libminibot3d_social_force.so'><goal>3 1</goal>"
                 "<goal>-3 1</goal><desired_speed>1.2</desired_speed><goal_radius>0.4"
                 "</goal_radius></plugin></actor>"),
      {}, &warnings);
  ASSERT_EQ(w.actors.size(), 1u);
  const Actor& a = w.actors[0];
  EXPECT_TRUE(a.social_force);
  ASSERT_EQ(a.social.goals.size(), 2u);
  EXPECT_EQ(a.social.goals[0], Eigen::Vector2d(3, 1));
  EXPECT_DOUBLE_EQ(a.social.desired_speed, 1.2);
  EXPECT_DOUBLE_EQ(a.social.goal_radius, 0.4);
  EXPECT_DOUBLE_EQ(a.x, -3.0);
  EXPECT_TRUE(warnings.empty());
  ExpectRefusal("<actor name='q'><plugin name='w' filename='libminibot3d_social_force.so'>"
                "<desired_speed>1</desired_speed></plugin></actor>",
                "<actor name=\"q\"> social force plugin: no <goal>");
  ExpectRefusal("<actor name='q'><plugin name='w' filename='libminibot3d_social_force.so'>"
                "<goal>1</goal></plugin></actor>",
                "<goal> must be two numbers");
}

SimulatorOptions Options(const std::string& physics) {
  SimulatorOptions o;
  o.physics = physics;
  o.cmd_timeout = 1e6;
  o.actor_radius = 0.25;
  return o;
}

class ActorSimTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ActorSimTest, TheLaserAndTheCameraSeeAnActorWhereItIsAtTheTime) {
  // An actor crossing 2 m ahead of the robot, from y = -3 to y = 3 in 6 s: at t = 3 s it is on
  // the robot's axis.
  World world = testing::MakeRoom(4.0);
  world.actors.push_back(Walker({Wp(0, 2, -3), Wp(6, 2, 3)}));
  Simulator sim(ParseRobotModel(testing::SensingDiffDriveUrdf()), std::move(world), Options(GetParam()));
  std::vector<float> ranges;
  sim.TakeScan(0, &ranges);
  EXPECT_NEAR(ranges[90], 4.0, 1e-2);  // the room's wall: the actor is far to the side
  while (sim.time() < 3.0 - 1e-9) sim.Step();
  const ActorState& s = sim.actor_state(0);
  EXPECT_NEAR(s.y, 0.0, 1e-9);
  sim.TakeScan(0, &ranges);
  EXPECT_NEAR(ranges[90], 2.0 - 0.25, 2e-3);
  DepthFrame frame;
  sim.TakeFrame(0, &frame);
  EXPECT_NEAR(frame.depth[15 * 41 + 20], 2.0 - 0.25 - 0.16, 2e-3);
}

TEST_P(ActorSimTest, ARobotDrivingIntoAnActorIsHeldAndReportsItsName) {
  World world = testing::MakeRoom(4.0);
  Actor standing;
  standing.name = "visitor";
  standing.x = 1.0;
  world.actors.push_back(standing);
  Simulator sim(ParseRobotModel(testing::SensingDiffDriveUrdf()), std::move(world), Options(GetParam()));
  sim.SetCommand(0.3, 0.0);
  while (sim.time() < 5.0) sim.Step();
  // The body's front (0.15 m ahead of the centre) stops at the actor's surface, 0.75 m ahead.
  EXPECT_LT(sim.true_pose().x, 1.0 - 0.25 - 0.15 + 1e-3);
  EXPECT_GT(sim.true_pose().x, 1.0 - 0.25 - 0.15 - 0.02);
  const auto events = sim.TakeCollisionEvents();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].shape_name, "actor visitor");
  std::string what;
  EXPECT_TRUE(sim.PoseCollides(Pose2{1.2, 0.0, 0.0}, &what));
  EXPECT_EQ(what, "actor visitor");
}

TEST_P(ActorSimTest, ASocialForceCrowdWalksReplaysExactlyAndKeepsOffTheWalls) {
  // Two groups of three crossing a 4 m room (inner faces at +-2) in opposite directions, in
  // interleaved lanes, past a robot standing at the side.
  auto run = [&] {
    World world = testing::MakeRoom(4.0);
    for (int k = 0; k < 6; ++k) {
      Actor a;
      a.name = "p" + std::to_string(k);
      const double side = k % 2 ? 1.0 : -1.0;
      a.x = 1.5 * side, a.y = -0.6 + 0.3 * k;
      a.social_force = true;
      a.social.goals = {Eigen::Vector2d(-a.x, a.y), Eigen::Vector2d(a.x, a.y)};
      world.actors.push_back(a);
    }
    SimulatorOptions options = Options(GetParam());
    options.spawn = Pose2{0.0, -1.5, 0.0};
    Simulator sim(ParseRobotModel(testing::SensingDiffDriveUrdf()), std::move(world), options);
    double nearest_wall = 1e9;
    std::vector<double> trace;
    std::vector<double> farthest(sim.actor_count(), 0.0);  // from the start
    while (sim.time() < 30.0) {
      sim.Step();
      for (size_t k = 0; k < sim.actor_count(); ++k) {
        const ActorState& a = sim.actor_state(k);
        nearest_wall = std::min(nearest_wall, 2.0 - std::max(std::abs(a.x), std::abs(a.y)));
        farthest[k] = std::max(farthest[k], std::hypot(a.x - sim.world().actors[k].x,
                                                       a.y - sim.world().actors[k].y));
        if (sim.steps() % 1000 == 0) trace.insert(trace.end(), {a.x, a.y});
      }
    }
    EXPECT_GT(nearest_wall, 0.25 - 0.05) << "a pedestrian walked into a wall";
    // Each got through the others to the far side (its goal 3 m away, reached within 0.3 m).
    for (size_t k = 0; k < farthest.size(); ++k) EXPECT_GT(farthest[k], 2.7 - 1e-9) << k;
    return std::make_pair(trace, sim.collision_count());
  };
  const auto a = run(), b = run();
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.second, b.second);
}

INSTANTIATE_TEST_SUITE_P(Backends, ActorSimTest, ::testing::Values("kinematic", "bullet"));

}  // namespace
}  // namespace minibot3d_sim
