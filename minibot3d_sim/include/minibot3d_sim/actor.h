// Actors: people and other things that move through a world on a script, as SDF's <actor> with
// <script> and <trajectory> waypoints describes them and Gazebo plays them.
//
// Gazebo's playback (gazebo::physics::Actor with common::PoseAnimation):
//  * the trajectories of a script play one after another, in the order of the file, each lasting
//    its last waypoint's <time>; the script starts <delay_start> s after the world starts and, with
//    <loop> (the default), starts over when the last trajectory ends; without it the actor stays
//    at the end. Before it starts the actor stands at its first waypoint.
//  * between two waypoints, the position follows a cubic Hermite spline through all of the
//    trajectory's waypoints (a cardinal spline: the tangent at waypoint i is
//    (1 - tension) (p[i+1] - p[i-1]) / 2, at an open end (1 - tension) of half the neighbouring
//    segment, and the two ends share one tangent when the trajectory returns to its start),
//    parameterised by the fraction of the time between the two waypoints; the heading turns by
//    spherical interpolation, i.e. along the shorter way, at a constant rate.
// <auto_start> false waits for a trigger that minibot3d never sends: such an actor stands at its
// first waypoint. An actor with the social-force plugin (social_force.h) walks between its goals
// instead, reacting to the others, the robots and the walls. An actor has no collision in Gazebo; here it is an upright cylinder (radius and
// height from the simulator's options) standing on the floor at its position.
#ifndef MINIBOT3D_SIM_ACTOR_H_
#define MINIBOT3D_SIM_ACTOR_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_sim/social_force.h"

namespace minibot3d_sim {

struct ActorWaypoint {
  double time = 0.0;  // s from the start of its trajectory
  double x = 0.0, y = 0.0, z = 0.0, yaw = 0.0;
};

struct ActorTrajectory {
  int id = 0;
  std::string type;
  double tension = 0.0;
  std::vector<ActorWaypoint> waypoints;  // at least one, times increasing
  double duration() const { return waypoints.back().time; }
};

struct Actor {
  std::string name;
  bool loop = true;
  double delay_start = 0.0;
  bool auto_start = true;
  std::vector<ActorTrajectory> trajectories;  // empty: the actor stands at `x, y, yaw`
  double x = 0.0, y = 0.0, yaw = 0.0;         // its <pose>: where it stands or starts walking
  // A pedestrian of the social force model (its <plugin filename="libminibot3d_social_force.so">):
  // starts at its pose and walks between social.goals; the script is not used.
  bool social_force = false;
  SocialForceAgentOptions social;
};

// Where an actor is and how it moves (world frame, m, rad, m/s, rad/s).
struct ActorState {
  double x = 0.0, y = 0.0, yaw = 0.0;
  double vx = 0.0, vy = 0.0, wz = 0.0;
};

// The actor's state `t` s after the world started.
ActorState ActorAt(const Actor& actor, double t);

// The whole script's length (s): the sum of its trajectories' durations.
double ScriptLength(const Actor& actor);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_ACTOR_H_
