// The move_base state machine with scripted planners: success, planner and
// controller failures through the recovery list to an abort that says why,
// oscillation, cancel and preemption; the recoveries of its own (back_out,
// wait) and waiting for someone who shuts the only way.
#include "minibot3d_navigation/move_base/navigation_executive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "minibot3d_navigation/move_base/back_out_recovery.h"
#include "minibot3d_navigation/move_base/wait_recovery.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

// A unicycle driven by `cmd` for dt seconds.
void Drive(const Twist2& cmd, double dt, Pose2* p) {
  p->x += cmd.vx * std::cos(p->yaw) * dt;
  p->y += cmd.vx * std::sin(p->yaw) * dt;
  p->yaw = NormalizeAngle(p->yaw + cmd.wz * dt);
}

class StraightPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "straight"; }
  Path MakePlan(const Costmap2D&, const Pose2& start, const Pose2& goal) override {
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
  Twist2 ComputeVelocity(const Pose2& pose, const Twist2&, const Path& plan,
                          const Costmap2D&) override {
    if (fail) throw ControlError("all 42 trajectories collide");
    Twist2 cmd;
    if (stall) return cmd;
    const double heading = std::atan2(plan.back().y - pose.y, plan.back().x - pose.x);
    cmd.vx = 0.5;
    cmd.wz = 2.0 * AngleDiff(heading, pose.yaw);
    return cmd;
  }
  bool IsGoalReached(const Pose2& pose, const Twist2&, const Path& plan) override {
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
  void Start(const RobotState&) override { ++starts; cycles_left = cycles; }
  bool Step(const RobotState&, Twist2* cmd) override {
    cmd->wz = 0.5;
    cmd->vx = -reverse;
    return cycles_left-- > 0;
  }
  int starts = 0;
  int cycles_left = 0;
  int cycles = 3;
  double reverse = 0.0;  // m/s backwards while it runs (a back-out)

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
      r = exec.Step(state, Pose2());
      if (!r.message.empty()) messages.push_back(r.message);
      if (r.status != GoalStatus::kActive) return r;
      Drive(r.cmd, dt, &state.global_pose);
      state.local_pose = state.global_pose;
    }
    return r;
  }
  std::vector<std::string> messages;
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
  EXPECT_EQ(h.exec.Step(h.state, Pose2()).status, GoalStatus::kNone);
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
  // The recovery says why it runs (it used to print an empty reason).
  bool said = false;
  for (const auto& m : h.messages) {
    said |= m.rfind("recovering: ", 0) == 0 && m.find("oscillation_distance=") != std::string::npos;
  }
  EXPECT_TRUE(said);
}

// Recoveries that move the robot (backing out 0.5 m) are not progress: an oscillating goal still
// runs out of recoveries and aborts. Counting their motion as progress restarted the list after
// every back-out and kept the robot shuttling in and out of a pocket for good.
TEST(NavigationExecutive, ARecoverysOwnMotionIsNotProgress) {
  MoveBaseOptions o;
  o.oscillation_timeout = 2.0;
  o.recovery_reset_distance = 0.3;
  Harness h(o);
  for (CountingRecovery* r : {&h.r1, &h.r2}) {
    r->cycles = 20;
    r->reverse = 0.5;
  }
  h.controller.stall = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(100.0);
  ASSERT_EQ(r.status, GoalStatus::kAborted) << "still active after 100 s";
  EXPECT_NE(r.message.find("even after executing recovery behaviors"), std::string::npos)
      << r.message;
  EXPECT_EQ(h.r1.starts, 1);
  EXPECT_EQ(h.r2.starts, 1);
}

TEST(NavigationExecutive, CancelStopsAndPreemptionReplaces) {
  Harness h;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  CycleResult r = h.exec.Step(h.state, Pose2());
  EXPECT_GT(r.cmd.vx, 0.0);
  h.exec.Cancel();
  r = h.exec.Step(h.state, Pose2());
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

// Drives a unicycle by the recovery's commands until it finishes.
int RunRecovery(RecoveryBehavior* rec, RobotState* state, double dt = 0.05,
                double* max_vx = nullptr) {
  rec->Start(*state);
  Twist2 cmd;
  int steps = 0;
  while (rec->Step(*state, &cmd) && steps < 2000) {
    if (max_vx != nullptr) *max_vx = std::max(*max_vx, cmd.vx);
    Drive(cmd, dt, &state->local_pose);
    state->time += dt;
    ++steps;
  }
  return steps;
}

// A trail driven forwards on an arc: from (0, 0) heading 0, turning left.
std::vector<Pose2> ArcTrail(int n = 60) {
  std::vector<Pose2> trail;
  for (int i = 0; i <= n; ++i) {
    const double yaw = 0.6 * i / n;
    const double s = 0.02 * i;
    trail.push_back({s * std::cos(yaw / 2.0), s * std::sin(yaw / 2.0), yaw});
  }
  return trail;
}

double DistanceToTrail(const std::vector<Pose2>& trail, const Pose2& p) {
  double best = 1e300;
  for (const Pose2& t : trail) best = std::min(best, std::hypot(t.x - p.x, t.y - p.y));
  return best;
}

// A robot at the end of `trail`, backing out on `costmap`.
RobotState AtTrailEnd(const std::vector<Pose2>& trail, const Costmap2D& costmap,
                      bool control_failed) {
  RobotState state;
  state.local_pose = trail.back();
  state.local_costmap = &costmap;
  state.trail = &trail;
  state.control_failed = control_failed;
  return state;
}

void SetLethal(Costmap2D* costmap, double x, double y) {
  int mx, my;
  costmap->WorldToMapNoBounds(x, y, &mx, &my);
  costmap->set_cost(mx, my, kLethalObstacle);
}

TEST(BackOutRecovery, ReversesAlongTheTrailItDroveThrough) {
  const std::vector<Pose2> trail = ArcTrail();
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  RobotState state = AtTrailEnd(trail, costmap, /*control_failed=*/true);
  BackOutOptions o;
  o.distance = 0.6;
  BackOutRecovery rec("back_out", o, MakeCircleFootprint(0.12));
  // Checked along the way: never forwards, never off the trail.
  rec.Start(state);
  ASSERT_FALSE(rec.route().empty());
  Twist2 cmd;
  double worst = 0.0;
  int steps = 0;
  const Pose2 start = state.local_pose;
  while (rec.Step(state, &cmd) && steps++ < 2000) {
    EXPECT_LE(cmd.vx, 0.0);
    Drive(cmd, 0.05, &state.local_pose);
    state.time += 0.05;
    worst = std::max(worst, DistanceToTrail(trail, state.local_pose));
  }
  EXPECT_LT(worst, 0.03);
  // It got `distance` away (to within the last target's tolerance).
  EXPECT_GT(std::hypot(state.local_pose.x - start.x, state.local_pose.y - start.y), 0.55);
}

TEST(BackOutRecovery, DoesNothingAfterOscillationOrWithoutTrail) {
  const std::vector<Pose2> trail = ArcTrail();
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  RobotState state = AtTrailEnd(trail, costmap, /*control_failed=*/false);
  BackOutRecovery rec("back_out", BackOutOptions(), MakeCircleFootprint(0.12));
  // Oscillation with room to turn: reversing would undo progress.
  EXPECT_EQ(RunRecovery(&rec, &state), 0);
  EXPECT_NE(rec.outcome().find("not needed"), std::string::npos) << rec.outcome();
  state.control_failed = true;
  state.trail = nullptr;
  EXPECT_EQ(RunRecovery(&rec, &state), 0);
}

TEST(BackOutRecovery, BacksOutAfterOscillationWhenWedged) {
  // A robot that drove into a dead-end slot with its outline on an obstacle:
  // the local planner has no move, so the trigger is oscillation, not a
  // control failure; the way it came is still open.
  const std::vector<Pose2> trail = ArcTrail();
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  const Footprint fp = MakeCircleFootprint(0.12);
  const Pose2 end = trail.back();
  // An obstacle cell under the front of the footprint.
  SetLethal(&costmap, end.x + 0.11 * std::cos(end.yaw), end.y + 0.11 * std::sin(end.yaw));
  RobotState state = AtTrailEnd(trail, costmap, /*control_failed=*/false);
  ASSERT_EQ(FootprintCost(costmap, fp, state.local_pose), kLethalObstacle);
  BackOutRecovery rec("back_out", BackOutOptions(), fp);
  EXPECT_GT(RunRecovery(&rec, &state), 0);
  EXPECT_GT(std::hypot(state.local_pose.x - end.x, state.local_pose.y - end.y), 0.55);
  EXPECT_NE(FootprintCost(costmap, fp, state.local_pose), kLethalObstacle);
  EXPECT_NE(rec.outcome().find("reached its end"), std::string::npos) << rec.outcome();
}

TEST(BackOutRecovery, LeavesADeadEndSlotLongerThanItsDistance) {
  // A dead-end slot 1.3 m deep (x in [0, 1.3]) that the robot (0.23 m wide)
  // drove 1 m into from x = -1.  Its walls are mapped a cell thick, into
  // cells the robot's sides graze (y in [0.10, 0.15] and mirrored), as a desk
  // passed 3 cm away is.  Reversing 0.6 m would leave it in the slot, where
  // it cannot turn, so the route goes on to where it can; the grazed cells
  // do not stop it.
  Costmap2D costmap(120, 80, 0.05, -3.0, -2.0);
  for (double x = 0.0; x <= 1.3; x += 0.025) {
    SetLethal(&costmap, x, 0.14);
    SetLethal(&costmap, x, -0.14);
  }
  for (double y = -0.14; y <= 0.14; y += 0.025) SetLethal(&costmap, 1.3, y);
  const Footprint fp = {{0.12, 0.115}, {-0.12, 0.115}, {-0.12, -0.115}, {0.12, -0.115}};
  std::vector<Pose2> trail;
  for (double x = -1.0; x <= 1.0 + 1e-9; x += 0.02) trail.push_back({x, 0.0, 0.0});
  RobotState state = AtTrailEnd(trail, costmap, /*control_failed=*/true);
  BackOutOptions o;
  o.distance = 0.6;
  BackOutRecovery rec("back_out", o, fp);
  rec.Start(state);
  ASSERT_FALSE(rec.route().empty());
  const double end_x = rec.route().back().x;
  EXPECT_LT(end_x, -0.1);   // out of the slot, with room to turn
  EXPECT_GT(end_x, -0.45);  // and no further than that
  RunRecovery(&rec, &state);
  EXPECT_LT(state.local_pose.x, -0.07) << rec.outcome();
  EXPECT_NE(rec.outcome().find("reached its end"), std::string::npos) << rec.outcome();
}

TEST(BackOutRecovery, StopsBeforeSomethingNewOnItsWay) {
  const std::vector<Pose2> trail = ArcTrail();
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  // A wall across the trail 0.35 m behind the robot, seen after it passed.
  for (int my = 0; my < 80; ++my) {
    int mx, unused;
    costmap.WorldToMapNoBounds(0.85, 0.0, &mx, &unused);
    costmap.set_cost(mx, my, kLethalObstacle);
  }
  RobotState state = AtTrailEnd(trail, costmap, /*control_failed=*/true);
  const Footprint fp = MakeCircleFootprint(0.12);
  BackOutRecovery rec("back_out", BackOutOptions(), fp);
  RunRecovery(&rec, &state);
  EXPECT_NE(FootprintCost(costmap, fp, state.local_pose), kLethalObstacle);
  EXPECT_GT(state.local_pose.x, 0.85 + 0.12);
  EXPECT_LT(state.local_pose.x, trail.back().x - 0.05);  // it did back up
}

// Plans straight to the goal unless a lethal cell lies on that line; then
// round it via a waypoint at y = +1 (or fails if `fail_if_blocked`).
class DetourPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "detour"; }
  Path MakePlan(const Costmap2D& costmap, const Pose2& start, const Pose2& goal) override {
    ++calls;
    bool blocked = false;
    for (double f = 0.0; f <= 1.0; f += 0.01) {
      int mx, my;
      if (costmap.WorldToMap(start.x + f * (goal.x - start.x), start.y + f * (goal.y - start.y),
                             &mx, &my) &&
          costmap.cost(mx, my) == kLethalObstacle) {
        blocked = true;
      }
    }
    last_blocked = blocked;
    if (!blocked) return Line(start, goal);
    if (fail_if_blocked) throw PlanningError(PlanningError::Code::kNoPath, "no way round");
    Path p = Line(start, {start.x + 1.0, 1.0, 0.0});
    Path q = Line({start.x + 1.0, 1.0, 0.0}, goal);
    p.insert(p.end(), q.begin() + 1, q.end());
    return p;
  }
  static Path Line(const Pose2& a, const Pose2& b) {
    Path p;
    for (int i = 0; i <= 20; ++i) {
      p.push_back({a.x + (b.x - a.x) * i / 20.0, a.y + (b.y - a.y) * i / 20.0, 0.0});
    }
    return p;
  }
  int calls = 0;
  bool last_blocked = false;
  bool fail_if_blocked = false;
};

// The executive with blocked-place memory on, driven until control has
// failed for controller_patience and one place is remembered.
struct BlockedHarness {
  explicit BlockedHarness(bool fail_if_blocked)
      : costmap(100, 100, 0.05, -2.5, -2.5), r1("conservative_reset"),
        exec(Options(), &planner, &controller, {&r1}) {
    planner.fail_if_blocked = fail_if_blocked;
    controller.fail = true;
    state.global_costmap = &costmap;
    state.local_costmap = &costmap;
    exec.SetGoal({2.0, 0.0, 0.0}, 0.0);
    for (; state.time < 1.5 && exec.blocked().empty(); state.time += 0.1) {
      exec.Step(state, Pose2());
    }
  }
  static MoveBaseOptions Options() {
    MoveBaseOptions o;
    o.controller_patience = 1.0;
    o.blocked_radius = 0.3;
    o.blocked_lookahead = 0.5;
    return o;
  }
  Costmap2D costmap;
  DetourPlanner planner;
  GoToGoal controller;
  CountingRecovery r1;
  NavigationExecutive exec;
  RobotState state;
};

TEST(NavigationExecutive, RemembersWhereControlFailedAndPlansRoundIt) {
  BlockedHarness h(false);
  NavigationExecutive& exec = h.exec;
  RobotState& state = h.state;
  ASSERT_EQ(exec.blocked().size(), 1u);
  // Half a metre ahead along the plan (straight at the goal).
  EXPECT_NEAR(exec.blocked()[0].x, 0.5, 0.11);
  EXPECT_NEAR(exec.blocked()[0].y, 0.0, 1e-9);
  h.controller.fail = false;
  // Let the recovery finish, then the next plan goes round the disc.
  for (int i = 0; i < 10 && !h.planner.last_blocked; ++i, state.time += 0.1) {
    exec.Step(state, Pose2());
  }
  EXPECT_TRUE(h.planner.last_blocked);
  EXPECT_NEAR(exec.plan()[20].y, 1.0, 1e-9);  // via the detour waypoint
  // The original costmap is untouched.
  int mx, my;
  ASSERT_TRUE(h.costmap.WorldToMap(0.5, 0.0, &mx, &my));
  EXPECT_EQ(h.costmap.cost(mx, my), 0);
}

TEST(NavigationExecutive, ForgetsBlockedPlacesWhenNoPlanGoesRoundThem) {
  BlockedHarness h(true);
  NavigationExecutive& exec = h.exec;
  RobotState& state = h.state;
  ASSERT_EQ(exec.blocked().size(), 1u);
  h.controller.fail = false;
  bool replanned = false;
  for (int i = 0; i < 10 && !replanned; ++i, state.time += 0.1) {
    replanned = exec.Step(state, Pose2()).new_plan;
  }
  EXPECT_TRUE(replanned);
  EXPECT_TRUE(exec.blocked().empty());  // no way round: forgotten, plain plan
  EXPECT_FALSE(h.planner.last_blocked);
}

TEST(NavigationExecutive, RecordsTheTrailItDrives) {
  Harness h;
  h.exec.SetGoal({2.0, 0.0, 0.0}, 0.0);
  ASSERT_EQ(h.Run(30.0).status, GoalStatus::kSucceeded);
  const std::vector<Pose2>& trail = h.exec.trail();
  ASSERT_GT(trail.size(), 50u);  // ~1.9 m at 2 cm spacing
  for (size_t i = 1; i < trail.size(); ++i) {
    EXPECT_LT(std::hypot(trail[i].x - trail[i - 1].x, trail[i].y - trail[i - 1].y), 0.05);
  }
  EXPECT_NEAR(trail.back().x, h.state.local_pose.x, 0.03);
}

TEST(NavigationExecutive, TrailDropsTheLoopsOfARobotShufflingToAndFro) {
  // 1 m in, then 200 shuffles of 0.1 m back and forth at the end: the trail
  // is still the way in (its 500-pose cap would otherwise hold only shuffles).
  Harness h;
  Pose2 p{0.0, 0.0, 0.0};
  auto drive_to = [&h, &p](double x) {
    const double step = x > p.x ? 0.005 : -0.005;
    while (std::abs(x - p.x) > 1e-9) {
      p.x = std::abs(x - p.x) < std::abs(step) ? x : p.x + step;
      h.state.local_pose = p;
      h.exec.Step(h.state, Pose2());
    }
  };
  drive_to(1.0);
  for (int k = 0; k < 200; ++k) {
    drive_to(0.9);
    drive_to(1.0);
  }
  const std::vector<Pose2>& trail = h.exec.trail();
  ASSERT_FALSE(trail.empty());
  EXPECT_NEAR(trail.front().x, 0.0, 0.01);
  EXPECT_NEAR(trail.back().x, 1.0, 0.02);
  EXPECT_LT(trail.size(), 60u);  // ~1 m at 2 cm spacing
  for (size_t i = 1; i < trail.size(); ++i) EXPECT_GT(trail[i].x, trail[i - 1].x);
}


// Plans the straight line from start to goal (a pose every 0.05 m); no path when a pose of it lies
// on a cell of cost inscribed or more, as A* would find none through a doorway someone stands in.
class LinePlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "line"; }
  Path MakePlan(const Costmap2D& costmap, const Pose2& start, const Pose2& goal) override {
    ++calls;
    const double length = std::hypot(goal.x - start.x, goal.y - start.y);
    const int n = std::max(1, static_cast<int>(std::ceil(length / 0.05)));
    Path path;
    for (int i = 0; i <= n; ++i) {
      const double u = static_cast<double>(i) / n;
      Pose2 p{start.x + u * (goal.x - start.x), start.y + u * (goal.y - start.y), 0.0};
      int mx, my;
      if (costmap.WorldToMap(p.x, p.y, &mx, &my) &&
          costmap.cost(mx, my) >= kInscribedInflatedObstacle) {
        throw PlanningError(PlanningError::Code::kNoPath, "no path: the doorway is shut");
      }
      path.push_back(p);
    }
    return path;
  }
  int calls = 0;
};

// GoToGoal that finds no command when the costmap 0.15 m ahead is inscribed or lethal, as the
// DWA finds none into an obstacle.
class StopsShortOfObstacles : public GoToGoal {
 public:
  Twist2 ComputeVelocity(const Pose2& pose, const Twist2& v, const Path& plan,
                         const Costmap2D& costmap) override {
    int mx, my;
    if (costmap.WorldToMap(pose.x + 0.15 * std::cos(pose.yaw), pose.y + 0.15 * std::sin(pose.yaw),
                           &mx, &my) &&
        costmap.cost(mx, my) >= kInscribedInflatedObstacle) {
      throw ControlError("every trajectory ends in the inscribed band");
    }
    return GoToGoal::ComputeVelocity(pose, v, plan, costmap);
  }
};

// Someone standing across the line y = 0 at x = 2: lethal, with an inscribed band round them.
void StandIn(Costmap2D* costmap, uint8_t band = kInscribedInflatedObstacle) {
  for (double y = -0.5; y <= 0.5; y += 0.05) {
    for (double x = 1.85; x <= 2.15; x += 0.05) {
      int mx, my;
      costmap->WorldToMapNoBounds(x, y, &mx, &my);
      costmap->set_cost(mx, my, std::abs(x - 2.0) < 0.03 ? kLethalObstacle : band);
    }
  }
}

void StepAside(Costmap2D* costmap) { costmap->ResetAll(); }

TEST(WaitRecovery, DoesNothingUnlessTheWayIsShut) {
  WaitRecovery rec("wait", WaitOptions(), MakeCircleFootprint(0.12));
  RobotState state;
  state.control_failed = true;  // a path exists; the robot could not follow it
  EXPECT_EQ(RunRecovery(&rec, &state), 0);
  EXPECT_NE(rec.outcome().find("not needed"), std::string::npos) << rec.outcome();
}

TEST(WaitRecovery, StandsUntilAPathExistsAgain) {
  WaitRecovery rec("wait", WaitOptions(), MakeCircleFootprint(0.12));
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  RobotState state;
  state.local_costmap = &costmap;
  state.no_path = true;
  int asked = 0;
  state.path_exists = [&] {
    ++asked;
    return state.time > 2.9;  // from the check at 3 s
  };
  double max_vx = -1.0;
  RunRecovery(&rec, &state, 0.05, &max_vx);
  EXPECT_EQ(max_vx, 0.0);  // it stood still
  EXPECT_NEAR(state.time, 3.0, 0.051);
  EXPECT_EQ(asked, 6);  // twice a second
  EXPECT_EQ(rec.outcome(), "the way opened after 3.0 s");
}

TEST(WaitRecovery, GivesUpAfterItsDuration) {
  WaitOptions o;
  o.duration = 4.0;
  WaitRecovery rec("wait", o, MakeCircleFootprint(0.12));
  RobotState state;
  state.no_path = true;
  state.path_exists = [] { return false; };
  RunRecovery(&rec, &state);
  EXPECT_NEAR(state.time, 4.0, 0.051);
  EXPECT_EQ(rec.outcome(), "still no path to the goal after 4.0 s");
}

TEST(WaitRecovery, BacksOffToTheClearanceFirst) {
  // A wall across the robot's way 0.18 m in front of its footprint (circle of 0.12 m at the
  // origin, facing +x): it backs off until the wall is 0.45 m from the footprint, then stands.
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  for (double y = -0.5; y <= 0.5; y += 0.05) SetLethal(&costmap, 0.325, y);
  WaitRecovery rec("wait", WaitOptions(), MakeCircleFootprint(0.12));
  RobotState state;
  state.local_costmap = &costmap;
  state.no_path = true;
  state.path_exists = [] { return false; };
  EXPECT_LT(rec.ClearanceAhead(costmap, state.local_pose, 0.45), 0.45);
  rec.Start(state);
  Twist2 cmd;
  double backed_at = -1.0;
  for (int i = 0; i < 200 && rec.Step(state, &cmd); ++i) {
    EXPECT_LE(cmd.vx, 0.0);
    if (cmd.vx < 0.0) backed_at = state.time;
    Drive(cmd, 0.05, &state.local_pose);
    state.time += 0.05;
  }
  EXPECT_GE(rec.ClearanceAhead(costmap, state.local_pose, 0.45), 0.45);
  EXPECT_LT(rec.ClearanceAhead(costmap, state.local_pose, 0.45), 0.45 + 0.02);
  EXPECT_LT(backed_at, 3.0);  // then it stood for the rest of the wait
}

TEST(WaitRecovery, BacksOffNoFurtherThanItsBackAllows) {
  Costmap2D costmap(80, 80, 0.05, -2.0, -2.0);
  for (double y = -0.5; y <= 0.5; y += 0.05) {
    SetLethal(&costmap, 0.325, y);   // in front
    SetLethal(&costmap, -0.275, y);  // behind
  }
  WaitRecovery rec("wait", WaitOptions(), MakeCircleFootprint(0.12));
  RobotState state;
  state.local_costmap = &costmap;
  state.no_path = true;
  state.path_exists = [] { return false; };
  RunRecovery(&rec, &state);
  EXPECT_LT(state.local_pose.x, -0.02);  // it made what room there was
  EXPECT_EQ(FootprintCost(costmap, MakeCircleFootprint(0.12), state.local_pose) ==
                kLethalObstacle, false);
}

// Drives at a goal 3 m ahead through a doorway at x = 2 where someone stands from t = 1 s to
// t = 20 s; the recoveries are wait, then two that count their starts.
struct DoorwayHarness {
  explicit DoorwayHarness(double wait_duration)
      : costmap(200, 200, 0.05, -5.0, -5.0),
        wait("wait", Waiting(wait_duration), MakeCircleFootprint(0.12)),
        r1("conservative_reset"),
        r2("rotate_recovery"),
        exec(Options(wait_duration), &planner, &controller, {&wait, &r1, &r2}) {
    state.global_costmap = &costmap;
    state.local_costmap = &costmap;
  }
  static WaitOptions Waiting(double duration) {
    WaitOptions o;
    o.duration = duration;
    return o;
  }
  static MoveBaseOptions Options(double wait_duration) {
    MoveBaseOptions o;
    o.wait_duration = wait_duration;
    o.planner_frequency = 1.0;
    o.planner_patience = 5.0;
    return o;
  }
  CycleResult Run(double max_time, double dt = 0.05) {
    CycleResult r;
    for (; state.time < max_time; state.time += dt) {
      if (!stood && state.time >= shut - 1e-6) StandIn(&costmap), stood = true;
      if (!left && state.time >= leaves - 1e-6) StepAside(&costmap), left = true;
      r = exec.Step(state, Pose2());
      if (!r.message.empty()) messages.push_back(r.message);
      if (r.status != GoalStatus::kActive) return r;
      Drive(r.cmd, dt, &state.global_pose);
      state.local_pose = state.global_pose;
      if (state.time < leaves) x_while_shut = std::max(x_while_shut, state.global_pose.x);
    }
    return r;
  }
  double shut = 1.0, leaves = 20.0;  // s
  bool stood = false, left = false;
  double x_while_shut = -1e9;
  std::vector<std::string> messages;
  Costmap2D costmap;
  LinePlanner planner;
  StopsShortOfObstacles controller;
  WaitRecovery wait;
  CountingRecovery r1, r2;
  NavigationExecutive exec;
  RobotState state;
};

TEST(NavigationExecutive, WaitsForSomeoneInTheDoorwayAtADistanceThenDrivesOn) {
  DoorwayHarness h(30.0);
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  const CycleResult r = h.Run(60.0);
  ASSERT_EQ(r.status, GoalStatus::kSucceeded) << r.message;
  EXPECT_GT(h.state.time, 20.0);
  EXPECT_LT(h.state.time, 25.0);
  // Once replanning found no way, the old plan was followed only to 0.45 m short of the
  // inscribed band (x = 1.85), and no recovery but the wait ran.
  EXPECT_LE(h.x_while_shut, 1.85 - 0.45 + 0.03);
  EXPECT_GT(h.x_while_shut, 1.85 - 0.45 - 0.1);
  EXPECT_EQ(h.r1.starts, 0);
  EXPECT_EQ(h.r2.starts, 0);
  bool opened = false;
  for (const std::string& m : h.messages) opened |= m.find("the way opened after") != std::string::npos;
  EXPECT_TRUE(opened);
}

TEST(NavigationExecutive, WithoutTheWaitTheRecoveriesRunBesideThem) {
  // The control, wait_duration 0: the robot drives on up to the band (its controller stops it
  // there) and goes through the other recoveries while the doorway is shut.
  DoorwayHarness h(0.0);
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  h.Run(60.0);
  EXPECT_GT(h.x_while_shut, 1.85 - 0.2);
  EXPECT_EQ(h.r1.starts, 1);
  EXPECT_EQ(h.r2.starts, 1);
}

TEST(NavigationExecutive, AWayOpensOnlyWhereTheRobotFitsAtAnyHeading) {
  // Once the one in the doorway leaves a band of cost 220 behind (below inscribed: the planner
  // passes it), the way is not open yet by the open-way test of cost 200 (the cost at the
  // footprint's circumscribed radius): the wait goes on. At cost 100 the way is open.
  DoorwayHarness h(30.0);
  h.exec.SetOpenWayTest(200, 0.17);
  h.leaves = 1e9;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  h.Run(12.0);  // shut at 1 s; replanning fails; the wait from about 6 s
  ASSERT_EQ(h.exec.state(), NavState::kClearing);
  auto band = [&h](uint8_t cost) {
    h.costmap.ResetAll();
    for (double y = -0.5; y <= 0.5; y += 0.05) {
      for (double x = 1.85; x <= 2.15; x += 0.05) {
        int mx, my;
        h.costmap.WorldToMapNoBounds(x, y, &mx, &my);
        h.costmap.set_cost(mx, my, cost);
      }
    }
  };
  band(220);
  h.Run(h.state.time + 5.0);
  EXPECT_EQ(h.exec.state(), NavState::kClearing);  // still waiting
  band(100);
  const CycleResult r = h.Run(h.state.time + 20.0);
  EXPECT_EQ(r.status, GoalStatus::kSucceeded) << r.message;
  EXPECT_EQ(h.r1.starts, 0);
}

TEST(NavigationExecutive, AWaitThatDoesNotApplyIsPassedOverAtOnce) {
  // Control fails with a path there (nothing shuts the way): the wait does not apply, so the next
  // recovery starts at the same cycle, not after another controller_patience.
  DoorwayHarness h(30.0);
  h.shut = 1e9;
  h.controller.fail = true;
  h.exec.SetGoal({3.0, 0.0, 0.0}, 0.0);
  while (h.r1.starts == 0 && h.state.time < 30.0) {
    h.exec.Step(h.state, Pose2());
    h.state.time += 0.05;
  }
  EXPECT_EQ(h.r1.starts, 1);
  EXPECT_NEAR(h.state.time, MoveBaseOptions().controller_patience, 0.2);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
