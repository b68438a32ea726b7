// The move_base state machine, ROS-free: plan, control, recover, give up.
//
// Same states and rules as ROS move_base (move_base.cpp, executeCycle):
//  PLANNING     make a global plan; on success go to CONTROLLING.  A failure
//               is retried every cycle until planner_patience seconds pass
//               without a valid plan (or max_planning_retries is exceeded),
//               then CLEARING.
//  CONTROLLING  replan at planner_frequency (if > 0); succeed when the local
//               planner says the goal is reached; otherwise ask it for a
//               command.  When it finds none the executive replans, and after
//               controller_patience seconds without a valid command goes to
//               CLEARING.  If the robot has not moved oscillation_distance in
//               oscillation_timeout seconds it also goes to CLEARING.
//  CLEARING     run the next recovery behaviour; when it finishes, PLANNING.
//               With no behaviour left the goal is ABORTED, and the message
//               says what kept failing (the planner's or controller's own
//               error: which goal, which obstacle) — not just "failed".
// Not in ROS move_base, for getting through clutter: the executive keeps the
// robot's trail (poses driven through, local frame, loop-erased: a return to
// where it has been drops the loop since) for the back_out recovery; when
// control fails or the robot oscillates it remembers the stretch of plan it
// could not pass (a disc of blocked_radius round the plan point
// blocked_lookahead ahead, in the global frame) and plans round those discs
// for the rest of the goal — the pocket or gap is not tried again —
// forgetting them only if no plan exists without them; and it restarts the
// recovery list once the robot has driven recovery_reset_distance from where
// the last recovery began (move_base restarts it after any valid command).
// With wait_duration > 0, when replanning finds no path (someone stands in the
// only doorway), the old plan is followed only up to 0.45 m (proxemics'
// intimate zone) plus the circumscribed radius short of its first pose now
// inscribed or lethal, and the wait recovery (wait_recovery.h) asks PathExists
// whether the way has opened, by the stricter test SetOpenWayTest gives.
// Differences, on purpose: planning runs synchronously in the control cycle
// (our planners take milliseconds, and a simulator at 10x real time would
// otherwise see plans arrive at random points of sim time), and a goal off the
// global costmap is aborted at once, since no recovery can change that.
// Time is an input (simulator seconds), so the machine is tested without ROS.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_NAVIGATION_EXECUTIVE_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_NAVIGATION_EXECUTIVE_H_

#include <memory>
#include <string>
#include <vector>

#include "minibot3d_navigation/dwa/local_planner.h"
#include "minibot3d_navigation/move_base/move_base_options.h"
#include "minibot3d_navigation/move_base/recovery_behavior.h"
#include "minibot3d_navigation/planner/global_planner.h"

namespace minibot3d_navigation {
namespace nav {

enum class NavState { kIdle, kPlanning, kControlling, kClearing };
enum class GoalStatus { kNone, kActive, kSucceeded, kAborted };

const char* NavStateName(NavState state);

struct CycleResult {
  Twist2 cmd;                         // send this to the base
  GoalStatus status = GoalStatus::kNone;
  std::string message;                 // why it was aborted (or succeeded)
  bool new_plan = false;               // plan() changed this cycle
};

class NavigationExecutive {
 public:
  // The planners and recoveries are owned by the caller (the node keeps the
  // costmaps they act on) and must outlive the executive.
  NavigationExecutive(const MoveBaseOptions& options, GlobalPlanner* global_planner,
                      LocalPlanner* local_planner, std::vector<RecoveryBehavior*> recoveries);

  // Cells of this cost or more (up to lethal) count as closed when the wait
  // recovery asks whether the way to the goal has opened: the node gives the
  // inflated cost at the footprint's circumscribed radius, so a way counts as
  // open only where the robot fits at any heading, not through a gap beside
  // someone that only looks wide enough because the laser sees the front of
  // them. Cells within keep_radius (m; the circumscribed radius) of the robot
  // and of the goal are left as they are, so a robot standing close to a wall
  // can still start. Default: 253, the planner's own test.
  void SetOpenWayTest(uint8_t cost, double keep_radius) {
    open_way_cost_ = cost;
    open_way_keep_ = keep_radius;
  }

  // A new goal in the global frame replaces any current one (preemption).
  void SetGoal(const Pose2& goal, double time);
  // Drops the goal; the next Step returns a zero command and kNone.
  void Cancel();

  // One control cycle.  `global_to_local` is the pose of the global frame in
  // the local one (map in odom), used to hand the plan to the local planner.
  CycleResult Step(const RobotState& state, const Pose2& global_to_local);

  NavState state() const { return state_; }
  bool active() const { return state_ != NavState::kIdle; }
  const Pose2& goal() const { return goal_; }
  const Path& plan() const { return plan_; }        // global frame
  const Path& local_plan() const { return local_plan_; }  // last plan handed down, local frame
  const std::string& last_error() const { return last_error_; }
  // Poses driven through (local frame, oldest first) and the remembered
  // blocked places (global frame) of the current goal.
  const std::vector<Pose2>& trail() const { return trail_; }
  const std::vector<Point2>& blocked() const { return blocked_; }

 private:
  enum class Trigger { kPlanning, kControlling, kOscillation };

  bool TryPlan(const RobotState& state, double time);
  // A path from the robot to the goal on the global costmap as it is, cells of
  // open_way_cost or more closed (SetOpenWayTest; the plan is not kept): what
  // the wait recovery asks.
  bool PathExists(const RobotState& state);
  // Distance (m) along the plan from the robot to the first pose of cost
  // inscribed or more on the global costmap (infinity if none).
  double DistanceToShutPose(const RobotState& state) const;
  void RecordTrail(const Pose2& local_pose);
  void RememberBlocked(const RobotState& state);
  // The global costmap with the blocked discs made lethal (except round the
  // robot and the goal), in planning_costmap_.
  const Costmap2D& PlanningCostmap(const RobotState& state);
  // What the recoveries are told of the failure `trigger` (control_failed,
  // no_path) and how they ask for a path (path_exists, which refers to *state).
  void DescribeFailure(Trigger trigger, RobotState* state);
  CycleResult EnterClearing(Trigger trigger, const RobotState& state);
  CycleResult Abort(const std::string& message);

  const MoveBaseOptions options_;
  GlobalPlanner* global_planner_;
  LocalPlanner* local_planner_;
  std::vector<RecoveryBehavior*> recoveries_;

  NavState state_ = NavState::kIdle;
  Pose2 goal_;
  Path plan_;
  Path local_plan_;
  std::string last_error_;
  PlanningError::Code last_error_code_ = PlanningError::Code::kNoPath;
  double last_valid_plan_ = 0.0;
  double last_valid_control_ = 0.0;
  double last_oscillation_reset_ = 0.0;
  double next_plan_time_ = 0.0;
  Pose2 oscillation_pose_;
  int planning_retries_ = 0;
  size_t recovery_index_ = 0;
  Pose2 recovery_pose_;
  std::vector<Pose2> trail_;
  std::vector<Point2> blocked_;
  Costmap2D planning_costmap_;
  Costmap2D open_way_costmap_;
  uint8_t open_way_cost_ = kInscribedInflatedObstacle;
  double open_way_keep_ = 0.0;
  bool recovery_running_ = false;
  // The last replanning found no path: the plan may run into what shut the way.
  bool plan_shut_ = false;
  Trigger trigger_ = Trigger::kPlanning;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_NAVIGATION_EXECUTIVE_H_
