// The local planner's cost term for obstacles that move (people), from a
// short-horizon prediction at constant velocity of the tracked obstacles
// (tracking/obstacle_tracker.h), as the velocity-obstacle family scores a
// candidate command against where the others will be rather than where they
// are (Fiorini & Shiller, "Motion planning in dynamic environments using
// velocity obstacles", IJRR 17(7), 1998; in a DWA as Seder & Petrovic,
// "Dynamic window based approach to mobile robot motion control in the
// presence of moving obstacles", ICRA 2007).
//
// Every pose after the start of a rollout and of its braking tail
// (trajectory.h) has a time t after now; up to moving_obstacle_horizon each
// obstacle (the outline the sensor saw of it, or a disc) is moved to where it
// will be at t, and d(t) is the distance from the footprint at the pose to it
// (negative when they overlap).
//  - Illegal: d(t) < moving_obstacle_margin + moving_obstacle_deviation * t
//    on the way the command still has to stop (its first control period and
//    its braking tail): the margin grows with the time ahead at the speed at
//    which a person may stray from the constant-velocity prediction (slowing,
//    turning, stepping towards the robot), as the reachable sets of passive
//    motion safety do (Bouraine, Fraichard & Salhi, "Provably safe
//    navigation for mobile robots with limited field-of-views in dynamic
//    environments", Autonomous Robots 32(3), 2012); unless the
//    trajectory brakes to a standstill (kind kStop) or, once the planner has
//    waited (set_backing_out), the obstacle is not closing in on a robot
//    standing still and the trajectory keeps farther from it than standing
//    would (backing out of a standoff with a person who stopped; sliding
//    along one is never enough).  As for static
//    obstacles (trajectory.h), a command is taken only if the robot can still
//    stop short of every predicted position, so where contact cannot be
//    avoided (a person walking into the robot) the robot is standing when it
//    happens: the planner yields (dwa_planner.h).  Later poses of the
//    rollout only cost, so that people passing near the path ahead do not
//    freeze the robot.
//  - Cost: the largest (1 - d(t) / personal_distance), weighted by
//    (1 - t / horizon) (later predictions are less sure), over the
//    trajectory: 0 beyond personal_distance, 1 at contact now.
#ifndef MINIBOT3D_NAVIGATION_DWA_MOVING_OBSTACLE_CRITIC_H_
#define MINIBOT3D_NAVIGATION_DWA_MOVING_OBSTACLE_CRITIC_H_

#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/dwa/trajectory_critic.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

// A moving obstacle now (the costmap's frame) and its velocity: the points
// seen of it (`outline`, relative to `position`), or, with no outline, a disc
// of `radius` round `position`.
struct MovingObstacle {
  Point2 position;
  Point2 velocity;  // m/s
  double radius = 0.0;
  std::vector<Point2> outline;
};

class MovingObstacleCritic : public TrajectoryCritic {
 public:
  MovingObstacleCritic(const Footprint& footprint, double horizon, double margin,
                       double deviation, double personal_distance)
      : footprint_(footprint), horizon_(horizon), margin_(margin), deviation_(deviation),
        personal_distance_(personal_distance) {}
  std::string name() const override { return "MovingObstacle"; }
  bool Prepare(const Pose2& pose, const Twist2& velocity, const Path& plan,
               const Costmap2D& costmap) override;
  double Score(const Trajectory& traj) override;

  // The obstacles for the next cycles (until set again).
  void SetObstacles(const std::vector<MovingObstacle>& obstacles) { obstacles_ = obstacles; }
  // Whether trajectories may leave the margin of an obstacle that is not
  // closing in (after a wait).
  void set_backing_out(bool allowed) { backing_out_ = allowed; }
  const std::vector<MovingObstacle>& obstacles() const { return obstacles_; }
  // Distance (m) from the footprint at `pose` to obstacle `k` moved on for `t`
  // s; negative when they overlap.
  double Distance(const Pose2& pose, size_t k, double t) const;

 private:
  // Scores one pose at time t into *worst; false if it comes within the
  // margin where that is `binding`.
  bool ScorePose(const Pose2& pose, double t, bool binding, double* worst) const;

  Footprint footprint_;
  double horizon_, margin_, deviation_, personal_distance_;
  std::vector<MovingObstacle> obstacles_;
  Pose2 start_;
  bool backing_out_ = false;
};

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_MOVING_OBSTACLE_CRITIC_H_
