// Tests of the RBPF SLAM core (rbpf_slam.h) and its resampling step.
#include "minibot3d_slam/rbpf_slam.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "parallel_for.h"
#include "resampling.h"
#include "minibot3d_testing/synthetic_world.h"

namespace minibot3d_slam {
namespace {

using minibot3d_testing::Office;
using minibot3d_testing::World;

TEST(ResamplingTest, DominantParticleIsCopiedEverywhere) {
  std::vector<double> w(20, 1e-9);
  w[13] = 1.0 - 19 * 1e-9;
  for (double u0 : {0.001, 0.01, 0.049}) {
    for (std::size_t parent : LowVarianceResample(w, u0)) EXPECT_EQ(parent, 13u) << u0;
  }
}

TEST(ResamplingTest, CopiesAreProportionalToWeights) {
  // Systematic resampling draws a particle of weight w floor(N·w) or ceil(N·w) times.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> w(30);
    double sum = 0.0;
    for (double& x : w) sum += (x = u(rng) * u(rng));
    for (double& x : w) x /= sum;
    const std::vector<std::size_t> parents = LowVarianceResample(w, u(rng) / 30.0);
    ASSERT_EQ(parents.size(), w.size());
    std::vector<int> copies(w.size(), 0);
    for (std::size_t p : parents) ++copies[p];
    for (std::size_t i = 0; i < w.size(); ++i) {
      EXPECT_GE(copies[i], static_cast<int>(std::floor(30 * w[i] - 1e-9))) << i;
      EXPECT_LE(copies[i], static_cast<int>(std::ceil(30 * w[i] + 1e-9))) << i;
    }
  }
  // Uniform weights: every particle once.
  const std::vector<std::size_t> same = LowVarianceResample(std::vector<double>(8, 0.125), 0.06);
  for (std::size_t i = 0; i < same.size(); ++i) EXPECT_EQ(same[i], i);
}

// A closed tour of the office: straight legs and turns in place, at scan rate.
std::vector<Pose2> Tour() {
  std::vector<Pose2> truth;
  Pose2 p{-4.5, -2.8, 0.0};
  auto go = [&](double dist, double step) {
    const int n = static_cast<int>(std::round(dist / step));
    for (int i = 0; i < n; ++i) {
      p = Compose(p, Pose2{step, 0.0, 0.0});
      truth.push_back(p);
    }
  };
  auto turn = [&](double angle) {
    const int n = static_cast<int>(std::round(std::fabs(angle) / 0.1));
    for (int i = 0; i < n; ++i) {
      p.yaw = NormalizeAngle(p.yaw + angle / n);
      truth.push_back(p);
    }
  };
  truth.push_back(p);
  for (int lap = 0; lap < 2; ++lap) {
    go(8.8, 0.1);
    turn(M_PI / 2);
    go(5.6, 0.1);
    turn(M_PI / 2);
    go(8.8, 0.1);
    turn(M_PI / 2);
    go(5.6, 0.1);
    turn(M_PI / 2);
  }
  return truth;
}

// Odometry along `truth` with a systematic rotation bias (3 %) and a scale error (2 %) plus noise,
// so that it drifts by decimetres over the tour.
std::vector<Pose2> NoisyOdometry(const std::vector<Pose2>& truth) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Pose2> odom{truth[0]};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Pose2 u = Between(truth[i - 1], truth[i]);
    u.x = u.x * 1.02 + 0.003 * noise(rng);
    u.y += 0.002 * noise(rng);
    u.yaw = u.yaw * 1.03 + 0.002 * noise(rng) + 0.0015 * std::fabs(u.x) / 0.1;
    odom.push_back(Compose(odom.back(), u));
  }
  return odom;
}

GmappingOptions TourOptions(int subcell_match, int sample_proposal) {
  GmappingOptions o;
  o.particles = 15;
  o.linearUpdate = 0.3;
  o.angularUpdate = 0.25;
  o.seed = 5;
  o.subcellMatch = subcell_match;
  o.sampleProposal = sample_proposal;
  return o;
}

void DriveTour(const World& world, const std::vector<Pose2>& truth, const std::vector<Pose2>& odom,
               RbpfSlam* slam) {
  for (std::size_t i = 0; i < truth.size(); ++i) {
    slam->AddScan(world.Scan(truth[i], 181, M_PI, 30.0, 0.1 * static_cast<double>(i)), odom[i]);
  }
}

// The tour with odometry that drifts by decimetres; the filter must stay close to the truth with
// every combination of the matcher's refinement and the paper's sampled proposal.
void CheckNoisyOdometryTour(int subcell_match, int sample_proposal) {
  const World world = Office();
  const std::vector<Pose2> truth = Tour();
  const std::vector<Pose2> odom = NoisyOdometry(truth);
  RbpfSlam slam(TourOptions(subcell_match, sample_proposal));
  DriveTour(world, truth, odom, &slam);
  EXPECT_GT(slam.processed_scans(), 60);
  // The map frame starts at the first odometry pose, which is the first true pose here.
  const std::vector<StampedPose> traj = slam.BestTrajectory();
  ASSERT_EQ(static_cast<int>(traj.size()), slam.processed_scans());
  double worst = 0.0, worst_odom = 0.0, sum = 0.0;
  for (const StampedPose& sp : traj) {
    const std::size_t i = static_cast<std::size_t>(std::lround(sp.time / 0.1));
    worst = std::max(worst, std::hypot(sp.pose.x - truth[i].x, sp.pose.y - truth[i].y));
    sum += std::hypot(sp.pose.x - truth[i].x, sp.pose.y - truth[i].y);
    worst_odom = std::max(worst_odom, std::hypot(odom[i].x - truth[i].x, odom[i].y - truth[i].y));
  }
  EXPECT_GT(worst_odom, 0.5);  // the odometry alone is far off
  // gmapping's matcher (5 cm cells, a deliberately wide score) is good to a few centimetres.
  EXPECT_LT(sum / static_cast<double>(traj.size()), 0.12);
  EXPECT_LT(worst, 0.25);
  const Pose2 last = slam.BestPose();
  EXPECT_LT(std::hypot(last.x - truth.back().x, last.y - truth.back().y), 0.15);
  EXPECT_LT(std::fabs(NormalizeAngle(last.yaw - truth.back().yaw)), 0.05);

  // Walls are where they are: sample points along every wall; nearly all must be occupied within
  // one cell, while the middle of the free corridor is free.
  const GridMap map = slam.Map();
  auto value = [&](double x, double y) {
    const int cx = static_cast<int>(std::floor((x - map.origin_x) / map.resolution));
    const int cy = static_cast<int>(std::floor((y - map.origin_y) / map.resolution));
    if (cx < 0 || cy < 0 || cx >= map.width || cy >= map.height) return -1;
    return static_cast<int>(map.data[static_cast<std::size_t>(cy) * map.width + cx]);
  };
  auto occupied_near = [&](double x, double y) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (value(x + dx * map.resolution, y + dy * map.resolution) == 100) return true;
      }
    }
    return false;
  };
  int samples = 0, hits = 0;
  for (const auto& s : {world.walls[0], world.walls[1], world.walls[2], world.walls[3]}) {
    for (double t = 0.05; t < 0.95; t += 0.02) {
      ++samples;
      hits += occupied_near(s.x0 + t * (s.x1 - s.x0), s.y0 + t * (s.y1 - s.y0)) ? 1 : 0;
    }
  }
  EXPECT_GT(hits, 0.9 * samples);
  for (double x = -4.0; x <= 4.0; x += 0.5) EXPECT_EQ(value(x, -2.8), 0) << x;
  EXPECT_EQ(value(0.0, 0.0), -1);  // inside the inner block: never seen
}

TEST(RbpfSlamTest, NoisyOdometryTourGivesTrajectoryAndMapCloseToTheTruth) {
  CheckNoisyOdometryTour(1, 0);  // the defaults
}

TEST(RbpfSlamTest, NoisyOdometryTourWithoutSubcellRefinement) { CheckNoisyOdometryTour(0, 0); }

TEST(RbpfSlamTest, NoisyOdometryTourWithTheSampledProposal) {
  CheckNoisyOdometryTour(1, 1);
  CheckNoisyOdometryTour(0, 1);
}

// Wheels slipping in a turn in place: in the second lap's first turn the odometry counts three
// times the rotation the robot makes (a quarter turn counted as three), as seen in a real log of a
// building (a turn in place counted four times over). With gmapping's update rule (a scan every
// 0.5 rad of counted turn) each processed scan is predicted about 0.33 rad off. One particle
// without motion noise, so that only the matcher decides: from the prediction its climb ends in a
// wrong optimum of the noisy scan (1 cm range noise), from the start turned back by turnSlip of
// the turn (the default) it finds the heading.
TEST(RbpfSlamTest, HeadingIsKeptWhenTheWheelsSlipInATurn) {
  const World world = Office();
  const std::vector<Pose2> truth = Tour();
  // The second lap's first turn: the fifth run of in-place steps.
  std::size_t turn_start = 0;
  int turns_seen = 0;
  for (std::size_t i = 2; i < truth.size() && turn_start == 0; ++i) {
    const bool turning = truth[i].yaw != truth[i - 1].yaw;
    const bool was_turning = truth[i - 1].yaw != truth[i - 2].yaw;
    if (turning && !was_turning && ++turns_seen == 5) turn_start = i;
  }
  ASSERT_GT(turn_start, 0u);
  std::vector<Pose2> odom{truth[0]};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Pose2 u = Between(truth[i - 1], truth[i]);
    if (i >= turn_start && i < turn_start + 16) u.yaw *= 3.0;
    odom.push_back(Compose(odom.back(), u));
  }
  for (double turn_slip : {0.5, 0.0}) {
    GmappingOptions o = TourOptions(1, 0);
    o.angularUpdate = 0.5;
    o.particles = 1;
    o.srr = o.srt = o.str = o.stt = 0.0;
    o.turnSlip = turn_slip;
    RbpfSlam slam(o);
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (std::size_t i = 0; i < truth.size(); ++i) {
      LaserScan scan = world.Scan(truth[i], 361, M_PI, 30.0, 0.1 * static_cast<double>(i));
      for (double& r : scan.ranges) {
        if (std::isfinite(r)) r += noise(rng);
      }
      slam.AddScan(scan, odom[i]);
    }
    double heading = 0.0;  // worst along the trajectory
    for (const StampedPose& sp : slam.BestTrajectory()) {
      const std::size_t k = static_cast<std::size_t>(std::lround(sp.time / 0.1));
      heading = std::max(heading, std::fabs(NormalizeAngle(sp.pose.yaw - truth[k].yaw)));
    }
    const Pose2 last = slam.BestPose();
    if (turn_slip > 0.0) {
      EXPECT_LT(heading, 0.03);
      EXPECT_LT(std::hypot(last.x - truth.back().x, last.y - truth.back().y), 0.1);
    } else {
      EXPECT_GT(heading, 0.2) << "the slip is caught without turnSlip: the test proves nothing";
    }
  }
}

// The particles are matched on `threads` threads; the proposal's random draws are made afterwards
// in particle order, so one thread and three give the same trajectory, bit for bit.
TEST(RbpfSlamTest, TheResultDoesNotDependOnTheThreadCount) {
  const World world = Office();
  std::vector<Pose2> truth = Tour();
  truth.resize(truth.size() / 3);  // two thirds of a lap
  const std::vector<Pose2> odom = NoisyOdometry(truth);
  for (int sample_proposal : {0, 1}) {
    std::vector<std::vector<StampedPose>> runs;
    for (int threads : {1, 3}) {
      GmappingOptions o = TourOptions(1, sample_proposal);
      o.threads = threads;
      RbpfSlam slam(o);
      DriveTour(world, truth, odom, &slam);
      runs.push_back(slam.BestTrajectory());
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    ASSERT_GT(runs[0].size(), 20u);
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
      EXPECT_EQ(runs[0][i].pose.x, runs[1][i].pose.x) << "sampleProposal " << sample_proposal << ", node " << i;
      EXPECT_EQ(runs[0][i].pose.y, runs[1][i].pose.y) << "sampleProposal " << sample_proposal << ", node " << i;
      EXPECT_EQ(runs[0][i].pose.yaw, runs[1][i].pose.yaw) << "sampleProposal " << sample_proposal;
    }
  }
}

TEST(ParallelForTest, EveryIndexRunsOnceAndAJobsExceptionReachesTheCaller) {
  for (int threads : {1, 2, 5}) {
    std::vector<int> runs(1000, 0);
    ParallelFor(runs.size(), threads, [&](std::size_t i) { ++runs[i]; });
    EXPECT_EQ(std::count(runs.begin(), runs.end(), 1), 1000) << threads << " threads";
    EXPECT_THROW(ParallelFor(runs.size(), threads,
                             [](std::size_t i) {
                               if (i == 17) throw std::runtime_error("job 17 failed");
                             }),
                 std::runtime_error)
        << threads << " threads";
  }
  ParallelFor(0, 2, [](std::size_t) { FAIL() << "no job expected"; });
  EXPECT_EQ(ResolveThreads(3), 3);
  EXPECT_GE(ResolveThreads(0), 1);
}

LaserScan WallScan(double time, int beams = 91) {
  // Facing a wall 3 m ahead and walls 2 m to both sides (a corridor's end).
  World w;
  w.AddBox(-5.0, -2.0, 3.0, 2.0);
  return w.Scan(Pose2{}, beams, M_PI, 30.0, time);
}

// What the filter keeps grows by a bounded amount per processed scan — one trajectory node and
// the loop closer's compact scan (a float range and a beam index a beam; directions are shared) —
// and not with the readings it skipped or the particles: the office tour driven four times,
// compared after two and after four laps. (Stored bytes are counted by the filter's accessors,
// not by RSS, so the test is exact.)
TEST(RbpfSlamTest, StoredBytesGrowByABoundedAmountPerProcessedScan) {
  const World world = Office();
  const std::vector<Pose2> tour = Tour();  // two laps, ending where it starts
  GmappingOptions o;
  o.particles = 5;
  o.linearUpdate = 0.3;
  o.angularUpdate = 0.25;
  o.seed = 3;
  ASSERT_EQ(o.loopClosure, 1);
  RbpfSlam slam(o);
  constexpr int kBeams = 181;
  std::size_t bytes_after_two = 0;
  int processed_after_two = 0;
  int fed = 0;
  for (int round = 0; round < 2; ++round) {
    for (const Pose2& p : tour) {
      slam.AddScan(world.Scan(p, kBeams, M_PI, 30.0, 0.1 * fed), p);
      ++fed;
    }
    if (round == 0) {
      bytes_after_two = slam.TrajectoryBytes() + slam.LoopScanBytes();
      processed_after_two = slam.processed_scans();
    }
  }
  const int processed = slam.processed_scans() - processed_after_two;
  ASSERT_GT(processed, 100);
  ASSERT_LT(slam.processed_scans(), fed / 2);  // most readings are not processed
  const double per_scan =
      static_cast<double>(slam.TrajectoryBytes() + slam.LoopScanBytes() - bytes_after_two) / processed;
  // Stored scan (8 bytes a beam + ~90 bytes of vectors) + node (~75 bytes with its allocation,
  // plus the particles' branches); ranges and angles as doubles would be 16 bytes a beam.
  EXPECT_LE(per_scan, 8.0 * kBeams + 256.0);
  EXPECT_GE(per_scan, 4.0 * kBeams);  // the stored scans are counted at all
  // The trajectory tree holds about one node per processed scan, not one per particle.
  EXPECT_LE(slam.TrajectoryBytes(), static_cast<std::size_t>(slam.processed_scans() + 50 * o.particles) * 96);
}

TEST(RbpfSlamTest, UpdatesAreTriggeredByMotionAndTime) {
  GmappingOptions o;
  o.particles = 3;
  o.linearUpdate = 0.5;
  o.angularUpdate = 0.3;
  o.temporalUpdate = 2.0;
  RbpfSlam slam(o);
  EXPECT_TRUE(slam.AddScan(WallScan(0.0), Pose2{}));  // the first scan always
  EXPECT_FALSE(slam.AddScan(WallScan(0.1), Pose2{0.2, 0.0, 0.0}));
  EXPECT_FALSE(slam.AddScan(WallScan(0.2), Pose2{0.4, 0.0, 0.0}));
  EXPECT_TRUE(slam.AddScan(WallScan(0.3), Pose2{0.55, 0.0, 0.0}));  // 0.55 m travelled
  EXPECT_FALSE(slam.AddScan(WallScan(0.4), Pose2{0.55, 0.0, 0.2}));
  EXPECT_TRUE(slam.AddScan(WallScan(0.5), Pose2{0.55, 0.0, 0.35}));  // 0.35 rad turned
  // Path length counts, not net displacement: forth and back 0.3 m each.
  EXPECT_FALSE(slam.AddScan(WallScan(0.6), Pose2{0.85, 0.0, 0.35}));
  EXPECT_TRUE(slam.AddScan(WallScan(0.7), Pose2{0.55, 0.0, 0.35}));
  // Standing still: only the temporal update fires, after more than 2 s.
  EXPECT_FALSE(slam.AddScan(WallScan(2.0), Pose2{0.55, 0.0, 0.35}));
  EXPECT_TRUE(slam.AddScan(WallScan(2.8), Pose2{0.55, 0.0, 0.35}));
  EXPECT_EQ(slam.processed_scans(), 5);
  EXPECT_EQ(slam.BestTrajectory().size(), 5u);
  // Without the temporal update, standing still never processes.
  o.temporalUpdate = -1.0;
  RbpfSlam still(o);
  EXPECT_TRUE(still.AddScan(WallScan(0.0), Pose2{}));
  for (int i = 1; i < 50; ++i) EXPECT_FALSE(still.AddScan(WallScan(i * 1.0), Pose2{}));
}

TEST(RbpfSlamTest, StopUpdateProcessesTheScanWhereTheRobotComesToRest) {
  GmappingOptions o;
  o.particles = 3;
  o.linearUpdate = 0.5;
  o.angularUpdate = 0.3;
  for (const bool stop_update : {false, true}) {
    SCOPED_TRACE(stop_update ? "stopUpdate on" : "stopUpdate off");
    o.stopUpdate = stop_update;
    RbpfSlam slam(o);
    EXPECT_TRUE(slam.AddScan(WallScan(0.0), Pose2{}));
    // Driving 0.2 m (below linearUpdate) and stopping: the first scan at rest is the stop's.
    EXPECT_FALSE(slam.AddScan(WallScan(0.1), Pose2{0.1, 0.0, 0.0}));
    EXPECT_FALSE(slam.AddScan(WallScan(0.2), Pose2{0.2, 0.0, 0.0}));
    EXPECT_EQ(slam.AddScan(WallScan(0.3), Pose2{0.2, 0.0, 0.0}), stop_update);
    // Standing on: nothing more, whichever way.
    EXPECT_FALSE(slam.AddScan(WallScan(0.4), Pose2{0.2, 0.0, 0.0}));
    // Turning 0.1 rad on the spot and stopping is a stop too.
    EXPECT_FALSE(slam.AddScan(WallScan(0.5), Pose2{0.2, 0.0, 0.1}));
    EXPECT_EQ(slam.AddScan(WallScan(0.6), Pose2{0.2, 0.0, 0.1}), stop_update);
    // Odometry jitter below 2 cm and 0.02 rad since the last processed scan is not a stop.
    EXPECT_FALSE(slam.AddScan(WallScan(0.7), Pose2{0.21, 0.0, 0.1}));
    EXPECT_FALSE(slam.AddScan(WallScan(0.8), Pose2{0.21, 0.0, 0.1}));
    // Slowing to a crawl (a millimetre a scan) is not a stop; the stop after it is.
    EXPECT_FALSE(slam.AddScan(WallScan(0.9), Pose2{0.215, 0.0, 0.1}));
    EXPECT_FALSE(slam.AddScan(WallScan(1.0), Pose2{0.25, 0.0, 0.1}));
    EXPECT_FALSE(slam.AddScan(WallScan(1.1), Pose2{0.252, 0.0, 0.1}));
    EXPECT_EQ(slam.AddScan(WallScan(1.2), Pose2{0.2525, 0.0, 0.1}), stop_update);
    EXPECT_EQ(slam.processed_scans(), stop_update ? 4 : 1);
  }
}

TEST(RbpfSlamTest, PoseBetweenProcessedScansFollowsOdometry) {
  GmappingOptions o;
  o.particles = 4;
  RbpfSlam slam(o);
  const Pose2 start{1.0, 2.0, 0.5};
  slam.AddScan(WallScan(0.0), start);
  EXPECT_NEAR(slam.BestPose().x, 1.0, 1e-12);  // the map frame starts at the first odometry pose
  const Pose2 odom = Compose(start, Pose2{0.2, 0.05, 0.1});
  EXPECT_FALSE(slam.AddScan(WallScan(0.1), odom));
  const Pose2 best = slam.BestPose();
  EXPECT_NEAR(best.x, odom.x, 1e-9);
  EXPECT_NEAR(best.y, odom.y, 1e-9);
  const Pose2 back = Compose(slam.MapToOdom(), odom);
  EXPECT_NEAR(back.x, best.x, 1e-9);
  EXPECT_NEAR(back.y, best.y, 1e-9);
  EXPECT_NEAR(NormalizeAngle(back.yaw - best.yaw), 0.0, 1e-9);
  EXPECT_GE(slam.Entropy(), 0.0);
  EXPECT_LE(slam.Entropy(), std::log(4.0) + 1e-9);
}

// Localize (readings between processed scans): down a bare corridor the heading and the position
// across it come from the map, the position along it stays the guess's (nothing there measures it);
// in a room every component comes from the map.
TEST(RbpfSlamTest, LocalizeTakesFromTheMapWhatTheMapMeasures) {
  GmappingOptions o;
  o.particles = 1;
  o.linearUpdate = 0.2;
  o.loopClosure = 0;
  // A corridor 2 m wide and 100 m long, its walls off the cell boundaries, its ends out of reach.
  World corridor;
  corridor.walls.push_back({-50.0, -0.987, 50.0, -0.987});
  corridor.walls.push_back({-50.0, 1.013, 50.0, 1.013});
  // Range noise of about a centimetre (fixed, so the test is repeatable).
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  const auto noisy = [&](LaserScan scan) {
    for (double& r : scan.ranges) {
      if (std::isfinite(r)) r += noise(rng);
    }
    return scan;
  };
  RbpfSlam slam(o);
  for (int i = 0; i <= 40; ++i) {
    const Pose2 pose{0.1 * i, 0.0, 0.0};
    slam.AddScan(noisy(corridor.Scan(pose, 181, M_PI, 8.0, 0.1 * i)), pose);
  }
  const Pose2 truth{2.5, 0.1, 0.02};
  const LaserScan scan = noisy(corridor.Scan(truth, 181, M_PI, 8.0));
  const Pose2 guess{2.5 + 0.15, 0.1 + 0.03, 0.02 + 0.04};
  const Pose2 found = slam.Localize(scan, guess);
  EXPECT_NEAR(found.x, guess.x, 0.02);  // along: the guess's (the climb alone wandered 0.12 m)
  EXPECT_NEAR(found.y, truth.y, 0.01);
  EXPECT_NEAR(NormalizeAngle(found.yaw - truth.yaw), 0.0, 0.005);

  const World office = Office();
  RbpfSlam room(o);
  for (int i = 0; i <= 20; ++i) {
    const Pose2 pose{-3.0 + 0.1 * i, -1.5, 0.0};
    room.AddScan(office.Scan(pose, 181, M_PI, 30.0, 0.1 * i), pose);
  }
  const Pose2 at{-2.0, -1.5, 0.0};
  const Pose2 off{-2.0 + 0.03, -1.5 - 0.02, 0.04};
  const Pose2 matched = room.Localize(office.Scan(at, 181, M_PI, 30.0), off);
  EXPECT_NEAR(matched.x, at.x, 0.01);
  EXPECT_NEAR(matched.y, at.y, 0.01);
  EXPECT_NEAR(NormalizeAngle(matched.yaw - at.yaw), 0.0, 0.005);
}

TEST(RbpfSlamTest, BadReadingsAndOddScansAreHandled) {
  GmappingOptions o;
  o.particles = 5;
  o.linearUpdate = 0.1;
  RbpfSlam slam(o);
  World w;
  w.AddBox(-5.0, -2.0, 3.0, 2.0);
  w.AddBox(1.0, 1.0, 1.5, 1.5);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  LaserScan s = w.Scan(Pose2{}, 91, M_PI, 30.0, 0.0);
  s.ranges[3] = nan;
  s.ranges[10] = inf;
  s.ranges[11] = -inf;
  s.ranges[12] = 0.0;
  s.ranges[20] = 1e9;
  EXPECT_TRUE(slam.AddScan(s, Pose2{}));
  // Fewer beams, in reversed order, over a narrower field of view.
  LaserScan few = w.Scan(Pose2{0.15, 0.0, 0.0}, 31, 2.0, 30.0, 0.1);
  std::reverse(few.ranges.begin(), few.ranges.end());
  std::reverse(few.angles.begin(), few.angles.end());
  EXPECT_TRUE(slam.AddScan(few, Pose2{0.15, 0.0, 0.0}));
  LaserScan all_bad = w.Scan(Pose2{0.3, 0.0, 0.0}, 91, M_PI, 30.0, 0.2);
  for (double& r : all_bad.ranges) r = nan;
  EXPECT_TRUE(slam.AddScan(all_bad, Pose2{0.3, 0.0, 0.0}));
  LaserScan empty;
  empty.time = 0.3;
  EXPECT_TRUE(slam.AddScan(empty, Pose2{0.45, 0.0, 0.0}));
  // A sensor mounted 0.2 m ahead of the base and turned by 0.3 rad.
  const Pose2 mount{0.2, 0.0, 0.3};
  LaserScan mounted = w.Scan(Compose(Pose2{0.6, 0.0, 0.0}, mount), 181, M_PI, 30.0, 0.4);
  mounted.sensor_in_base = mount;
  EXPECT_TRUE(slam.AddScan(mounted, Pose2{0.6, 0.0, 0.0}));
  EXPECT_EQ(slam.processed_scans(), 5);
  const Pose2 p = slam.BestPose();
  EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw));
  EXPECT_LT(std::hypot(p.x - 0.6, p.y), 0.05);
  EXPECT_LT(std::fabs(p.yaw), 0.03);
  LaserScan mismatched = w.Scan(Pose2{0.6, 0.0, 0.0});
  mismatched.angles.pop_back();
  EXPECT_THROW(slam.AddScan(mismatched, Pose2{0.7, 0.0, 0.0}), std::invalid_argument);
}

TEST(RbpfSlamTest, MapStartsAtTheConfiguredExtentAndGrows) {
  GmappingOptions o;
  o.particles = 2;
  o.xmin = -2.0;
  o.ymin = -1.0;
  o.xmax = 2.0;
  o.ymax = 1.0;
  RbpfSlam slam(o);
  GridMap empty = slam.Map();
  EXPECT_EQ(empty.width, 80);
  EXPECT_EQ(empty.height, 40);
  EXPECT_DOUBLE_EQ(empty.origin_x, -2.0);
  slam.AddScan(WallScan(0.0), Pose2{});
  const GridMap m = slam.Map();
  // The walls seen (x = 3 ahead, y = ±2 aside) lie outside the initial extent.
  EXPECT_GE(m.origin_x + m.width * m.resolution, 3.0);
  EXPECT_LE(m.origin_y, -2.0);
  EXPECT_GE(m.origin_y + m.height * m.resolution, 2.0);
  int occupied = 0;
  for (auto v : m.data) occupied += v == 100;
  EXPECT_GT(occupied, 50);
}

TEST(RbpfSlamTest, InvalidOptionsAreRejected) {
  GmappingOptions o;
  o.particles = 0;
  EXPECT_THROW(RbpfSlam{o}, std::invalid_argument);
}

}  // namespace
}  // namespace minibot3d_slam
