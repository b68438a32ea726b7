// Dynamic Window Approach local planner (Fox, Burgard & Thrun, "The dynamic
// window approach to collision avoidance", IEEE Robotics & Automation
// Magazine 4(1):23-33, 1997), as base_local_planner's TrajectoryPlannerROS
// runs it with dwa = true, for a non-holonomic (skid-steer) base.
//
// Each control cycle:
//  1. Prune the plan to the pose closest to the robot (prune_plan).
//  2. Goal: within xy_goal_tolerance (latched if latch_xy_goal_tolerance),
//     brake to a stop, then rotate in place to the goal yaw at
//     [min_in_place_vel_theta, max_vel_theta], slowing at acc_lim_theta so
//     that it stops inside yaw_goal_tolerance; zero once within it.  If that
//     turn, from where the robot is, would put the footprint on a lethal cell
//     (the robot reached the tolerance between two table legs, say), it first
//     goes on following the plan towards the goal itself (step 4), checking
//     again every cycle, and turns as soon as the turn is clear; it gives up
//     only when the turn is blocked within a cell of the goal.
//  3. If the plan ahead (the first plan pose heading_lookahead or more from
//     the robot) is more than rotate_to_path_angle off the heading (a quarter
//     of it when the robot is at creeping speed, max(min_vel_x, |escape_vel|),
//     or stopped), brake and rotate in place towards it until it is within an
//     eighth of rotate_to_path_angle.
//  4. Otherwise sample the dynamic window (trajectory.h): vx_samples x
//     (vtheta_samples + the straight command; with max_centripetal_acc set,
//     each speed's theta samples span only the arcs with |vx * vtheta| within
//     it) and vtheta_samples in-place rotations, roll each out for sim_time and score it with the critics
//     (critics.h):
//       path_distance_bias * path_dist + goal_distance_bias * goal_dist
//       + occdist_scale * occ_cost      (x resolution when meter_scoring)
//     The cheapest legal trajectory wins.  An in-place rotation replaces it
//     when it costs no more (the one whose end pose looks closest to the
//     goal, heading_lookahead ahead), but only if that is closer than from
//     the current pose, its direction is not forbidden by the oscillation
//     flags, it does not leave the robot more than rotate_to_path_angle off
//     the plan (step 3 would turn it back), and the robot has not yet turned
//     a full circle without moving oscillation_reset_dist.
//     (TrajectoryPlanner takes any rotation when nothing else is legal, and
//     can spin in front of an obstacle for ever.)
//     A trajectory is also scored against the moving obstacles' predicted
//     positions (moving_obstacle_critic.h): moving_obstacle_scale * cost,
//     illegal when its motion brings the footprint within
//     moving_obstacle_margin of one.
//  5. Nothing legal and some trajectory refused for a moving obstacle: brake
//     (standing, zero) and wait for the obstacle to pass (Mode kYield), which
//     is not a failure.  After moving_obstacle_wait s of it, the robot may
//     back away from an obstacle that has stopped within the margin (a
//     person facing it in a standoff).
//     Nothing legal otherwise: if moving, brake at the acceleration limits (always
//     admissible after an admissible command).  If stopped with the
//     footprint already in the inscribed band (stuck), back up at escape_vel
//     (TrajectoryPlanner's escape; forward trajectories stay off until the
//     robot has moved escape_reset_dist or turned escape_reset_theta),
//     provided that keeps the footprint off lethal cells.  A robot that is
//     clear but blocked (stopped in front of an obstacle on the plan) gets a
//     ControlError instead: TrajectoryPlanner would back up and come forward
//     again, or wander off along the obstacle; move_base's recovery and
//     replanning are the better cure.
//
// Safety: a trajectory is legal only if neither its rollout nor its braking
// tail (the command held for one control period, then braking at acc_lim_x
// and acc_lim_theta) puts the footprint's outline on a lethal or unknown cell
// or off the map, or, faster than creeping (max(min_vel_x, |escape_vel|)),
// nearer to a lethal cell than a margin growing with speed (the whole
// inscribed band, cost 253, from full_margin_vel on); speeds are capped so a
// rollout is at least as long as the stopping distance: Fox et al.'s
// admissible velocities, v <= sqrt(2 * dist(v, w) * acc_lim_x).  So the
// planner slows down for an obstacle it can see whatever max_vel_x, sim_time
// and controller_frequency are.  When
// ComputeVelocity throws, the caller must command zero (move_base does): the
// previous command was chosen so that braking from here is collision-free.
//
// Inputs are in the local costmap's frame: robot pose, robot velocity (in the
// robot frame, from odometry), the global plan transformed into that frame,
// the local costmap (robot footprint already cleared, inflated).
#ifndef MINIBOT3D_NAVIGATION_DWA_DWA_PLANNER_H_
#define MINIBOT3D_NAVIGATION_DWA_DWA_PLANNER_H_

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/dwa/critics.h"
#include "minibot3d_navigation/dwa/dwa_options.h"
#include "minibot3d_navigation/dwa/local_planner.h"
#include "minibot3d_navigation/dwa/moving_obstacle_critic.h"
#include "minibot3d_navigation/dwa/trajectory.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

class DwaPlanner : public LocalPlanner {
 public:
  // What the last ComputeVelocity did.
  enum class Mode {
    kNone,
    kFollowPath,    // best sampled / in-place / braking trajectory
    kEscape,        // backing up at escape_vel
    kRotateToPath,  // plan far off the heading: braking / turning on the spot
    kApproachGoal,  // in xy tolerance, going on towards the goal, where it can turn
    kStopAtGoal,    // in xy tolerance, braking before the final rotation
    kRotateToGoal,  // in xy tolerance, turning to the goal yaw
    kAtGoal,        // in xy and yaw tolerance: zero command
    kYield,         // every way on meets a moving obstacle: braking / standing
  };

  struct CycleStats {
    Mode mode = Mode::kNone;
    int evaluated = 0;  // trajectories generated and scored
    // Rejections per critic, in the order of critics(): Oscillation,
    // PathDist, GoalDist, ObstacleCost, MovingObstacle.
    std::array<int, 5> rejected{};
    int pruned = 0;  // skipped once their partial cost exceeded the best
    // Legal in-place rotations not taken: not turning towards the goal, the
    // robot already turned a full circle on the spot, or they would leave it
    // facing more than rotate_to_path_angle away from the plan.
    int rotations_refused = 0;
  };

  // Throws std::invalid_argument if `options` fail ValidateDwaOptions or the
  // footprint has fewer than 3 points.
  DwaPlanner(const DwaOptions& options, const Footprint& footprint);

  std::string name() const override { return "dwa_local_planner"; }
  void Reset() override;
  Twist2 ComputeVelocity(const Pose2& pose, const Twist2& velocity,
                          const Path& plan, const Costmap2D& costmap) override;
  bool IsGoalReached(const Pose2& pose, const Twist2& velocity,
                     const Path& plan) override;

  const DwaOptions& options() const { return options_; }
  // The trajectory behind the last command (for the local_plan topic); empty
  // poses when the command was not simulated (at goal).
  const Trajectory& last_trajectory() const { return best_; }
  const CycleStats& last_stats() const { return stats_; }
  bool Yielding() const override { return stats_.mode == Mode::kYield; }
  // The pruned plan of the last cycle.
  const Path& pruned_plan() const { return pruned_; }
  // Local goal of the last cycle's goal-distance grid.
  Point2 local_goal() const { return goal_critic_.local_goal(); }
  const TrajectoryGenerator& generator() const { return generator_; }
  // The moving obstacles (in the costmap's frame, now) the next cycles
  // avoid, until set again (moving_obstacle_critic.h).
  void SetMovingObstacles(const std::vector<MovingObstacle>& obstacles) {
    moving_critic_.SetObstacles(obstacles);
  }

 private:
  void CheckInputs(const Pose2& pose, const Twist2& velocity,
                   const Path& plan, const Costmap2D& costmap) const;
  void PrunePlan(const Pose2& pose, const Path& plan,
                 const Costmap2D& costmap);
  bool Stopped(const Twist2& velocity) const;
  // max(min_vel_x, |escape_vel|): the speed of the way out, and below which
  // the robot turns to the path on the spot at a quarter of
  // rotate_to_path_angle.
  double CreepSpeed() const;
  // The braking trajectory from `velocity` at the acceleration limits, with
  // the first period's braking command.
  void GenerateBraking(const Pose2& pose, const Twist2& velocity,
                       Trajectory* traj) const;
  // Braking command; its trajectory becomes last_trajectory().
  Twist2 Brake(const Pose2& pose, const Twist2& velocity, Mode mode,
                const Costmap2D& costmap);
  // In-place rotation towards `target_yaw`, stopping within `tolerance`.
  // Returns false if that rotation collides (best_ then holds it); brakes
  // instead, setting yielded_, if it would meet a moving obstacle.
  bool RotateTowards(const Pose2& pose, const Twist2& velocity,
                     double target_yaw, double tolerance,
                     const Costmap2D& costmap, Twist2* command);
  // Whether turning on the spot from `pose` to `target_yaw` (the shorter way)
  // keeps the footprint off lethal cells.
  bool TurnIsClear(const Pose2& pose, double target_yaw, const Costmap2D& costmap);
  // Angle from the heading to the first plan pose heading_lookahead or more
  // from the robot; NaN if that pose is off the costmap.
  double PathHeadingError(const Pose2& pose, const Costmap2D& costmap) const;
  // The best-scoring admissible trajectory (see the header comment, steps 4
  // and 5), or the escape; throws ControlError when there is neither.
  Twist2 FollowPath(const Pose2& pose, const Twist2& velocity,
                     const Costmap2D& costmap);

  // The trajectory FollowPath has chosen so far (held in best_).
  struct Choice {
    bool found = false;
    double cost = std::numeric_limits<double>::infinity();
  };
  // Sets the critics' scales for this costmap and prepares them for the cycle.
  void PrepareCritics(const Pose2& pose, const Twist2& velocity,
                      const Costmap2D& costmap);
  // Ends an escape once the robot has moved escape_reset_dist or turned
  // escape_reset_theta since it began.
  void UpdateEscape(const Pose2& pose);
  // One pass of the search: pass 0 under the speed's margin, pass 1 (lethal
  // cells only) for a way out of the inscribed band.
  void SearchPass(int pass, const Pose2& pose, const Twist2& velocity,
                  const VelocityWindow& win, const Costmap2D& costmap,
                  Choice* choice);
  void SampleArcs(int pass, const Pose2& pose, const Twist2& velocity,
                  const VelocityWindow& win, const Costmap2D& costmap,
                  Choice* choice);
  void SampleEscapeArcs(const Pose2& pose, const Twist2& velocity,
                        const VelocityWindow& win, const Costmap2D& costmap,
                        Choice* choice);
  void SampleRotations(int pass, const Pose2& pose, const Twist2& velocity,
                       const VelocityWindow& win, const Costmap2D& costmap,
                       Choice* choice);
  // Takes the legal in-place rotation in candidate_ if it turns the robot
  // towards the goal (pass 0) and nearer to it than the rotations so far.
  void ConsiderRotation(int pass, const Costmap2D& costmap, double ahead_now,
                        double* heading_dist, Choice* choice);
  // Whether candidate_ ends with the outline out of the inscribed band (pass 1
  // only; any end will do in pass 0).
  bool ExitsBand(int pass, const Costmap2D& costmap) const;
  // candidate_ becomes the choice.
  void Take(Choice* choice);
  void TakeIfBetter(int pass, const Costmap2D& costmap, Choice* choice);
  // Nothing legal: backs up at escape_vel when stuck, else throws ControlError.
  Twist2 EscapeOrFail(const Pose2& pose, const Twist2& velocity,
                      const Costmap2D& costmap);
  // Scores `candidate_` into its cost: negative if illegal, or +infinity if
  // pruned (partial cost above `bound`).
  double Evaluate(double bound);
  std::string Diagnose(const Pose2& pose, const Costmap2D& costmap) const;
  // "nearest obstacle 0.12 m ahead of the footprint (bearing 5 deg)".
  std::string NearestObstacle(const Pose2& pose,
                              const Costmap2D& costmap) const;

  const DwaOptions options_;
  const Footprint footprint_;
  TrajectoryGenerator generator_;
  OscillationCritic oscillation_critic_;
  PathDistCritic path_critic_;
  GoalDistCritic goal_critic_;
  ObstacleCostCritic obstacle_critic_;
  MovingObstacleCritic moving_critic_;
  std::array<TrajectoryCritic*, 5> critics_;

  Trajectory best_;
  Trajectory candidate_;
  Path pruned_;
  CycleStats stats_;

  bool latched_ = false;
  Pose2 latched_goal_;
  bool rotating_to_goal_ = false;
  bool rotating_to_path_ = false;
  bool escaping_ = false;
  // This cycle's turn on the spot met a moving obstacle and braked instead.
  bool yielded_ = false;
  // Consecutive cycles in Mode::kYield (moving_obstacle_wait).
  int yield_cycles_ = 0;
  Pose2 escape_pose_;
  // Rotation on the spot since the robot last moved oscillation_reset_dist.
  Pose2 spin_anchor_;
  double last_yaw_ = 0.0;
  double spun_in_place_ = 0.0;
};

const char* DwaModeName(DwaPlanner::Mode mode);

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_DWA_PLANNER_H_
