// Recovery behaviours (nav_core::RecoveryBehavior), run by the navigation
// executive when planning or control keeps failing or the robot oscillates.
//
// Lifecycle: Start() once when the executive enters the recovery, then Step()
// every control cycle until it returns false (finished); the command it writes
// is sent to the base.  The two behaviours of move_base's default list:
//  - ClearCostmapRecovery: resets the obstacle layers outside a square of
//    side reset_distance centred on the robot (clear_costmap_recovery);
//  - RotateRecovery: turns in place one full turn so the sensors see all
//    around (rotate_recovery), stopping early if the footprint would hit
//    something it can see on the local costmap.
//  - BackOutRecovery (back_out, not in ROS): reverses along the poses the
//    robot drove through, newest first, so a robot that squeezed into a spot
//    it cannot leave forwards (a pocket, a gap narrower than its footprint
//    turns in) leaves it the way it came: ground it has already covered.
//  - WaitRecovery (wait, not in ROS; Nav2's Wait behaviour, ended early): when
//    no path to the goal exists, stands still until one exists again
//    or wait_duration has passed, so a robot whose only way is shut by someone
//    standing in a doorway waits for them and then replans, instead of
//    clearing its costmaps and turning on the spot beside them.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_

#include <functional>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

// What a recovery (and the executive) sees each cycle.
struct RobotState {
  double time = 0.0;      // seconds, the simulator's clock
  Pose2 global_pose;     // in the global costmap's frame (map)
  Pose2 local_pose;      // in the local costmap's frame (odom)
  Twist2 velocity;       // in the robot's frame
  const Costmap2D* global_costmap = nullptr;
  const Costmap2D* local_costmap = nullptr;
  // Poses the robot drove through, in the local frame, oldest first (the
  // executive records them; nullptr when nobody does).
  const std::vector<Pose2>* trail = nullptr;
  // Set while recovering because the local planner found no command (not
  // because of oscillation or a planning failure).
  bool control_failed = false;
  // Set while recovering because the planner found no path between a start
  // and a goal that are both free (not because either is in an obstacle).
  bool no_path = false;
  // Whether the global planner finds a path from the robot to the goal on the
  // global costmap as it is now (the executive supplies it while recovering;
  // empty when nobody can tell).
  std::function<bool()> path_exists;
};

class RecoveryBehavior {
 public:
  virtual ~RecoveryBehavior() = default;
  virtual std::string name() const = 0;
  // Whether it can help with this failure at all; the executive passes over one
  // that cannot, to the next in the list, as if it had run.
  virtual bool Applies(const RobotState& /*state*/) const { return true; }
  virtual void Start(const RobotState& state) = 0;
  virtual bool Step(const RobotState& state, Twist2* cmd) = 0;
  // After Step returned false: what it did and why it ended, for the log
  // ("" when there is nothing to say).
  virtual std::string outcome() const { return ""; }
};

class ClearCostmapRecovery : public RecoveryBehavior {
 public:
  // `clear` is called with reset_distance once, at Start.
  ClearCostmapRecovery(std::string name, double reset_distance,
                       std::function<void(double)> clear);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;

 private:
  std::string name_;
  double reset_distance_;
  std::function<void(double)> clear_;
};

struct RotateRecoveryOptions {
  double max_rotational_vel = 1.0;     // rad/s (max_vel_theta)
  double min_rotational_vel = 0.4;     // rad/s (min_in_place_vel_theta)
  double acc_lim_th = 3.2;             // rad/s^2
  double frequency = 20.0;             // Hz, the control rate
  double sim_granularity = 0.017;      // rad between footprint checks
  double tolerance = 0.10;             // rad short of a full turn = done
  double timeout = 30.0;               // s; a turn that does not progress stops
};

class RotateRecovery : public RecoveryBehavior {
 public:
  RotateRecovery(std::string name, const RotateRecoveryOptions& options,
                 Footprint footprint);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;

 private:
  std::string name_;
  RotateRecoveryOptions options_;
  Footprint footprint_;
  double start_time_ = 0.0;
  double last_yaw_ = 0.0;
  double turned_ = 0.0;
};

struct BackOutOptions {
  double distance = 0.6;          // m from the start, along the trail
  double vel = 0.15;              // m/s backwards
  double max_rotational_vel = 1.0;  // rad/s while straightening up
  double min_rotational_vel = 0.4;  // rad/s at least when turning on the spot
  double timeout_factor = 3.0;    // gives up after timeout_factor * route length / vel + 2 s
};

// Backs the robot out along the way it came.
// When: after a control failure (state.control_failed: the way ahead is
// blocked), or after any other trigger when the robot cannot turn on the spot
// where it is (its footprint at one of 16 headings touches a lethal cell on
// the local costmap): a robot that drove into a dead-end slot oscillates
// there, since the local planner finds no move out.  Otherwise (oscillation
// or a planning failure with room to turn) it does nothing: reversing would
// undo progress the robot may still make.
// How: reverse pure pursuit along the trail (Coulter, "Implementation of the
// Pure Pursuit Path Tracking Algorithm", CMU-RI-TR-92-01, driven backwards).
// Start takes the trail poses, newest first, up to the first one `distance`
// from the robot in a straight line, so a robot that wiggled its way into a
// spot gets that far out of it — or, if it could not turn on the spot there,
// on to the first trail pose where it can, at most 3 * distance away: a
// dead-end slot is left, not just reversed in.  Each Step steers the robot's
// back at the first of them at least 0.1 m away: turning on the spot while it
// lies more than 0.6 rad off the back, else reversing at `vel` on the arc
// through it (w = v * 2 dy / d^2).  Positions only: the turns of the way in
// are not replayed.
// It stops at the last pose, on timeout, or when the footprint 0.2 s ahead
// touches a lethal cell on the local costmap and either that pose is off the
// trail, or the cell lies in the back half of the footprint (the way it is
// going) more than a cell inside its sides: poses it drove through are free,
// so a cell grazed by a side or left at the front is rounding (a wall mapped a
// cell thick, a desk passed 3 cm away), while one behind it is something new.
// outcome() says how far it backed and why it stopped.
class BackOutRecovery : public RecoveryBehavior {
 public:
  BackOutRecovery(std::string name, const BackOutOptions& options, Footprint footprint);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;
  std::string outcome() const override { return outcome_; }
  // The poses still to back through (for tests and logs).
  const std::vector<Pose2>& route() const { return route_; }

 private:
  bool OnTrail(const Pose2& pose) const;
  bool CanTurnAt(const Costmap2D* costmap, const Pose2& pose) const;
  // No lethal cell under the back half of the footprint at `pose`, its sides
  // moved in by one cell.
  bool BackClear(const Costmap2D& costmap, const Pose2& pose) const;
  std::string name_;
  BackOutOptions options_;
  Footprint footprint_;
  std::vector<Pose2> route_;  // newest first
  double route_length_ = 0.0;  // m along the route
  Pose2 start_pose_;
  std::string outcome_;
  size_t next_ = 0;
  double start_time_ = 0.0;
};

struct WaitOptions {
  double duration = 30.0;      // s; the longest wait (wait_duration)
  double check_period = 0.5;   // s between two checks for a path
  double clearance = 0.45;     // m kept in front of the footprint while waiting
  double backoff_vel = 0.15;   // m/s backwards while making room
  double max_backoff = 1.0;    // m; the farthest it backs off
};

// Waits for the way to open.
// When: after a planning failure with no path between a free start and a
// free goal (state.no_path): something shuts the only way (a person in a
// doorway, a trolley left in a corridor). After a control failure or
// oscillation a path exists, and a goal or start in an obstacle is not a way
// that opens by waiting: then it does not apply (Applies) and does nothing.
// How: first it makes room. A robot that drove up to whoever blocks the way
// (the old plan is followed for planner_patience after replanning fails)
// backs straight off while anything lethal on the local costmap lies within
// `clearance` of the front half of its footprint (0.45 m: the edge of the
// intimate zone of proxemics, Hall 1966), for at most max_backoff, stopping
// where the footprint a step behind would touch a lethal cell or leave the
// costmap. Then it commands zero while the costmaps keep updating from the
// sensors. Every check_period it asks state.path_exists and ends as soon as a
// path exists (the executive then plans and drives on), or when `duration`
// has passed (the next recovery in the list runs). outcome() says which,
// after how long, and how far it backed off.
class WaitRecovery : public RecoveryBehavior {
 public:
  WaitRecovery(std::string name, const WaitOptions& options, Footprint footprint);
  std::string name() const override { return name_; }
  bool Applies(const RobotState& state) const override { return state.no_path; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;
  std::string outcome() const override { return outcome_; }
  // Distance (m) from the footprint at `pose` to the nearest lethal cell of
  // `costmap` in front of the robot's centre (infinity when none is within
  // `range`).
  double ClearanceAhead(const Costmap2D& costmap, const Pose2& pose, double range) const;

 private:
  std::string name_;
  WaitOptions options_;
  Footprint footprint_;
  double circumscribed_ = 0.0;
  bool needed_ = false;
  bool backing_ = false;
  Pose2 start_pose_;
  double start_time_ = 0.0;
  double next_check_ = 0.0;
  std::string outcome_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
