#include "minibot3d_navigation/move_base/navigation_executive.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

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

void NavigationExecutive::SetGoal(const Pose2& goal, double time) {
  goal_ = goal;
  state_ = NavState::kPlanning;
  plan_.clear();
  local_plan_.clear();
  last_error_.clear();
  last_valid_plan_ = time;
  last_valid_control_ = time;
  last_oscillation_reset_ = time;
  next_plan_time_ = time;
  oscillation_pose_ = Pose2{std::nan(""), std::nan(""), 0.0};
  planning_retries_ = 0;
  recovery_index_ = 0;
  recovery_running_ = false;
  blocked_.clear();
  plan_shut_ = false;
  local_planner_->Reset();
}

void NavigationExecutive::Cancel() {
  state_ = NavState::kIdle;
  recovery_running_ = false;
}

namespace {
constexpr double kTrailSpacing = 0.02;     // m between recorded trail poses
constexpr double kTrailYawSpacing = 0.1;   // rad (turns on the spot are recorded too)
constexpr size_t kTrailMaxPoses = 500;     // >= 10 m of trail at kTrailSpacing
constexpr size_t kMaxBlocked = 32;
// m kept, beyond the circumscribed radius, between the robot and what shut its way (the edge of
// proxemics' intimate zone, Hall 1966).
constexpr double kStandOffShut = 0.45;
}  // namespace

void NavigationExecutive::RecordTrail(const Pose2& p) {
  // Loop erasure: back where it has been, the loop driven since is dropped, so
  // the trail stays the way back (a robot that shuffles to and fro in a pocket
  // does not fill it with the shuffle and lose the way in).
  for (size_t i = 0; i + 1 < trail_.size(); ++i) {
    if (std::hypot(p.x - trail_[i].x, p.y - trail_[i].y) < kTrailSpacing) {
      trail_.resize(i + 1);
      break;
    }
  }
  if (!trail_.empty()) {
    const Pose2& last = trail_.back();
    if (std::hypot(p.x - last.x, p.y - last.y) < kTrailSpacing &&
        std::abs(AngleDiff(p.yaw, last.yaw)) < kTrailYawSpacing) {
      return;
    }
  }
  trail_.push_back(p);
  if (trail_.size() > kTrailMaxPoses) trail_.erase(trail_.begin(), trail_.begin() + 100);
}

void NavigationExecutive::RememberBlocked(const RobotState& state) {
  if (options_.blocked_radius <= 0.0 || plan_.empty()) return;
  // The plan pose nearest the robot, then the first one blocked_lookahead
  // beyond it (straight-line distance from the robot).
  const Pose2& r = state.global_pose;
  size_t nearest = 0;
  double best = 1e300;
  for (size_t i = 0; i < plan_.size(); ++i) {
    const double d = std::hypot(plan_[i].x - r.x, plan_[i].y - r.y);
    if (d < best) best = d, nearest = i;
  }
  size_t i = nearest;
  while (i + 1 < plan_.size() &&
         std::hypot(plan_[i].x - r.x, plan_[i].y - r.y) < options_.blocked_lookahead) {
    ++i;
  }
  // Never the goal itself: the goal stays plannable.
  const Point2 c{plan_[i].x, plan_[i].y};
  if (std::hypot(c.x - goal_.x, c.y - goal_.y) < options_.blocked_radius + 0.1) return;
  blocked_.push_back(c);
  if (blocked_.size() > kMaxBlocked) blocked_.erase(blocked_.begin());
}

const Costmap2D& NavigationExecutive::PlanningCostmap(const RobotState& state) {
  const Costmap2D& g = *state.global_costmap;
  planning_costmap_ = g;
  const double res = g.resolution();
  // The cells round the robot and the goal stay as they are, so the start
  // and goal remain plannable (a robot that could not back out is still in
  // its disc: the disc then only counts once it has left).
  const double keep = options_.blocked_radius;
  const int rc = static_cast<int>(std::ceil(options_.blocked_radius / res));
  for (const Point2& b : blocked_) {
    int cx, cy;
    g.WorldToMapNoBounds(b.x, b.y, &cx, &cy);
    for (int my = cy - rc; my <= cy + rc; ++my) {
      for (int mx = cx - rc; mx <= cx + rc; ++mx) {
        if (!g.InBounds(mx, my)) continue;
        double wx, wy;
        g.MapToWorld(mx, my, &wx, &wy);
        if (std::hypot(wx - b.x, wy - b.y) > options_.blocked_radius) continue;
        if (std::hypot(wx - state.global_pose.x, wy - state.global_pose.y) < keep ||
            std::hypot(wx - goal_.x, wy - goal_.y) < keep) {
          continue;
        }
        planning_costmap_.set_cost(mx, my, kLethalObstacle);
      }
    }
  }
  return planning_costmap_;
}

bool NavigationExecutive::TryPlan(const RobotState& state, double time) {
  next_plan_time_ = options_.planner_frequency > 0.0 ? time + 1.0 / options_.planner_frequency
                                                     : 1e300;
  // Round the places remembered as blocked; when there is no way round them
  // all, forget the oldest and try again.
  while (!blocked_.empty()) {
    try {
      plan_ = global_planner_->MakePlan(PlanningCostmap(state), state.global_pose, goal_);
      if (!plan_.empty()) {
        last_valid_plan_ = time;
        planning_retries_ = 0;
        return true;
      }
    } catch (const PlanningError& e) {
      if (e.code() == PlanningError::Code::kGoalOffMap) throw;
    }
    blocked_.erase(blocked_.begin());
  }
  try {
    plan_ = global_planner_->MakePlan(*state.global_costmap, state.global_pose, goal_);
    if (plan_.empty()) throw PlanningError(PlanningError::Code::kNoPath, "planner returned an empty path");
    last_valid_plan_ = time;
    planning_retries_ = 0;
    return true;
  } catch (const PlanningError& e) {
    last_error_ = e.what();
    last_error_code_ = e.code();
    ++planning_retries_;
    if (e.code() == PlanningError::Code::kGoalOffMap) throw;
    return false;
  }
}

double NavigationExecutive::DistanceToShutPose(const RobotState& state) const {
  const Costmap2D& g = *state.global_costmap;
  const Pose2& r = state.global_pose;
  size_t i = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < plan_.size(); ++k) {
    const double d = std::hypot(plan_[k].x - r.x, plan_[k].y - r.y);
    if (d < best) best = d, i = k;
  }
  double along = 0.0;
  for (; i < plan_.size(); ++i) {
    if (i > 0) along += std::hypot(plan_[i].x - plan_[i - 1].x, plan_[i].y - plan_[i - 1].y);
    int mx, my;
    if (!g.WorldToMap(plan_[i].x, plan_[i].y, &mx, &my)) continue;
    const uint8_t c = g.cost(mx, my);
    if (c >= kInscribedInflatedObstacle && c != kNoInformation) return along;
  }
  return std::numeric_limits<double>::infinity();
}

bool NavigationExecutive::PathExists(const RobotState& state) {
  const Costmap2D* costmap = state.global_costmap;
  if (open_way_cost_ < kInscribedInflatedObstacle) {
    open_way_costmap_ = *costmap;
    const double keep = open_way_keep_ + costmap->resolution();
    uint8_t* data = open_way_costmap_.mutable_data();
    for (int my = 0; my < costmap->size_y(); ++my) {
      for (int mx = 0; mx < costmap->size_x(); ++mx) {
        uint8_t& v = data[costmap->Index(mx, my)];
        if (v < open_way_cost_ || v >= kLethalObstacle) continue;
        double wx, wy;
        costmap->MapToWorld(mx, my, &wx, &wy);
        if (std::hypot(wx - state.global_pose.x, wy - state.global_pose.y) < keep ||
            std::hypot(wx - goal_.x, wy - goal_.y) < keep) {
          continue;
        }
        v = kLethalObstacle;
      }
    }
    costmap = &open_way_costmap_;
  }
  try {
    return !global_planner_->MakePlan(*costmap, state.global_pose, goal_).empty();
  } catch (const PlanningError&) {
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

void NavigationExecutive::DescribeFailure(Trigger trigger, RobotState* state) {
  state->control_failed = trigger == Trigger::kControlling;
  state->no_path = trigger == Trigger::kPlanning && last_error_code_ == PlanningError::Code::kNoPath;
  state->path_exists = [this, state] { return PathExists(*state); };
}

CycleResult NavigationExecutive::EnterClearing(Trigger trigger, const RobotState& state) {
  trigger_ = trigger;
  if (trigger == Trigger::kControlling) RememberBlocked(state);
  recovery_pose_ = state.global_pose;
  RobotState s = state;
  DescribeFailure(trigger, &s);
  if (options_.recovery_behavior_enabled) {
    while (recovery_index_ < recoveries_.size() && !recoveries_[recovery_index_]->Applies(s)) {
      ++recovery_index_;
    }
  }
  if (options_.recovery_behavior_enabled && recovery_index_ < recoveries_.size()) {
    state_ = NavState::kClearing;
    recoveries_[recovery_index_]->Start(s);
    recovery_running_ = true;
    CycleResult r;
    r.status = GoalStatus::kActive;
    std::ostringstream why;
    if (trigger == Trigger::kOscillation) {
      why << "oscillating: moved less than oscillation_distance=" << options_.oscillation_distance
          << " m in oscillation_timeout=" << options_.oscillation_timeout << " s";
    } else {
      why << last_error_;
    }
    r.message = "recovering: " + recoveries_[recovery_index_]->name() + " (" + why.str() + ")";
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

CycleResult NavigationExecutive::Step(const RobotState& input, const Pose2& global_to_local) {
  CycleResult result;
  RecordTrail(input.local_pose);
  if (state_ == NavState::kIdle) return result;
  RobotState state = input;
  state.trail = &trail_;
  DescribeFailure(trigger_, &state);
  result.status = GoalStatus::kActive;
  const double t = state.time;

  // Progress resets the oscillation clock (and the recoveries, if they were
  // started because of oscillation), as in move_base. A recovery's own motion (backing out) is
  // not progress: move_base's recoveries run to completion inside one cycle, these across many.
  if (state_ != NavState::kClearing && (!std::isfinite(oscillation_pose_.x) ||
      std::hypot(state.global_pose.x - oscillation_pose_.x,
                 state.global_pose.y - oscillation_pose_.y) >= options_.oscillation_distance)) {
    last_oscillation_reset_ = t;
    oscillation_pose_ = state.global_pose;
    if (trigger_ == Trigger::kOscillation) recovery_index_ = 0;
  }

  if (state_ == NavState::kClearing) {
    Twist2 cmd;
    if (recovery_running_ && recoveries_[recovery_index_]->Step(state, &cmd)) {
      result.cmd = cmd;
      return result;
    }
    if (recovery_running_) {
      const std::string outcome = recoveries_[recovery_index_]->outcome();
      if (!outcome.empty()) {
        result.message = "recovery " + recoveries_[recovery_index_]->name() + " ended: " + outcome;
      }
    }
    recovery_running_ = false;
    ++recovery_index_;
    // Progress and moving on are measured from where the recovery left the robot.
    oscillation_pose_ = state.global_pose;
    recovery_pose_ = state.global_pose;
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
      plan_shut_ = false;
      state_ = NavState::kControlling;
    } else if (t >= next_plan_time_) {
      // Periodic replanning; on failure keep following the old plan until
      // planner_patience runs out.
      if (TryPlan(state, t)) {
        result.new_plan = true;
        plan_shut_ = false;
      } else if (t - last_valid_plan_ > options_.planner_patience) {
        return EnterClearing(Trigger::kPlanning, state);
      } else {
        plan_shut_ = last_error_code_ == PlanningError::Code::kNoPath;
      }
    }
  } catch (const PlanningError& e) {
    return Abort(std::string("Goal is off the global costmap: ") + e.what());
  }

  // CONTROLLING.
  local_plan_.clear();
  local_plan_.reserve(plan_.size());
  for (const Pose2& p : plan_) local_plan_.push_back(Compose(global_to_local, p));

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
  if (options_.wait_duration > 0.0 && plan_shut_ &&
      DistanceToShutPose(state) < open_way_keep_ + kStandOffShut) {
    // The plan runs into what shut the way and no other exists: stand off it (planner_patience
    // then starts the recoveries), rather than drive up to whoever stands there.
    result.cmd = Twist2();
    last_valid_control_ = t;
    return result;
  }
  try {
    result.cmd = local_planner_->ComputeVelocity(state.local_pose, state.velocity, local_plan_,
                                                 *state.local_costmap);
    last_valid_control_ = t;
    // Standing for a moving obstacle to pass is waiting, not oscillating.
    if (local_planner_->Yielding()) last_oscillation_reset_ = t;
    if (recovery_index_ > 0 && trigger_ != Trigger::kOscillation &&
        options_.recovery_reset_distance > 0.0 &&
        std::hypot(state.global_pose.x - recovery_pose_.x,
                   state.global_pose.y - recovery_pose_.y) >= options_.recovery_reset_distance) {
      recovery_index_ = 0;
    }
  } catch (const ControlError& e) {
    last_error_ = e.what();
    result.cmd = Twist2();
    if (t - last_valid_control_ > options_.controller_patience) {
      return EnterClearing(Trigger::kControlling, state);
    }
    state_ = NavState::kPlanning;  // replan, as move_base does
  }
  return result;
}

}  // namespace nav
}  // namespace minibot3d_navigation
