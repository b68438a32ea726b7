#include "minibot3d_navigation/move_base/navigation_executive.h"

#include <cmath>
#include <sstream>
#include <utility>

#include "minibot3d_navigation/option_table.h"

namespace minibot3d_navigation {
namespace nav {

const char* NavStateName(NavState state) {
  switch (state) {
    case NavState::kIdle: return "IDLE";
    case NavState::kPlanning: return "PLANNING";
    case NavState::kControlling: return "CONTROLLING";
    case NavState::kClearing: return "CLEARING";
  }
  return "?";
}

NavigationExecutive::NavigationExecutive(const MoveBaseOptions& options,
                                         GlobalPlanner* global_planner,
                                         LocalPlanner* local_planner,
                                         std::vector<RecoveryBehavior*> recoveries)
    : options_(options),
      global_planner_(global_planner),
      local_planner_(local_planner),
      recoveries_(std::move(recoveries)) {
  ValidateMoveBaseOptions(options_);
}

void NavigationExecutive::SetGoal(const Pose2D& goal, double time) {
  goal_ = goal;
  state_ = NavState::kPlanning;
  plan_.clear();
  local_plan_.clear();
  last_error_.clear();
  last_valid_plan_ = time;
  last_valid_control_ = time;
  last_oscillation_reset_ = time;
  next_plan_time_ = time;
  oscillation_pose_ = Pose2D{std::nan(""), std::nan(""), 0.0};
  planning_retries_ = 0;
  recovery_index_ = 0;
  recovery_running_ = false;
  local_planner_->Reset();
}

void NavigationExecutive::Cancel() {
  state_ = NavState::kIdle;
  recovery_running_ = false;
}

bool NavigationExecutive::TryPlan(const RobotState& state, double time) {
  next_plan_time_ = options_.planner_frequency > 0.0 ? time + 1.0 / options_.planner_frequency
                                                     : 1e300;
  try {
    plan_ = global_planner_->MakePlan(*state.global_costmap, state.global_pose, goal_);
    if (plan_.empty()) throw PlanningError(PlanningError::Code::kNoPath, "planner returned an empty path");
    last_valid_plan_ = time;
    planning_retries_ = 0;
    return true;
  } catch (const PlanningError& e) {
    last_error_ = e.what();
    ++planning_retries_;
    if (e.code() == PlanningError::Code::kGoalOffMap) throw;
    return false;
  }
}

CycleResult NavigationExecutive::Abort(const std::string& message) {
  state_ = NavState::kIdle;
  recovery_running_ = false;
  CycleResult r;
  r.status = GoalStatus::kAborted;
  r.message = message;
  return r;
}

CycleResult NavigationExecutive::EnterClearing(Trigger trigger, const RobotState& state) {
  trigger_ = trigger;
  if (options_.recovery_behavior_enabled && recovery_index_ < recoveries_.size()) {
    state_ = NavState::kClearing;
    recoveries_[recovery_index_]->Start(state);
    recovery_running_ = true;
    CycleResult r;
    r.status = GoalStatus::kActive;
    r.message = "recovering: " + recoveries_[recovery_index_]->name() + " (" + last_error_ + ")";
    return r;
  }
  std::ostringstream msg;
  const char* after = recoveries_.empty() || !options_.recovery_behavior_enabled
                          ? ""
                          : " even after executing recovery behaviors";
  switch (trigger) {
    case Trigger::kPlanning:
      msg << "Failed to find a valid plan" << after << ": " << last_error_;
      break;
    case Trigger::kControlling:
      msg << "Failed to find a valid control for " << options_.controller_patience << " s"
          << after << " (controller stuck): " << last_error_;
      break;
    case Trigger::kOscillation:
      msg << "Robot is oscillating: it moved less than oscillation_distance="
          << options_.oscillation_distance << " m in oscillation_timeout="
          << options_.oscillation_timeout << " s" << after;
      break;
  }
  return Abort(msg.str());
}

CycleResult NavigationExecutive::Step(const RobotState& state, const Pose2D& global_to_local) {
  CycleResult result;
  if (state_ == NavState::kIdle) return result;
  result.status = GoalStatus::kActive;
  const double t = state.time;

  // Progress resets the oscillation clock (and the recoveries, if they were
  // started because of oscillation), as in move_base.
  if (!std::isfinite(oscillation_pose_.x) ||
      std::hypot(state.global_pose.x - oscillation_pose_.x,
                 state.global_pose.y - oscillation_pose_.y) >= options_.oscillation_distance) {
    last_oscillation_reset_ = t;
    oscillation_pose_ = state.global_pose;
    if (trigger_ == Trigger::kOscillation) recovery_index_ = 0;
  }

  if (state_ == NavState::kClearing) {
    Twist2D cmd;
    if (recovery_running_ && recoveries_[recovery_index_]->Step(state, &cmd)) {
      result.cmd = cmd;
      return result;
    }
    recovery_running_ = false;
    ++recovery_index_;
    state_ = NavState::kPlanning;
    last_valid_plan_ = t;
    last_valid_control_ = t;
    last_oscillation_reset_ = t;
    planning_retries_ = 0;
    return result;
  }

  try {
    if (state_ == NavState::kPlanning) {
      if (!TryPlan(state, t)) {
        const bool out_of_patience = t - last_valid_plan_ > options_.planner_patience;
        const bool out_of_retries = options_.max_planning_retries >= 0 &&
                                    planning_retries_ > options_.max_planning_retries;
        if (out_of_patience || out_of_retries) return EnterClearing(Trigger::kPlanning, state);
        return result;
      }
      result.new_plan = true;
      state_ = NavState::kControlling;
    } else if (t >= next_plan_time_) {
      // Periodic replanning; on failure keep following the old plan until
      // planner_patience runs out.
      if (TryPlan(state, t)) {
        result.new_plan = true;
      } else if (t - last_valid_plan_ > options_.planner_patience) {
        return EnterClearing(Trigger::kPlanning, state);
      }
    }
  } catch (const PlanningError& e) {
    return Abort(std::string("Goal is off the global costmap: ") + e.what());
  }

  // CONTROLLING.
  local_plan_.clear();
  local_plan_.reserve(plan_.size());
  for (const Pose2D& p : plan_) local_plan_.push_back(Compose(global_to_local, p));

  if (local_planner_->IsGoalReached(state.local_pose, state.velocity, local_plan_)) {
    state_ = NavState::kIdle;
    result.status = GoalStatus::kSucceeded;
    result.message = "Goal reached.";
    return result;
  }
  if (options_.oscillation_timeout > 0.0 &&
      t - last_oscillation_reset_ > options_.oscillation_timeout) {
    return EnterClearing(Trigger::kOscillation, state);
  }
  try {
    result.cmd = local_planner_->ComputeVelocity(state.local_pose, state.velocity, local_plan_,
                                                 *state.local_costmap);
    last_valid_control_ = t;
  } catch (const ControlError& e) {
    last_error_ = e.what();
    result.cmd = Twist2D();
    if (t - last_valid_control_ > options_.controller_patience) {
      return EnterClearing(Trigger::kControlling, state);
    }
    state_ = NavState::kPlanning;  // replan, as move_base does
  }
  return result;
}

}  // namespace nav
}  // namespace minibot3d_navigation
