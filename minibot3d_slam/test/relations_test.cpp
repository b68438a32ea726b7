// The relations metric (Kümmerle et al. 2009): files, matching, errors, generation.
#include "minibot3d_slam/relations.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace minibot3d_slam {
namespace {

namespace fs = std::filesystem;

class RelationsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "relations_test.XXXXXX").string();
    ASSERT_NE(::mkdtemp(&tmpl[0]), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  fs::path dir_;
};

// A figure-eight-ish drive at 10 Hz for `seconds`: turning and translating, so that errors in
// heading show up in translation of later relations.
std::vector<StampedPose> Drive(double seconds, double t0 = 100.0) {
  std::vector<StampedPose> poses;
  Pose2 p;
  for (int k = 0; k * 0.1 <= seconds + 1e-9; ++k) {
    poses.push_back(StampedPose{t0 + k * 0.1, p});
    const double turn = 0.3 * std::sin(0.2 * k * 0.1);
    p = Compose(p, Pose2{0.05, 0.0, turn * 0.1});
  }
  return poses;
}

TEST(RelationsMetric, PerfectEstimateHasZeroError) {
  const auto truth = Drive(30.0);
  const auto relations = MakeRelations(truth);
  ASSERT_GT(relations.size(), 30u);
  const RelationsReport r = EvaluateRelations(truth, relations);
  EXPECT_EQ(r.total, static_cast<int>(relations.size()));
  EXPECT_EQ(r.used, r.total);
  EXPECT_EQ(r.unmatched, 0);
  EXPECT_EQ(r.exact_matches, 2 * r.used);
  EXPECT_EQ(r.nearest_matches, 0);
  EXPECT_NEAR(r.translation.mean, 0.0, 1e-12);
  EXPECT_NEAR(r.translation.max, 0.0, 1e-12);
  EXPECT_NEAR(r.rotation.max, 0.0, 1e-12);
}

TEST(RelationsMetric, RigidlyMovedEstimateHasZeroError) {
  // Relations only see local geometry: the same trajectory in another frame is as good.
  const auto truth = Drive(20.0);
  auto moved = truth;
  const Pose2 offset{3.0, -2.0, 1.2};
  for (auto& p : moved) p.pose = Compose(offset, p.pose);
  const RelationsReport r = EvaluateRelations(moved, MakeRelations(truth));
  EXPECT_GT(r.used, 0);
  EXPECT_NEAR(r.translation.max, 0.0, 1e-9);
  EXPECT_NEAR(r.rotation.max, 0.0, 1e-9);
}

TEST(RelationsMetric, ConstantScaleBiasGivesKnownError) {
  // Straight along x at 1 m/s; the estimate overestimates distance by 10 %: a relation over
  // Δt seconds is off by 0.1 Δt m, and not at all in rotation.
  std::vector<StampedPose> truth, estimate;
  for (int k = 0; k <= 100; ++k) {
    const double t = k * 0.1;
    truth.push_back(StampedPose{t, Pose2{t, 0.0, 0.0}});
    estimate.push_back(StampedPose{t, Pose2{1.1 * t, 0.0, 0.0}});
  }
  std::vector<Relation> relations;
  for (double span : {1.0, 2.0, 3.0}) {
    relations.push_back(Relation{2.0, 2.0 + span, Pose2{span, 0.0, 0.0}});
  }
  const RelationsReport r = EvaluateRelations(estimate, relations);
  ASSERT_EQ(r.used, 3);
  EXPECT_NEAR(r.translation.mean, 0.2, 1e-9);          // (0.1 + 0.2 + 0.3) / 3
  EXPECT_NEAR(r.translation.stddev, 0.1, 1e-9);        // sample std of 0.1, 0.2, 0.3
  EXPECT_NEAR(r.translation.max, 0.3, 1e-9);
  EXPECT_NEAR(r.translation_sq.mean, 0.14 / 3, 1e-9);  // (0.01 + 0.04 + 0.09) / 3
  EXPECT_NEAR(r.rotation.mean, 0.0, 1e-12);
  ASSERT_EQ(r.errors.size(), 3u);
  EXPECT_NEAR(r.errors[2].x, 0.3, 1e-9);  // the estimate went too far: positive along x
}

TEST(RelationsMetric, ConstantHeadingBiasGivesKnownError) {
  // The estimate's heading drifts by 0.01 rad/s while the robot turns on the spot: rotational
  // error 0.01 Δt rad per relation, no translational error; errors are wrapped to [-π, π).
  std::vector<StampedPose> truth, estimate;
  for (int k = 0; k <= 100; ++k) {
    const double t = k * 0.1;
    truth.push_back(StampedPose{t, Pose2{1.0, 2.0, NormalizeAngle(0.5 * t)}});
    estimate.push_back(StampedPose{t, Pose2{1.0, 2.0, NormalizeAngle(0.51 * t)}});
  }
  const RelationsReport r =
      EvaluateRelations(estimate, {Relation{1.0, 3.0, Pose2{0, 0, 1.0}},
                                   Relation{0.0, 8.0, Pose2{0, 0, NormalizeAngle(4.0)}}});
  ASSERT_EQ(r.used, 2);
  EXPECT_NEAR(r.translation.max, 0.0, 1e-12);
  EXPECT_NEAR(r.rotation.mean, (0.02 + 0.08) / 2, 1e-9);
  EXPECT_NEAR(r.rotation.max, 0.08, 1e-9);
  EXPECT_NE(FormatReport(r).find("relations 2 translation_m 0.0000 ± 0.0000 rotation_deg 2.865 ± "),
            std::string::npos)
      << FormatReport(r);
}

TEST(RelationsMetric, UnmatchedRelationsAreCountedAndNearestMatchesReported) {
  std::vector<StampedPose> estimate;
  for (int k = 0; k <= 50; ++k) {
    const double t = k * 0.1 + 0.0004;
    if (t > 2.01 && t < 2.99) continue;  // nothing between 2.0 and 3.0 s
    estimate.push_back(StampedPose{t, Pose2{k * 0.1, 0, 0}});
  }
  const std::vector<Relation> relations = {
      Relation{1.0, 2.0, Pose2{1.0, 0, 0}},    // both exact (0.4 ms off)
      Relation{1.0, 1.52, Pose2{0.5, 0, 0}},   // 1.52 -> nearest 1.5004 (19.6 ms)
      Relation{1.0, 2.5, Pose2{1.5, 0, 0}},    // 2.5 is 0.5 s from any pose: unmatched
      Relation{4.0, 9.0, Pose2{5.0, 0, 0}},    // after the end: unmatched
      Relation{-1.0, 0.5, Pose2{1.5, 0, 0}}};  // before the start: unmatched
  const RelationsReport r = EvaluateRelations(estimate, relations);
  EXPECT_EQ(r.total, 5);
  EXPECT_EQ(r.used, 2);
  EXPECT_EQ(r.unmatched, 3);
  EXPECT_EQ(r.exact_matches, 3);
  EXPECT_EQ(r.nearest_matches, 1);
  EXPECT_NEAR(r.max_time_offset, 0.0196, 1e-9);
  EXPECT_NEAR(r.translation.max, 0.0, 1e-9);
  // A tighter tolerance turns the nearest match into an unmatched relation.
  MatchOptions strict;
  strict.nearest_tolerance = 0.01;
  EXPECT_EQ(EvaluateRelations(estimate, relations, strict).unmatched, 4);
}

TEST(RelationsMetric, MakeRelationsIsReproducibleAndWithinSpan) {
  const auto truth = Drive(60.0);
  MakeRelationsOptions o;
  o.every = 2.0;
  o.max_span = 5.0;
  o.random_per_anchor = 2;
  o.seed = 7;
  const auto a = MakeRelations(truth, o);
  const auto b = MakeRelations(truth, o);
  ASSERT_EQ(a.size(), b.size());
  std::set<std::pair<double, double>> pairs;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].t1, b[k].t1);
    EXPECT_EQ(a[k].t2, b[k].t2);
    EXPECT_GT(a[k].t2, a[k].t1);
    EXPECT_TRUE(pairs.emplace(a[k].t1, a[k].t2).second) << "duplicate relation";
    if (k > 0) {
      EXPECT_LE(a[k - 1].t1, a[k].t1) << "not sorted by t1";
    }
  }
  // 31 anchors (0, 2, ..., 60 s): 30 consecutive pairs (span 2 s <= 5 s, so possibly also drawn
  // at random) and 2 random ones each except the last anchor, which has nothing after it.
  EXPECT_GE(a.size(), 60u);
  EXPECT_LE(a.size(), 90u);
  for (const auto& r : a) {
    const bool consecutive = std::abs(r.t2 - r.t1 - 2.0) < 1e-6;
    EXPECT_TRUE(consecutive || r.t2 - r.t1 <= 5.0 + 1e-9) << r.t1 << " " << r.t2;
  }
  o.seed = 8;
  const auto c = MakeRelations(truth, o);
  bool differs = c.size() != a.size();
  for (std::size_t k = 0; !differs && k < a.size(); ++k) differs = a[k].t2 != c[k].t2;
  EXPECT_TRUE(differs) << "the seed does not change the random relations";
  EXPECT_THROW(MakeRelations(truth, MakeRelationsOptions{1.0, 0.0, 3, 0}), RelationsError);
}

TEST_F(RelationsTest, FilesRoundTripExactly) {
  const auto truth = Drive(10.0, 1700000000.123456);
  const std::string traj = (dir_ / "gt.txt").string();
  const std::string rel = (dir_ / "gt.relations").string();
  WriteTrajectory(traj, truth, "ground truth\nsecond line");
  WriteRelations(rel, MakeRelations(truth), "made in a test");
  const auto read_truth = ReadTrajectory(traj);
  ASSERT_EQ(read_truth.size(), truth.size());
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_EQ(read_truth[k].time, truth[k].time);
    EXPECT_EQ(read_truth[k].pose.yaw, truth[k].pose.yaw);
  }
  const RelationsReport r = EvaluateRelations(read_truth, ReadRelations(rel));
  EXPECT_EQ(r.unmatched, 0);
  EXPECT_EQ(r.translation.max, 0.0);
  // Only the two files, no temporaries.
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"gt.txt", "gt.relations"}));
}

TEST_F(RelationsTest, ReadsCommentsBlankLinesAndUnsortedPoses) {
  const std::string path = Write("t.txt",
                                 "# timestamp x y theta\n"
                                 "\n"
                                 "2.0 1 0 0   # trailing comment\n"
                                 "1.0 0 0 0\n"
                                 "   \t\n"
                                 "3e0 2 0 0.5\n");
  const auto poses = ReadTrajectory(path);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[0].time, 1.0);
  EXPECT_EQ(poses[2].pose.yaw, 0.5);
  const std::string rel = Write("r.relations", "1 2 1 0 0 0 0 0\n2 3 1 0 9 0.1 0.2 0.5\n");
  const auto relations = ReadRelations(rel);
  ASSERT_EQ(relations.size(), 2u);
  EXPECT_EQ(relations[1].delta.yaw, 0.5);  // yaw is the 8th column
  EXPECT_EQ(relations[1].delta.x, 1.0);
}

TEST_F(RelationsTest, BadLinesAreNamed) {
  auto expect = [](const std::function<void()>& f, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "no RelationsError; expected '" << needle << "'";
    } catch (const RelationsError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const std::string t = Write("t.txt", "# header\n0 0 0 0\n1 0 0\n");
  expect([&] { ReadTrajectory(t); }, t + ":3: expected 4 numbers");
  const std::string n = Write("n.txt", "0 0 0 0\n1 0 zero 0\n");
  expect([&] { ReadTrajectory(n); }, n + ":2: 'zero' is not a finite number");
  const std::string i = Write("i.txt", "0 0 0 nan\n");
  expect([&] { ReadTrajectory(i); }, i + ":1:");
  const std::string r = Write("r.relations", "1 2 1 0 0 0 0 0\n\n1 2 1 0 0 0\n");
  expect([&] { ReadRelations(r); }, r + ":3: expected 8 numbers");
  const std::string e = Write("e.txt", "# nothing\n\n");
  expect([&] { ReadTrajectory(e); }, e + "' has no data lines");
  expect([&] { ReadRelations((dir_ / "absent").string()); }, "cannot open relations file");
  expect([&] { WriteRelations((dir_ / "no" / "dir.relations").string(), {}); },
         (dir_ / "no" / "dir.relations").string());
}

}  // namespace
}  // namespace minibot3d_slam
