// The move_base state machine with scripted planners: success, planner and
// controller failures through the recovery list to an abort that says why,
// oscillation, cancel and preemption.
#include "minibot3d_navigation/move_base/navigation_executive.h"

#include <gtest/gtest.h>

#include <cmath>

namespace minibot3d_navigation {
namespace nav {
namespace {

class StraightPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "straight"; }
  Path MakePlan(const Costmap2D&, const Pose2D& start, const Pose2D& goal) override {
    ++calls;
    if (fail) throw PlanningError(fail_code, "goal (3.00, 0.00) is in an obstacle (cost 254)");
    return {start, goal};
  }
  bool fail = false;
  PlanningError::Code fail_code = PlanningError::Code::kGoalOccupied;
  int calls = 0;
};

// Drives straight at the plan's last pose at 0.5 m/s; or fails; or stalls.
class GoToGoal : public LocalPlanner {
 public:
  std::string name() const override { return "goto"; }
  void Reset() override { ++resets; }
  Twist2D ComputeVelocity(const Pose2D& pose, const Twist2D&, const Path& plan,
                          const Costmap2D&) override {
    if (fail) throw ControlError("all 42 trajectories collide");
    Twist2D cmd;
    if (stall) return cmd;
    const double heading = std::atan2(plan.back().y - pose.y, plan.back().x - pose.x);
    cmd.vx = 0.5;
    cmd.vtheta = 2.0 * AngleDiff(heading, pose.yaw);
    return cmd;
  }
  bool IsGoalReached(const Pose2D& pose, const Twist2D&, const Path& plan) override {
    return std::hypot(plan.back().x - pose.x, plan.back().y - pose.y) < 0.1;
  }
  bool fail = false;
  bool stall = false;
  int resets = 0;
};

class CountingRecovery : public RecoveryBehavior {
 public:
  explicit CountingRecovery(std::string n) : name_(std::move(n)) {}
  std::string name() const override { return name_; }
  void Start(const RobotState&) override { ++starts; cycles_left = 3; }
  bool Step(const RobotState&, Twist2D* cmd) override {
    cmd->vtheta = 0.5;
    return cycles_left-- > 0;
  }
  int starts = 0;
  int cycles_left = 0;

 private:
  std::string name_;
};

struct Harness {
  explicit Harness(MoveBaseOptions o = MoveBaseOptions())
      : costmap(10, 10, 1.0, -5.0, -5.0),
        r1("conservative_reset"),
        r2("rotate_recovery"),
        exec(o, &planner, &controller, {&r1, &r2}) {
    state.global_costmap = &costmap;
    state.local_costmap = &costmap;
  }
  // Runs until the goal finishes or max_time; integrates the commands.
  CycleResult Run(double max_time, double dt = 0.05) {
    CycleResult r;
    for (; state.time < max_time; state.time += dt) {
      r = exec.Step(state, Pose2D());
      if (r.status != GoalStatus::kActive) return r;
      Pose2D& p = state.global_pose;
      p.x += r.cmd.vx * std::cos(p.yaw) * dt;
      p.y += r.cmd.vx * std::sin(p.yaw) * dt;
      p.yaw = NormalizeAngle(p.yaw + r.cmd.vtheta * dt);
      state.local_pose = p;
    }
    return r;
  }
  Costmap2D costmap;
  StraightPlanner planner;
  GoToGoal controller;
  CountingRecovery r1, r2;
  NavigationExecutive exec;
  RobotState state;
};

TEST(NavigationExecutive, ReachesGoal) {
  Harness h;
  h.exec.SetGoal({2.0, 1.0, 0.0}, 0.0);
  const CycleResult r = h.Run(30.0);
  EXPECT_EQ(r.status, GoalStatus::kSucceeded) << r.message;
  EXPECT_NEAR(h.state.global_pose.x, 2.0, 0.1);
  EXPECT_EQ(h.planner.calls, 1);  // planner_frequency 0: plan once
  EXPECT_EQ(h.r1.starts, 0);
  EXPECT_FALSE(h.exec.active());
}

TEST(NavigationExecutive, ReplansAtPlannerFrequency) {
  MoveBaseOptions o;
  o.planner_frequency = 2.0;
  Harness h(o);
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(30.0);
  ASSERT_EQ(r.status, GoalStatus::kSucceeded);
  // About 6 s of driving at 2 Hz.
  EXPECT_GE(h.planner.calls, 10);
  EXPECT_LE(h.planner.calls, 15);
}

TEST(NavigationExecutive, PlannerFailureRunsRecoveriesThenAbortsSayingWhy) {
  Harness h;
  h.planner.fail = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted);
  EXPECT_NE(r.message.find("Failed to find a valid plan"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("goal (3.00, 0.00) is in an obstacle"), std::string::npos) << r.message;
  EXPECT_EQ(h.r1.starts, 1);
  EXPECT_EQ(h.r2.starts, 1);
  // Each recovery waits planner_patience (5 s) first: 3 x 5 s plus recovery cycles.
  EXPECT_GT(h.state.time, 15.0);
  EXPECT_LT(h.state.time, 17.0);
  EXPECT_EQ(h.exec.Step(h.state, Pose2D()).status, GoalStatus::kNone);
}

TEST(NavigationExecutive, MaxPlanningRetriesShortensPatience) {
  MoveBaseOptions o;
  o.max_planning_retries = 2;
  o.recovery_behavior_enabled = false;
  Harness h(o);
  h.planner.fail = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted);
  EXPECT_EQ(h.planner.calls, 3);
  EXPECT_EQ(h.r1.starts, 0);
}

TEST(NavigationExecutive, GoalOffMapAbortsAtOnce) {
  Harness h;
  h.planner.fail = true;
  h.planner.fail_code = PlanningError::Code::kGoalOffMap;
  h.exec.SetGoal({30.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted);
  EXPECT_LT(h.state.time, 0.01);
  EXPECT_NE(r.message.find("off the global costmap"), std::string::npos) << r.message;
}

TEST(NavigationExecutive, ControllerStuckAbortsAfterPatience) {
  MoveBaseOptions o;
  o.controller_patience = 2.0;
  Harness h(o);
  h.controller.fail = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted);
  EXPECT_NE(r.message.find("controller stuck"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("all 42 trajectories collide"), std::string::npos) << r.message;
  EXPECT_EQ(h.r1.starts, 1);
  EXPECT_EQ(h.r2.starts, 1);
  EXPECT_GT(h.state.time, 6.0);
  EXPECT_LT(h.state.time, 8.0);
}

TEST(NavigationExecutive, OscillationTriggersRecoveryAndAbort) {
  MoveBaseOptions o;
  o.oscillation_timeout = 2.0;
  Harness h(o);
  h.controller.stall = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted);
  EXPECT_NE(r.message.find("oscillating"), std::string::npos) << r.message;
  EXPECT_EQ(h.r1.starts, 1);
}

TEST(NavigationExecutive, CancelStopsAndPreemptionReplaces) {
  Harness h;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  CycleResult r = h.exec.Step(h.state, Pose2D());
  EXPECT_GT(r.cmd.vx, 0.0);
  h.exec.Cancel();
  r = h.exec.Step(h.state, Pose2D());
  EXPECT_EQ(r.status, GoalStatus::kNone);
  EXPECT_EQ(r.cmd.vx, 0.0);

  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  h.Run(2.0);
  h.exec.SetGoal({0.0, 2.0, 0.0}, h.state.time);  // preempt
  EXPECT_EQ(h.controller.resets, 3);  // one per SetGoal
  r = h.Run(40.0);
  ASSERT_EQ(r.status, GoalStatus::kSucceeded);
  EXPECT_NEAR(h.state.global_pose.y, 2.0, 0.1);
}

TEST(NavigationExecutive, RejectsBadOptionsNamingThem) {
  MoveBaseOptions o;
  o.controller_frequency = 0.0;
  o.recovery_behaviors = {"spin_forever"};
  try {
    ValidateMoveBaseOptions(o);
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("controller_frequency=0"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("spin_forever"), std::string::npos);
  }
  EXPECT_THROW(SetMoveBaseOption("planner_frequency", "fast", &o), std::invalid_argument);
  EXPECT_THROW(SetMoveBaseOption("planer_frequency", "1", &o), std::invalid_argument);
  SetMoveBaseOption("recovery_behaviors", "[conservative_reset, rotate_recovery]", &o);
  EXPECT_EQ(o.recovery_behaviors.size(), 2u);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
