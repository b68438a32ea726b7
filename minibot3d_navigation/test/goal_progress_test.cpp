// explore's GoalProgress: when a goal is given up (goal_progress.h).
#include "minibot3d_navigation/explore/goal_progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr double kTimeout = 20.0;

TEST(GoalProgressTest, ARobotDrivingToItsGoalKeepsIt) {
  GoalProgress p(kTimeout);
  p.Start(0.0, {0.0, 0.0}, {10.0, 0.0});
  for (int s = 1; s <= 40; ++s) EXPECT_EQ("", p.Update(s, {0.25 * s, 0.0})) << s;
}

TEST(GoalProgressTest, ARobotStandingStillLosesItAfterTheTimeout) {
  GoalProgress p(kTimeout);
  p.Start(0.0, {0.0, 0.0}, {5.0, 0.0});
  EXPECT_EQ("", p.Update(kTimeout - 1.0, {0.05, 0.0}));
  EXPECT_EQ("made no progress for 20 s", p.Update(kTimeout + 1.0, {0.05, 0.0}));
}

// A path that first leads away from the goal (round a wall) is not progress towards it, but
// moving keeps the goal for a while.
TEST(GoalProgressTest, APathLeadingAwayFirstKeepsTheGoalWhileTheRobotMoves) {
  GoalProgress p(kTimeout);
  p.Start(0.0, {0.0, 0.0}, {1.0, 0.0});
  double t = 0.0;
  for (int s = 1; s <= 25; ++s) {  // 25 s away from the goal at 0.2 m/s: 5 m
    t = s;
    ASSERT_EQ("", p.Update(t, {-0.2 * s, 0.0})) << s;
  }
  for (int s = 1; s <= 24; ++s) {  // and back to it
    t += 1.0;
    ASSERT_EQ("", p.Update(t, {-5.0 + 0.25 * s, 0.0})) << t;
  }
}

// move_base oscillating in front of a gap, backing out 1.3 m as its recovery and driving back
// to the same spot, every 30 s: the robot moves a lot and never gets closer.
TEST(GoalProgressTest, BackingOutAndComingBackForEverLosesTheGoal) {
  GoalProgress p(kTimeout);
  p.Start(0.0, {0.0, 0.0}, {2.0, 0.0});
  double t = 1.0;
  for (; t <= 9.0; t += 1.0) ASSERT_EQ("", p.Update(t, {0.2 * t, 0.0}));  // to 0.2 m short
  // Then, every 30 s: 10 s stuck there, 10 s backing out 1.3 m, 10 s driving back.
  const double stuck_at = t;
  std::string why;
  for (; t < 400.0 && why.empty(); t += 1.0) {
    const double phase = std::fmod(t - stuck_at, 30.0);
    const double x = phase < 10.0 ? 1.8
                                  : (phase < 20.0 ? 1.8 - 0.13 * (phase - 10.0)
                                                  : 0.5 + 0.13 * (phase - 20.0));
    why = p.Update(t, {x, 0.0});
  }
  EXPECT_EQ("got no closer for 60 s, though moving", why);
  EXPECT_LE(t, stuck_at + GoalProgress::kMovingTimeouts * kTimeout + 2.0);
}

TEST(GoalProgressTest, ATimeoutThatIsNotPositiveIsRefusedByName) {
  for (double bad : {0.0, -1.0}) {
    try {
      GoalProgress p(bad);
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("progress_timeout"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
