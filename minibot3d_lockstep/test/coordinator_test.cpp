#include "minibot3d_lockstep/coordinator.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_lockstep {
namespace {

using Names = std::vector<std::string>;
constexpr double kQ = 0.005;

Coordinator Make() {
  CoordinatorOptions o;
  o.quantum = kQ;
  o.timeout = 2.0;
  return Coordinator(o, "/sim");
}

TEST(CoordinatorTest, RejectsBadOptionsNamingThem) {
  CoordinatorOptions o;
  o.quantum = 0.0;
  try {
    ValidateOptions(o);
    FAIL() << "quantum 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lockstep_quantum"), std::string::npos);
  }
  o.quantum = 0.01;
  o.timeout = -1;
  EXPECT_THROW(ValidateOptions(o), std::invalid_argument);
}

TEST(CoordinatorTest, RefusesEmptyAndSimulatorNames) {
  Coordinator c = Make();
  EXPECT_FALSE(c.Register("", {}).empty());
  EXPECT_FALSE(c.Register("/sim", {}).empty());
  EXPECT_TRUE(c.Register("/a", {}).empty());
  EXPECT_EQ(c.Participants(), Names({"/a"}));
}

TEST(CoordinatorTest, NewParticipantIsDueOnceThenOnlyAtItsWakeTime) {
  Coordinator c = Make();
  c.Register("/b", {});
  c.Register("/a", {});
  EXPECT_EQ(c.Due(0.0), Names({"/a", "/b"}));  // name order
  c.MarkTicked("/a", 1, 0.0, 100.0);
  EXPECT_EQ(c.Due(0.0), Names({"/b"}));  // /a is waiting: never ticked twice
  EXPECT_EQ(c.Waiting(), Names({"/a"}));
  ASSERT_TRUE(c.Ack("/a", 1, 0.05, {}));
  c.MarkTicked("/b", 2, 0.0, 100.0);
  ASSERT_TRUE(c.Ack("/b", 2, 0.0, {}));  // 0: only on mail
  EXPECT_TRUE(c.Waiting().empty());
  EXPECT_TRUE(c.Due(0.045).empty());
  EXPECT_EQ(c.Due(0.05), Names({"/a"}));
  EXPECT_TRUE(c.Due(1000.0) == Names({"/a"}));  // /b never wakes without mail
}

TEST(CoordinatorTest, StaleOrUnknownAcksChangeNothing) {
  Coordinator c = Make();
  c.Register("/a", {});
  EXPECT_FALSE(c.Ack("/a", 1, 0.1, {}));  // not ticked yet
  c.MarkTicked("/a", 7, 0.0, 0.0);
  EXPECT_FALSE(c.Ack("/a", 6, 0.1, {}));
  EXPECT_FALSE(c.Ack("/nobody", 7, 0.1, {}));
  EXPECT_EQ(c.Waiting(), Names({"/a"}));
  EXPECT_TRUE(c.Ack("/a", 7, 0.1, {}));
}

TEST(CoordinatorTest, AWakeTimeNoLaterThanTheTickMeansTheNextQuantum) {
  Coordinator c = Make();
  c.Register("/a", {});
  c.MarkTicked("/a", 1, 1.0, 0.0);
  c.Ack("/a", 1, 0.5, {});
  EXPECT_TRUE(c.Due(1.0).empty());
  EXPECT_EQ(c.Due(1.0 + kQ), Names({"/a"}));
}

TEST(CoordinatorTest, MailOnAWakeTopicWakesOnlyItsReceiver) {
  Coordinator c = Make();
  c.Register("/amcl", {"/scan", "/initialpose"});
  c.Register("/move_base", {"/move_base/goal"});
  for (const char* n : {"/amcl", "/move_base"}) {
    c.MarkTicked(n, 1, 0.0, 0.0);
    c.Ack(n, 1, 0.0, {});
  }
  EXPECT_TRUE(c.Due(0.005).empty());
  // The simulator queued a scan to both and a tf message to both; only /scan wakes, only /amcl
  // (move_base does not list it).
  c.SetSent("/sim", {{"/scan", "/amcl", 1}, {"/scan", "/move_base", 1}, {"/tf", "/amcl", 3},
                     {"/tf", "/move_base", 3}});
  EXPECT_EQ(c.Due(0.005), Names({"/amcl"}));
  c.MarkTicked("/amcl", 2, 0.005, 0.0);
  c.Ack("/amcl", 2, 0.0, {{"/tf", "/move_base", 1}});
  EXPECT_TRUE(c.Due(0.01).empty());  // mail seen; tf is not a wake topic
  c.SetSent("/sim", {{"/scan", "/amcl", 2}, {"/scan", "/move_base", 2}});
  EXPECT_EQ(c.Due(0.01), Names({"/amcl"}));
}

TEST(CoordinatorTest, ExpectedListsWhatOthersQueuedToTheParticipant) {
  Coordinator c = Make();
  c.Register("/a", {});
  c.Register("/b", {});
  c.SetSent("/sim", {{"/scan", "/a", 10}, {"/scan", "/b", 9}, {"/scan", "/rviz", 10}});
  c.MarkTicked("/a", 1, 0.0, 0.0);
  c.Ack("/a", 1, 0.0, {{"/cmd_vel", "/sim", 4}, {"/tf", "/b", 2}, {"/tf", "/rviz", 2}});
  const auto e = c.Expected("/b");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0], (LinkCount{"/tf", "/a", 2}));
  EXPECT_EQ(e[1], (LinkCount{"/scan", "/sim", 9}));
  const auto s = c.Expected("/sim");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0], (LinkCount{"/cmd_vel", "/a", 4}));
  // Non-participants (rviz) are never waited on: nothing lists them.
  EXPECT_TRUE(c.Expected("/rviz").empty());
}

TEST(CoordinatorTest, AStalledParticipantIsOverdueAfterTheTimeoutAndRemovalForgetsIt) {
  Coordinator c = Make();
  c.Register("/a", {});
  c.Register("/b", {});
  c.MarkTicked("/a", 1, 0.0, 10.0);
  EXPECT_TRUE(c.Overdue(11.9).empty());
  EXPECT_NEAR(c.WaitingFor("/a", 11.0), 1.0, 1e-12);
  EXPECT_EQ(c.Overdue(12.1), Names({"/a"}));
  c.Ack("/a", 1, 0.0, {{"/tf", "/b", 5}});
  c.MarkTicked("/a", 2, 0.005, 20.0);
  EXPECT_TRUE(c.Remove("/a"));
  EXPECT_FALSE(c.Remove("/a"));
  EXPECT_TRUE(c.Waiting().empty());
  EXPECT_TRUE(c.Expected("/b").empty());  // /b no longer waits for /a's messages
  EXPECT_EQ(c.Participants(), Names({"/b"}));
}

// The default: a participant that is alive is waited for however long it takes (a loaded machine,
// a debugger); only its process going away drops it (the simulator's side).
TEST(CoordinatorTest, WithoutATimeoutNoParticipantIsEverOverdue) {
  CoordinatorOptions o;
  EXPECT_EQ(o.timeout, 0.0);
  EXPECT_NO_THROW(ValidateOptions(o));
  Coordinator c(o, "/sim");
  c.Register("/a", {});
  c.MarkTicked("/a", 1, 0.0, 10.0);
  EXPECT_TRUE(c.Overdue(10.0 + 3600.0).empty());
  EXPECT_NEAR(c.WaitingFor("/a", 3610.0), 3600.0, 1e-9);
  EXPECT_EQ(c.Waiting(), Names({"/a"}));
}

TEST(CoordinatorTest, AHeartbeatRestartsTheTimeoutButIsNotAnAcknowledgement) {
  Coordinator c = Make();  // timeout 2 s
  c.Register("/a", {});
  c.MarkTicked("/a", 1, 0.0, 10.0);
  EXPECT_FALSE(c.Heartbeat("/a", 2, 11.5));  // not the tick it holds
  EXPECT_TRUE(c.Heartbeat("/a", 1, 11.5));
  EXPECT_TRUE(c.Overdue(13.0).empty());  // 1.5 s since the heartbeat
  EXPECT_EQ(c.Overdue(13.6), Names({"/a"}));
  EXPECT_EQ(c.Waiting(), Names({"/a"}));
  EXPECT_FALSE(c.Heartbeat("/b", 1, 11.0));
}

TEST(CoordinatorTest, ARestartedParticipantStartsAfresh) {
  Coordinator c = Make();
  c.Register("/a", {});
  c.Register("/b", {});
  c.MarkTicked("/a", 1, 0.0, 0.0);
  c.Ack("/a", 1, 0.0, {{"/tf", "/b", 50}});
  ASSERT_EQ(c.Expected("/b").size(), 1u);
  c.Register("/a", {});  // same name again: its old connections are gone
  EXPECT_TRUE(c.Expected("/b").empty());
  EXPECT_EQ(c.Due(0.0), Names({"/a", "/b"}));
}

// Several robots, each with its own stack in a namespace: participants /robot1/amcl,
// /robot1/move_base, /robot10/amcl, ... on one clock. Mail follows the full topic name (robot1's
// scan wakes robot1's amcl only; a match on the last name segment would wake both amcls), and a
// stalled node is dropped by its exact name (a match on a name prefix would drop /robot10's
// nodes, or their counts, with /robot1's).
TEST(CoordinatorTest, NamespacedRobotsMailAndDropsStayWithinTheirRobot) {
  Coordinator c = Make();  // timeout 2 s
  const Names all = {"/robot1/amcl", "/robot1/move_base", "/robot10/amcl", "/robot10/move_base"};
  for (const char* r : {"/robot1", "/robot10"}) {
    const std::string ns = r;
    c.Register(ns + "/amcl", {ns + "/scan", ns + "/initialpose", "/map"});
    c.Register(ns + "/move_base", {ns + "/move_base/goal"});
  }
  EXPECT_EQ(c.Participants(), all);
  std::uint64_t seq = 0;
  for (const auto& n : all) {
    c.MarkTicked(n, ++seq, 0.0, 0.0);
    ASSERT_TRUE(c.Ack(n, seq, 0.0, {}));
  }
  // The simulator queues each robot's scan to its own amcl, and tf to everyone.
  c.SetSent("/sim", {{"/robot1/scan", "/robot1/amcl", 1}, {"/tf", "/robot1/amcl", 4},
                     {"/tf", "/robot10/amcl", 4}, {"/tf", "/robot1/move_base", 4},
                     {"/tf", "/robot10/move_base", 4}});
  EXPECT_EQ(c.Due(kQ), Names({"/robot1/amcl"}));
  c.SetSent("/sim", {{"/robot1/scan", "/robot1/amcl", 1}, {"/robot10/scan", "/robot10/amcl", 1}});
  EXPECT_EQ(c.Due(kQ), Names({"/robot1/amcl", "/robot10/amcl"}));

  // Both amcls answer; robot1's move_base takes a goal and then stalls.
  for (const char* n : {"/robot1/amcl", "/robot10/amcl"}) {
    c.MarkTicked(n, ++seq, kQ, 1.0);
    ASSERT_TRUE(c.Ack(n, seq, 0.0, {{"/tf", "/robot1/move_base", 2},
                                    {"/tf", "/robot10/move_base", 2}}));
  }
  c.MarkTicked("/robot1/move_base", ++seq, 0.05, 1.0);
  c.MarkTicked("/robot10/move_base", ++seq, 0.05, 1.0);
  ASSERT_TRUE(c.Ack("/robot10/move_base", seq, 0.1, {{"/robot10/cmd_vel", "/sim", 1}}));
  EXPECT_EQ(c.Overdue(3.5), Names({"/robot1/move_base"}));
  ASSERT_TRUE(c.Remove("/robot1/move_base"));

  EXPECT_EQ(c.Participants(), Names({"/robot1/amcl", "/robot10/amcl", "/robot10/move_base"}));
  EXPECT_TRUE(c.Waiting().empty());
  // robot10's move_base still waits for what both amcls sent it, and wakes at its own time.
  EXPECT_EQ(c.Expected("/robot10/move_base").size(), 2u);
  EXPECT_EQ(c.Due(0.1), Names({"/robot10/move_base"}));
  // The simulator still waits for robot10's command.
  const auto to_sim = c.Expected("/sim");
  ASSERT_EQ(to_sim.size(), 1u);
  EXPECT_EQ(to_sim[0], (LinkCount{"/robot10/cmd_vel", "/robot10/move_base", 1}));
  EXPECT_FALSE(c.Remove("/robot1/move_base"));
  EXPECT_TRUE(c.Has("/robot10/move_base"));
}

}  // namespace
}  // namespace minibot3d_lockstep
