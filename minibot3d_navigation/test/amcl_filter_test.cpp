// End-to-end tests of the AMCL filter on a synthetic 10 m x 8 m room with
// asymmetric furniture: tracking from a wrong-ish Gaussian guess, global
// localization from a uniform set, kidnapping recovery, the update gating,
// and the error handling for bad configuration and bad inputs; the
// confidence claim (split sets, unexplained scans, no claim before motion)
// and global localization / kidnapping with the map-wide search.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "amcl_test_utils.h"
#include "minibot3d_navigation/amcl/amcl_filter.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Drives a simulated robot: true pose in the map, odometry with 2 % / 0.5 deg
// noise per step in a drifting odometry frame, 360-beam scans from a laser
// mounted like minibot3d's (0.02 m ahead, upside down -> yaw pi).
class RobotSim {
 public:
  RobotSim(const OccupancyGrid& grid, const Pose2& truth, uint64_t seed)
      : grid_(grid), map_(grid, 2.0), truth_(truth), rng_(seed) {}

  // Moves by the robot-frame increment u; fails the test if the robot would
  // leave free space (keeps the scripted paths honest).
  void Move(const Pose2& u) {
    truth_ = Compose(truth_, u);
    int i, j;
    ASSERT_TRUE(map_.WorldToCell(truth_.x, truth_.y, &i, &j));
    ASSERT_TRUE(map_.IsFree(i, j)) << truth_.x << ", " << truth_.y;
    ASSERT_GT(map_.Distance(i, j), 0.15) << "path too close to an obstacle";
    std::normal_distribution<double> n(0.0, 1.0);
    const Pose2 noisy{u.x * (1 + 0.02 * n(rng_)), u.y + 0.005 * n(rng_),
                       u.yaw + 0.5 * kDeg * n(rng_)};
    odom_ = Compose(odom_, noisy);
  }
  // Teleports the robot without odometry (kidnapping).
  void Kidnap(const Pose2& p) { truth_ = p; }

  LaserScan Scan() {
    return testing::SimulateScan(grid_, truth_, kLaserPose, 360, 12.0, 0.01,
                                 &rng_);
  }
  const Pose2& truth() const { return truth_; }
  const Pose2& odom() const { return odom_; }

  static constexpr Pose2 kLaserPose{0.02, 0.0, kPi};

 private:
  OccupancyGrid grid_;
  MapModel map_;
  Pose2 truth_;
  Pose2 odom_{10.0, -5.0, 1.0};  // odometry frame unrelated to the map
  std::mt19937_64 rng_;
};

// A loop through the room (robot-frame increments), ~0.1 m / 5 deg steps.
std::vector<Pose2> LoopPath() {
  std::vector<Pose2> path;
  auto straight = [&](int n) {
    for (int k = 0; k < n; ++k) path.push_back({0.1, 0.0, 0.0});
  };
  auto turn = [&](int n, double deg) {
    for (int k = 0; k < n; ++k) path.push_back({0.05, 0.0, deg * kDeg});
  };
  straight(12);  // east-north-east
  turn(15, 6);   // left 90 deg
  straight(12);  // north-north-west
  turn(15, 6);   // left
  straight(10);  // west-south-west
  turn(15, 6);   // left
  straight(8);   // south-south-east
  return path;
}

double YawError(const Pose2& a, const Pose2& b) {
  return std::fabs(AngleDiff(a.yaw, b.yaw));
}
double PosError(const Pose2& a, const Pose2& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

// Runs the path, feeding every step to the filter.
void Drive(const std::vector<Pose2>& path, RobotSim* sim, AmclFilter* filter) {
  for (const Pose2& u : path) {
    sim->Move(u);
    if (::testing::Test::HasFatalFailure()) return;
    const UpdateResult r = filter->Update(sim->odom(), sim->Scan());
    ASSERT_NE(r.status, UpdateStatus::kRejectedBadScan) << r.message;
    ASSERT_NE(r.status, UpdateStatus::kRejectedBadOdometry) << r.message;
  }
}

// Updates the filter `updates` times where the robot stands (amcl's request_nomotion_update).
void Settle(int updates, RobotSim* sim, AmclFilter* filter) {
  for (int k = 0; k < updates; ++k) {
    filter->RequestNoMotionUpdate();
    filter->Update(sim->odom(), sim->Scan());
  }
}

const Pose2 kStartTruth{2.0, 1.5, 0.3};

// The pose a user gives amcl to start from.
void SetInitialPose(const Pose2& pose, AmclOptions* o) {
  o->initial_pose_x = pose.x;
  o->initial_pose_y = pose.y;
  o->initial_pose_a = pose.yaw;
}

TEST(AmclFilterTest, ConvergesFromWrongishGaussianGuess) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;  // ROS defaults, 30 beams, likelihood_field, diff
  o.initial_pose_x = kStartTruth.x + 0.3;
  o.initial_pose_y = kStartTruth.y - 0.3;
  o.initial_pose_a = kStartTruth.yaw + 10 * kDeg;
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 21);
  // First scan: integrated without motion.
  EXPECT_EQ(filter.Update(sim.odom(), sim.Scan()).status,
            UpdateStatus::kUpdated);
  Drive(LoopPath(), &sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  Settle(3, &sim, &filter);  // on the last pose
  const PoseEstimate& e = filter.estimate();
  EXPECT_LT(PosError(e.mean, sim.truth()), 0.1)
      << "estimate " << e.mean.x << ", " << e.mean.y << " truth "
      << sim.truth().x << ", " << sim.truth().y;
  EXPECT_LT(YawError(e.mean, sim.truth()), 3 * kDeg);
  EXPECT_TRUE(filter.converged());
  EXPECT_GT(e.weight, 0.9);
  // Covariance: small, symmetric, positive definite.
  EXPECT_LT(e.covariance(0, 0), 0.05);
  EXPECT_LT(e.covariance(2, 2), std::pow(5 * kDeg, 2));
  EXPECT_GT(e.covariance.determinant(), 0.0);
  EXPECT_LT(filter.particles().size(), 5000u) << "KLD shrank the set";
}

TEST(AmclFilterTest, GlobalLocalizationConvergesInDistinctiveRoom) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;
  o.max_particles = 20000;  // ~1 per 0.5 m x 0.5 m x 10 deg bin of the room
  AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
  EXPECT_EQ(filter.particles().size(), 20000u);
  EXPECT_GT(filter.estimate().covariance(0, 0), 4.0) << "uniform: no mode";
  RobotSim sim(grid, kStartTruth, 22);
  filter.Update(sim.odom(), sim.Scan());
  Drive(LoopPath(), &sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  Settle(3, &sim, &filter);
  const PoseEstimate& e = filter.estimate();
  EXPECT_LT(PosError(e.mean, sim.truth()), 0.1)
      << "estimate " << e.mean.x << ", " << e.mean.y << ", " << e.mean.yaw
      << " truth " << sim.truth().x << ", " << sim.truth().y << ", "
      << sim.truth().yaw;
  EXPECT_LT(YawError(e.mean, sim.truth()), 3 * kDeg);
}

// Back and forth: 12 x 0.1 m forward, then a tight U-turn to the left (180
// deg over 0.3 m), so each leg runs ~0.2 m beside the last: new views for the
// filter's evidence, which a shuttle along one line would not give.
std::vector<Pose2> ShuttlePath(int steps) {
  std::vector<Pose2> path;
  for (int k = 0; k < steps; ++k) {
    path.push_back(k % 18 < 12 ? Pose2{0.1, 0.0, 0.0}
                               : Pose2{0.05, 0.0, 30 * kDeg});
  }
  return path;
}

TEST(AmclFilterTest, AugmentedMclRecoversFromKidnapping) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;
  o.max_particles = 10000;
  o.recovery_alpha_slow = 0.001;
  o.recovery_alpha_fast = 0.1;
  o.global_search = false;  // augmented MCL alone (the search: below)
  SetInitialPose(kStartTruth, &o);
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 23);
  filter.Update(sim.odom(), sim.Scan());
  Drive(ShuttlePath(48), &sim, &filter);  // ends with a forward leg
  ASSERT_FALSE(HasFatalFailure());
  filter.RequestNoMotionUpdate();
  filter.Update(sim.odom(), sim.Scan());
  ASSERT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1);
  const Pose2 lost_estimate = filter.estimate().mean;

  // Carry the robot 4.5 m away and turn it round: odometry sees nothing.
  sim.Kidnap({6.0, 4.0, 3.0});
  double max_injection = 0.0;
  bool injected_far = false;
  for (const Pose2& u : ShuttlePath(102)) {  // ends with a forward leg
    sim.Move(u);
    ASSERT_FALSE(HasFatalFailure());
    filter.Update(sim.odom(), sim.Scan());
    max_injection = std::max(max_injection, filter.InjectionProbability());
    for (const Particle& p : filter.particles()) {
      if (PosError(p.pose, lost_estimate) > 3.0 &&
          PosError(p.pose, sim.truth()) > 1.0) {
        injected_far = true;  // neither old belief nor truth: a random pose
      }
    }
  }
  EXPECT_GT(max_injection, 0.01) << "w_fast dropped below w_slow";
  EXPECT_TRUE(injected_far) << "random poses were injected";
  Settle(3, &sim, &filter);
  EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1)
      << "estimate " << filter.estimate().mean.x << ", "
      << filter.estimate().mean.y << " truth " << sim.truth().x << ", "
      << sim.truth().y;
  EXPECT_LT(YawError(filter.estimate().mean, sim.truth()), 3 * kDeg);
}

// --- Confidence: the claim covers every mode and is earned over motion ---

double ClaimXY(const AmclFilter& f) {
  return f.estimate().claim_covariance(0, 0) +
         f.estimate().claim_covariance(1, 1);
}
constexpr double kDemoThreshold = 0.05;  // make demo: cov_xx + cov_yy (m^2)

// config/amcl.yaml, the shipped configuration.
AmclOptions ShippedOptions() {
  AmclOptions o;
  o.min_particles = 500;
  o.max_particles = 5000;
  o.update_min_d = 0.1;
  o.update_min_a = 0.2;
  o.resample_interval = 1;
  o.recovery_alpha_slow = 0.001;
  o.recovery_alpha_fast = 0.1;
  o.odom_model_type = "diff-corrected";
  o.odom_alpha1 = 0.05;
  o.odom_alpha2 = o.odom_alpha3 = o.odom_alpha4 = 0.01;
  o.laser_max_range = 12.0;
  o.laser_max_beams = 60;
  o.laser_sigma_hit = 0.1;
  o.laser_model_type = "likelihood_field_prob";
  o.laser_independent_beams = 0.5;
  o.confidence_challenges = 1;
  o.confidence_challenge_min_relative_score = 1.0;
  return o;
}

// Two identical 5 m x 4 m rooms side by side (10 m apart), each with the
// same asymmetric furniture: nothing in a scan tells them apart.  With
// `third_room`, a room of its own 2 m east of the second (x 17 to 22 m).
// The map reaches 2 m (laser_likelihood_max_dist) beyond the twins' outer
// walls, so an end point just past a wall sees the same field in both rooms
// (past a map edge it would be "off the map", the farthest distance, in one
// room only and the twins would not be identical).
constexpr double kTwinShift = 10.0;
OccupancyGrid MakeTwinRooms(bool third_room = false) {
  constexpr double kMargin = 2.0;
  OccupancyGrid g = testing::MakeFreeGrid(
      kMargin + (third_room ? 22.0 : 15.0 + kMargin), 4.0, 0.05, -kMargin);
  auto box = [&](double x0, double y0, double x1, double y1) {
    testing::FillBox(&g, x0 + kMargin, y0, x1 + kMargin, y1);
  };
  if (third_room) {
    box(17.0, 0.0, 22.0, 0.05);
    box(17.0, 3.95, 22.0, 4.0);
    box(17.0, 0.0, 17.05, 4.0);
    box(21.95, 0.0, 22.0, 4.0);
    box(19.0, 0.6, 19.3, 0.9);    // pillar
    box(20.6, 2.6, 21.95, 3.95);  // cabinet
  }
  for (int r = 0; r < 2; ++r) {
    const double x0 = r * kTwinShift;
    box(x0, 0.0, x0 + 5.0, 0.05);
    box(x0, 3.95, x0 + 5.0, 4.0);
    box(x0, 0.0, x0 + 0.05, 4.0);
    box(x0 + 4.95, 0.0, x0 + 5.0, 4.0);
    box(x0 + 1.0, 2.8, x0 + 1.6, 3.95);  // cupboard
    box(x0 + 3.5, 0.05, x0 + 3.7, 1.2);  // partition
  }
  return g;
}

// Back and forth inside a room, U-turns on the move (a turn on the spot
// shows the filter no new view): each lap 1 m ahead, then a half turn over
// 0.5 m.
std::vector<Pose2> UTurnLaps(int laps) {
  std::vector<Pose2> path;
  for (int lap = 0; lap < laps; ++lap) {
    path.insert(path.end(), 10, Pose2{0.1, 0.0, 0.0});
    path.insert(path.end(), 10, Pose2{0.05, 0.0, 18 * kDeg});
  }
  return path;
}

TEST(AmclConfidenceTest, SplitParticleSetClaimsLargeCovarianceAndTwoModes) {
  const OccupancyGrid grid = MakeTwinRooms();
  AmclOptions o = ShippedOptions();
  AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
  ASSERT_NE(filter.global_search(), nullptr) << filter.global_search_fallback();
  const Pose2 truth{2.2, 1.6, 0.4};
  RobotSim sim(grid, truth, 31);
  filter.Update(sim.odom(), sim.Scan());  // the search runs on this scan
  ASSERT_EQ(filter.last_search().count, 1);
  const auto& cands = filter.last_search().candidates;
  ASSERT_GE(cands.size(), 2u);
  // Both rooms are found, the true pose exactly (within the lattice).
  bool in_a = false, in_b = false;
  for (const SearchCandidate& c : cands) {
    in_a = in_a || (PosError(c.pose, truth) < 0.1 && YawError(c.pose, truth) < 3 * kDeg);
    const Pose2 twin{truth.x + kTwinShift, truth.y, truth.yaw};
    in_b = in_b || (PosError(c.pose, twin) < 0.1 && YawError(c.pose, twin) < 3 * kDeg);
  }
  EXPECT_TRUE(in_a && in_b);
  // Driving inside the room cannot split the twins: both modes stay, and so
  // does a covariance that spans them, however well each explains the scan.
  std::vector<Pose2> path;
  for (int k = 0; k < 10; ++k) path.push_back({0.1, 0.0, 0.0});
  for (int k = 0; k < 10; ++k) path.push_back({0.0, 0.0, 15 * kDeg});
  for (const Pose2& u : path) {
    sim.Move(u);
    ASSERT_FALSE(HasFatalFailure());
    filter.Update(sim.odom(), sim.Scan());
    EXPECT_GT(ClaimXY(filter), kDemoThreshold);
    EXPECT_FALSE(filter.confidence().confident);
  }
  EXPECT_GE(filter.confidence().modes, 2);
  EXPECT_GT(filter.confidence().explained_fraction, 0.9);
  // The second moment of two equal modes 10 m apart is ~ (10/2)^2 .. 10^2.
  EXPECT_GT(filter.estimate().claim_covariance(0, 0), 10.0);
  // ... while each cluster on its own is tight (what amcl would publish).
  EXPECT_LT(filter.estimate().covariance(0, 0), 0.05);
}

// Resampling keeps a hypothesis the evidence has not refuted, with its
// probability: in two identical rooms the scans never tell the seeded places
// apart, so a light hypothesis must stay exactly as probable as it was seeded
// (plain resampling lets it die by chance, and it never comes back).  A place
// in the third room, whose scans do not fit, is refuted and loses its floor.
TEST(AmclConfidenceTest, HypothesisKeepsItsProbabilityUntilTheEvidenceRefutesIt) {
  const OccupancyGrid grid = MakeTwinRooms(/*third_room=*/true);
  const Pose2 truth{2.2, 1.6, 0.4};
  const Pose2 twin{truth.x + kTwinShift, truth.y, truth.yaw};
  const Pose2 elsewhere{18.2, 2.0, 0.4};  // the third room
  for (int floor_count : {0, 100}) {
    AmclOptions o = ShippedOptions();
    o.hypothesis_min_particles = floor_count;
    o.recovery_alpha_slow = o.recovery_alpha_fast = 0.0;  // no injection
    AmclFilter filter(o, grid);
    // Seeded as the search would: weights in proportion to the scores.
    filter.SeedFromCandidates(
        {{truth, 1.0}, {twin, 0.002}, {elsewhere, 1.0}});
    ASSERT_EQ(filter.hypotheses().size(), 3u);
    RobotSim sim(grid, truth, 41);
    filter.Update(sim.odom(), sim.Scan());
    if (floor_count > 0) {
      // The first update cannot tell the twins apart either (over 30 seeds
      // the ratio stayed within 4 % of the prior).  Plain resampling keeps
      // the twin's ~3 expected particles or none, by chance.
      const double seeded = filter.hypotheses()[1].probability /
                            filter.hypotheses()[0].probability;
      EXPECT_NEAR(seeded, 0.002, 0.0002) << "the twin's prior";
    }
    std::vector<Pose2> path;
    for (int k = 0; k < 10; ++k) path.push_back({0.1, 0.0, 0.0});
    for (int k = 0; k < 10; ++k) path.push_back({0.0, 0.0, 15 * kDeg});
    for (int k = 0; k < 10; ++k) path.push_back({0.05, 0.0, -15 * kDeg});
    Drive(path, &sim, &filter);
    ASSERT_FALSE(HasFatalFailure());
    const std::vector<Hypothesis>& h = filter.hypotheses();
    ASSERT_EQ(h.size(), 3u);
    EXPECT_TRUE(h[2].refuted) << "the third room does not fit";
    EXPECT_EQ(h[2].particles, 0) << "a refuted place keeps no floor";
    EXPECT_FALSE(h[0].refuted);
    EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.3);
    if (floor_count == 0) {
      // Plain resampling: the twin's few particles died by chance.
      EXPECT_EQ(h[1].particles, 0);
      EXPECT_EQ(h[1].probability, 0.0);
    } else {
      EXPECT_FALSE(h[1].refuted);
      EXPECT_GE(h[1].particles, floor_count);
      // Same scans at both places: the ratio of probabilities is the prior's
      // (up to the particles' different fit, a factor of a few at most).
      const double ratio = h[1].probability / h[0].probability;
      EXPECT_GT(ratio, 0.002 / 5) << ratio;
      EXPECT_LT(ratio, 0.002 * 5) << ratio;
    }
  }
}

TEST(AmclConfidenceTest, ScanNotExplainedAtTheEstimateGivesLowFractionAndLargeCovariance) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o = ShippedOptions();
  // A confident-looking (tight) initial pose 1.5 m and 40 deg from the truth.
  o.initial_pose_x = kStartTruth.x + 1.5;
  o.initial_pose_y = kStartTruth.y;
  o.initial_pose_a = kStartTruth.yaw + 40 * kDeg;
  o.initial_cov_xx = o.initial_cov_yy = 0.01 * 0.01;
  o.initial_cov_aa = 0.001;
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 32);
  filter.Update(sim.odom(), sim.Scan());
  EXPECT_LT(filter.confidence().explained_fraction, 0.5);
  EXPECT_GT(filter.confidence().beams_used, 20);
  EXPECT_FALSE(filter.confidence().confident);
  EXPECT_GE(filter.estimate().claim_covariance(0, 0), kUnconfidentVarianceXY);
  EXPECT_GE(filter.estimate().claim_covariance(2, 2), kUnconfidentVarianceYaw);
  // The particles' own spread is still tiny: the claim, not the cloud, says lost.
  EXPECT_LT(filter.estimate().covariance(0, 0), 0.01);

  // At the truth the same scan is explained and the claim is small.
  filter.SetPose(kStartTruth, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  filter.Update(sim.odom(), sim.Scan());
  EXPECT_GT(filter.confidence().explained_fraction, 0.95);
  EXPECT_EQ(filter.confidence().modes, 1);
  EXPECT_TRUE(filter.confidence().confident);
  EXPECT_LT(ClaimXY(filter), kDemoThreshold);
}

// Global localization: never a claim while wrong, then the right one.
// `searches` (if given) receives every map-wide search run meanwhile.
void ExpectNoFalseClaimsThenRight(AmclFilter* filter, RobotSim* sim,
                                  const std::vector<Pose2>& path,
                                  double* travel_to_claim,
                                  std::vector<SearchReport>* searches = nullptr) {
  double travel = 0.0;
  *travel_to_claim = -1.0;
  for (const Pose2& u : path) {
    sim->Move(u);
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    travel += std::hypot(u.x, u.y);
    const int count = filter->last_search().count;
    // A claim is published with an update (amcl_pose): judge those.
    const UpdateStatus status = filter->Update(sim->odom(), sim->Scan()).status;
    if (searches != nullptr && filter->last_search().count != count) {
      searches->push_back(filter->last_search());
    }
    if (status != UpdateStatus::kUpdated) continue;
    if (ClaimXY(*filter) < kDemoThreshold) {
      // The definition of a false claim: > 1 m or > 30 deg off.
      // A right one is far closer.
      ASSERT_LT(PosError(filter->estimate().mean, sim->truth()), 0.3)
          << "false claim after " << travel << " m";
      ASSERT_LT(YawError(filter->estimate().mean, sim->truth()), 10 * kDeg)
          << "false claim after " << travel << " m";
      if (*travel_to_claim < 0.0) *travel_to_claim = travel;
    }
  }
}

// The search seeds only one of two identical rooms (max_candidates = 1): the
// filter's hypotheses all agree, yet the map holds a look-alike.  Before the
// first claim the challenge search finds the twin and adds it, so the filter
// never claims while the robot stays in a room that cannot be told apart
// (without the challenge it claims whichever room it was given).
TEST(AmclConfidenceTest, ChallengeAddsTheLookAlikeTheSearchMissedSoNoClaim) {
  const OccupancyGrid grid = MakeTwinRooms();
  for (int challenges : {0, 1}) {
    AmclOptions o = ShippedOptions();
    o.global_search_max_candidates = 1;
    o.confidence_challenges = challenges;
    AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
    ASSERT_NE(filter.global_search(), nullptr);
    RobotSim sim(grid, {2.2, 1.6, 0.4}, 35);
    filter.Update(sim.odom(), sim.Scan());
    ASSERT_EQ(filter.last_search().candidates.size(), 1u);
    bool claimed = false, challenged = false;
    // ~2.5 m of new views.
    for (const Pose2& u : UTurnLaps(3)) {
      sim.Move(u);
      ASSERT_FALSE(HasFatalFailure());
      filter.Update(sim.odom(), sim.Scan());
      claimed = claimed || filter.confidence().confident;
      challenged = challenged || filter.last_search().challenge;
    }
    if (challenges == 0) {
      EXPECT_TRUE(claimed) << "the unchallenged filter claims its one room";
      EXPECT_FALSE(challenged);
    } else {
      EXPECT_TRUE(challenged);
      EXPECT_FALSE(claimed) << "claimed one of two identical rooms";
      EXPECT_GE(filter.confidence().modes, 2);
      EXPECT_GT(ClaimXY(filter), kDemoThreshold);
    }
  }
}

// The filter is given only a wrong place that explains nearly all of every
// scan (the room next door, the same but for a pillar the robot sees): left
// alone it claims it.  The look-alike check before the claim searches the
// map, finds a place that explains the view better than the estimate's own,
// and adds it, even when it adds only such places (relative score 1.0, the
// shipped setting): the filter then claims the right room.
TEST(AmclConfidenceTest, ChallengeFindsAPlaceThatExplainsTheViewBetterThanTheEstimate) {
  OccupancyGrid grid = MakeTwinRooms();
  // A pillar in the second room only (grid frame: 2 m of margin).
  testing::FillBox(&grid, 2.0 + kTwinShift + 4.0, 3.0, 2.0 + kTwinShift + 4.5,
                   3.5);
  const Pose2 truth{2.2 + kTwinShift, 1.6, 0.4};
  const Pose2 wrong{2.2, 1.6, 0.4};
  for (int challenges : {0, 1}) {
    SCOPED_TRACE(challenges ? "checked" : "unchecked");
    AmclOptions o = ShippedOptions();
    o.recovery_alpha_slow = o.recovery_alpha_fast = 0.0;  // no random draws
    o.confidence_challenges = challenges;
    o.confidence_challenge_min_relative_score = 1.0;
    AmclFilter filter(o, grid);
    filter.SeedFromCandidates({{wrong, 1.0}});
    RobotSim sim(grid, truth, 43);
    filter.Update(sim.odom(), sim.Scan());
    EXPECT_GT(filter.confidence().explained_fraction,
              o.confidence_min_explained)
        << "the wrong room must pass the explained-beams test";
    bool false_claim = false, right_claim = false, challenged = false;
    for (const Pose2& u : UTurnLaps(6)) {
      sim.Move(u);
      ASSERT_FALSE(HasFatalFailure());
      filter.Update(sim.odom(), sim.Scan());
      challenged = challenged || filter.last_search().challenge;
      if (ClaimXY(filter) < kDemoThreshold) {
        const double err = PosError(filter.estimate().mean, sim.truth());
        false_claim = false_claim || err > 1.0;
        right_claim = right_claim || err < 0.3;
      }
    }
    if (challenges == 0) {
      EXPECT_TRUE(false_claim) << "the unchecked filter claims the wrong room";
    } else {
      EXPECT_TRUE(challenged);
      EXPECT_FALSE(false_claim);
      EXPECT_TRUE(right_claim);
    }
  }
}

// A turn on the spot shows a laser that sees all round the same scan,
// rotated: it fits a wrong place as well as the right one, so it earns no
// evidence, and nor does shuttling back and forth over the same places (the
// study's false claims were made both ways); travel to new places does.  A
// laser with a blind sector sees new walls as it turns, and its turns count.
TEST(AmclConfidenceTest, OnlyNewViewsEarnEvidenceAndTurnsAreNewOnlyWithABlindSector) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  for (bool all_round : {true, false}) {
    SCOPED_TRACE(all_round ? "360 deg laser" : "180 deg laser");
    AmclFilter filter(ShippedOptions(), grid, AmclFilter::Initialization::kGlobal);
    RobotSim sim(grid, kStartTruth, 37);
    auto scan = [&] {
      LaserScan s = sim.Scan();
      if (all_round) return s;
      LaserScan front = s;  // the beams within 90 deg of the laser's axis
      front.ranges.clear();
      front.angles.clear();
      for (size_t k = 0; k < s.angles.size(); ++k) {
        if (std::fabs(NormalizeAngle(s.angles[k])) <= kPi / 2) {
          front.ranges.push_back(s.ranges[k]);
          front.angles.push_back(s.angles[k]);
        }
      }
      return front;
    };
    filter.Update(sim.odom(), scan());
    ASSERT_EQ(filter.last_search().count, 1);
    bool claimed = false;
    for (int k = 0; k < 40; ++k) {  // two turns on the spot
      sim.Move({0.0, 0.0, 18 * kDeg});
      ASSERT_FALSE(HasFatalFailure());
      filter.Update(sim.odom(), scan());
      claimed = claimed || filter.confidence().confident;
    }
    if (all_round) {
      // Back and forth along one line re-reads the same views too.
      for (int k = 0; k < 54; ++k) {
        sim.Move(k % 18 < 6 ? Pose2{0.1, 0.0, 0.0} : k % 18 < 12
                                  ? Pose2{0.0, 0.0, 30 * kDeg}
                                  : Pose2{0.0, 0.0, 0.0});
        ASSERT_FALSE(HasFatalFailure());
        if (k % 18 >= 12) continue;
        filter.Update(sim.odom(), scan());
        claimed = claimed || filter.confidence().confident;
      }
      EXPECT_FALSE(claimed) << "claimed after turning on the spot or "
                               "shuttling along one line";
      // (Six places on the line, and the odometry's sideways noise, 5 mm a
      // step, may add a view or two.)
      EXPECT_LE(filter.confidence().evidence_updates, 9);
      EXPECT_GT(ClaimXY(filter), kDemoThreshold);
      // ... until it travels: 15 new views of 0.1 m.
      for (int k = 0; k < 25 && !filter.confidence().confident; ++k) {
        sim.Move({0.1, 0.0, k % 2 ? 4 * kDeg : -4 * kDeg});
        ASSERT_FALSE(HasFatalFailure());
        filter.Update(sim.odom(), scan());
      }
    }
    EXPECT_TRUE(filter.confidence().confident);
    EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1);
  }
}

TEST(AmclConfidenceTest, GlobalSearchSeedsTheFilterWhichClaimsOnlyAfterMotion) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o = ShippedOptions();
  AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
  ASSERT_NE(filter.global_search(), nullptr);
  RobotSim sim(grid, kStartTruth, 33);
  filter.Update(sim.odom(), sim.Scan());
  ASSERT_EQ(filter.last_search().count, 1);
  ASSERT_FALSE(filter.last_search().candidates.empty());
  EXPECT_LT(PosError(filter.last_search().candidates[0].pose, sim.truth()), 0.1);
  // One view is not evidence: no claim before the robot has moved.
  Settle(5, &sim, &filter);
  EXPECT_FALSE(filter.confidence().confident);
  EXPECT_GT(ClaimXY(filter), kDemoThreshold);
  double travel = -1.0;
  ExpectNoFalseClaimsThenRight(&filter, &sim, LoopPath(), &travel);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_GT(travel, 0.0) << "never claimed";
  EXPECT_LT(travel, 4.0);
  EXPECT_TRUE(filter.confidence().confident);
}

TEST(AmclConfidenceTest, KidnappedRobotIsFoundAgainByTheSearch) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o = ShippedOptions();
  SetInitialPose(kStartTruth, &o);
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 34);
  filter.Update(sim.odom(), sim.Scan());
  Drive(ShuttlePath(24), &sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  ASSERT_TRUE(filter.confidence().confident)
      << "explained " << filter.confidence().explained_fraction << " modes "
      << filter.confidence().modes << " evidence "
      << filter.confidence().evidence_updates << " error "
      << PosError(filter.estimate().mean, sim.truth());
  EXPECT_EQ(filter.last_search().count, 0) << "tracking needs no search";
  sim.Kidnap({6.0, 4.0, 3.0});
  double travel = -1.0;
  std::vector<SearchReport> searches;
  ExpectNoFalseClaimsThenRight(&filter, &sim, ShuttlePath(60), &travel,
                               &searches);
  ASSERT_FALSE(HasFatalFailure());
  ASSERT_GE(searches.size(), 1u);
  EXPECT_TRUE(searches.front().relocalization) << "lost: searched again";
  EXPECT_GT(travel, 0.0) << "never claimed again";
  EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1);
}

// Shipped options with the lost test off (only augmented MCL's random draws
// can bring a kidnapped filter back) and a tight start at `start`: w_slow
// begins at the tracking level, so a kidnapping drops w_fast below it and
// the filter draws random poses.
AmclOptions DrawsOnlyOptions(const Pose2& start) {
  AmclOptions o = ShippedOptions();
  o.confidence_lost_updates = 0;
  o.initial_pose_x = start.x;
  o.initial_pose_y = start.y;
  o.initial_pose_a = start.yaw;
  o.initial_cov_xx = o.initial_cov_yy = 0.02 * 0.02;
  o.initial_cov_aa = 0.02 * 0.02;
  return o;
}

// Drives 1 m straight ahead, tracking.
void DriveOneMetre(RobotSim* sim, AmclFilter* filter) {
  for (int k = 0; k < 10; ++k) {
    sim->Move({0.1, 0.0, 0.0});
    if (::testing::Test::HasFatalFailure()) return;
    filter->Update(sim->odom(), sim->Scan());
  }
}

// Kidnapped from a room of its own into one of two identical rooms.
// Augmented MCL's random draws soon land in a twin, and that mode explains
// every scan; claimed, it would be the wrong twin half the time.  It is not
// claimed: the map-wide search runs on it, finds both twins, and the filter
// keeps both while the robot stays where they cannot be told apart.  (The
// lost test is off, so only the draws can bring the filter back: in a
// building they often do before that test fires.)
TEST(AmclConfidenceTest, PlaceFoundByRandomDrawsIsSearchedNotClaimed) {
  const OccupancyGrid grid = MakeTwinRooms(true);
  const Pose2 start{18.2, 2.0, 0.2};
  AmclFilter filter(DrawsOnlyOptions(start), grid);
  ASSERT_NE(filter.global_search(), nullptr) << filter.global_search_fallback();
  RobotSim sim(grid, start, 36);
  filter.Update(sim.odom(), sim.Scan());
  DriveOneMetre(&sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  ASSERT_TRUE(filter.confidence().confident)
      << "explained " << filter.confidence().explained_fraction << " modes "
      << filter.confidence().modes << " evidence "
      << filter.confidence().evidence_updates << " error "
      << PosError(filter.estimate().mean, sim.truth());
  ASSERT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1);
  sim.Kidnap({2.2, 1.6, 0.4});  // the first twin
  bool claimed = false, searched_on_injected = false;
  for (const Pose2& u : ShuttlePath(90)) {
    sim.Move(u);
    ASSERT_FALSE(HasFatalFailure());
    // A claim is published with an update (amcl_pose): judge those.
    if (filter.Update(sim.odom(), sim.Scan()).status != UpdateStatus::kUpdated) {
      continue;
    }
    if (filter.confidence().confident && !claimed) {
      claimed = true;
      ADD_FAILURE() << "claimed (" << filter.estimate().mean.x << ", "
                    << filter.estimate().mean.y << ") in a room with a twin";
    }
    searched_on_injected =
        searched_on_injected || filter.last_search().found_by_injection;
  }
  EXPECT_TRUE(searched_on_injected)
      << "searches " << filter.last_search().count;
  EXPECT_GE(filter.confidence().modes, 2);
  EXPECT_GT(ClaimXY(filter), kDemoThreshold);
}

// The same in a room without a twin: the draws find the kidnapped robot,
// and the claim comes only after the search has weighed that place against
// the rest of the map.  (Without the check this run is not found again
// within its 9 m: the draws' modes never hold the weight long enough.)
TEST(AmclConfidenceTest, KidnappedFilterClaimsOnlyAfterSearchingWhatItsDrawsFound) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclFilter filter(DrawsOnlyOptions(kStartTruth), grid);
  RobotSim sim(grid, kStartTruth, 37);
  filter.Update(sim.odom(), sim.Scan());
  DriveOneMetre(&sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  ASSERT_TRUE(filter.confidence().confident);
  ASSERT_EQ(filter.last_search().count, 0);
  sim.Kidnap({6.0, 4.0, 3.0});
  bool searched = false, claimed = false;
  for (const Pose2& u : ShuttlePath(90)) {
    sim.Move(u);
    ASSERT_FALSE(HasFatalFailure());
    if (filter.Update(sim.odom(), sim.Scan()).status != UpdateStatus::kUpdated) {
      continue;
    }
    searched = searched || filter.last_search().found_by_injection;
    if (filter.confidence().confident && !claimed) {
      claimed = true;
      EXPECT_TRUE(searched) << "claimed a place only random draws had found";
      EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.3);
    }
  }
  EXPECT_TRUE(claimed) << "never found again";
}

TEST(AmclConfidenceTest, MapOverTheSearchBudgetSaysSoAndSpreadsUniformly) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o = ShippedOptions();
  o.global_search_budget = 0.05;  // 32,000 cells need ~0.11 s
  AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
  EXPECT_EQ(filter.global_search(), nullptr);
  const std::string why = filter.global_search_fallback();
  EXPECT_NE(why.find("global_search_budget"), std::string::npos) << why;
  EXPECT_NE(why.find("200 x 160 cells"), std::string::npos) << why;
  RobotSim sim(grid, kStartTruth, 35);
  filter.Update(sim.odom(), sim.Scan());
  EXPECT_EQ(filter.last_search().count, 0);
  // (A uniform set is one big cluster of touching bins, or many small
  // ones: either way its claim is large.)
  EXPECT_GT(ClaimXY(filter), kDemoThreshold);
}

// A corridor 50 m long and 2.4 m wide, with nothing on its walls, opening at
// its east end into a 10 m x 8 m room with furniture; its west end is closed.
// In the middle stretch a 12 m laser sees two parallel walls and nothing else.
OccupancyGrid MakeCorridorToRoom() {
  OccupancyGrid g = testing::MakeFreeGrid(60.0, 8.0, 0.05);
  testing::FillBox(&g, 0.0, 2.75, 50.0, 2.8);   // corridor, south wall
  testing::FillBox(&g, 0.0, 5.2, 50.0, 5.25);   // ... north wall
  testing::FillBox(&g, 0.0, 2.75, 0.05, 5.25);  // ... west end
  testing::FillBox(&g, 50.0, 0.0, 50.05, 2.8);  // room, west wall
  testing::FillBox(&g, 50.0, 5.2, 50.05, 8.0);
  testing::FillBox(&g, 50.0, 0.0, 60.0, 0.05);
  testing::FillBox(&g, 50.0, 7.95, 60.0, 8.0);
  testing::FillBox(&g, 59.95, 0.0, 60.0, 8.0);
  testing::FillBox(&g, 53.0, 1.0, 54.5, 1.6);   // table
  testing::FillBox(&g, 56.0, 5.5, 56.4, 7.95);  // partition
  testing::FillBox(&g, 58.0, 2.0, 58.3, 2.3);   // pillar
  // Outside the corridor and the room: unknown, as a SLAM map leaves it.
  for (int j = 0; j < g.height; ++j) {
    for (int i = 0; i < g.width; ++i) {
      const double x = (i + 0.5) * g.resolution, y = (j + 0.5) * g.resolution;
      if (x < 50.0 && (y < 2.75 || y > 5.25)) g.data[j * g.width + i] = -1;
    }
  }
  return g;
}

// What a scan says about the pose, by direction: in the corridor the walls
// fix y and the heading, nothing fixes x; in the room every direction is
// fixed.
TEST(AmclConfidenceTest, ScanInformationIsZeroAlongABareCorridor) {
  const OccupancyGrid grid = MakeCorridorToRoom();
  const MapModel map(grid, 2.0);
  const AmclOptions o = ShippedOptions();
  struct Case {
    Pose2 pose;
    double min_weakest, max_weakest;
  };
  for (const Case& c : {Case{{20.0, 4.0, 0.0}, 0.0, 0.01},
                        Case{{24.0, 3.6, 2.5}, 0.0, 0.01},
                        Case{{55.0, 4.0, 0.3}, 0.1, 1.0}}) {
    RobotSim sim(grid, c.pose, 38);
    PreparedScan scan;
    std::string error;
    ASSERT_TRUE(PrepareScan(sim.Scan(), o, &scan, &error)) << error;
    const Eigen::Matrix3d info = ScanInformation(map, scan, c.pose, 0.2);
    Eigen::Vector2d weakest_dir;
    const double weakest = WeakestTranslationInformation(info, &weakest_dir);
    EXPECT_GE(weakest, c.min_weakest) << "at x " << c.pose.x;
    EXPECT_LE(weakest, c.max_weakest) << "at x " << c.pose.x;
    if (c.pose.x < 50.0) {
      EXPECT_GT(std::fabs(weakest_dir.x()), 0.99) << "along the corridor";
      EXPECT_GT(info(1, 1), 0.5) << "the walls fix y";
      EXPECT_GT(info(2, 2), 1.0) << "... and the heading";
    }
  }
}

// Global localization in the middle of the bare corridor: the map-wide
// search finds the corridor everywhere, and the filter settles on one guess
// along it, which explains every scan from a new view and soon forms a
// single mode metres from the truth.  Only the information test keeps that
// from being a claim: with confidence_min_constraint 0 the filter calls
// itself confident more than 1 m off; with the default it does not claim
// (confident or by its covariance) until the room at the east end has fixed
// x, and then claims the right pose.
TEST(AmclConfidenceTest, NoClaimAlongABareCorridorUntilTheViewFixesThePose) {
  const OccupancyGrid grid = MakeCorridorToRoom();
  for (double min_constraint : {0.0, ShippedOptions().confidence_min_constraint}) {
    AmclOptions o = ShippedOptions();
    o.confidence_min_constraint = min_constraint;
    AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
    ASSERT_NE(filter.global_search(), nullptr) << filter.global_search_fallback();
    RobotSim sim(grid, {14.0, 4.0, 0.0}, 37);
    filter.Update(sim.odom(), sim.Scan());
    ASSERT_EQ(filter.last_search().count, 1);
    bool confident_while_wrong = false;
    double travel_to_claim = -1.0, travel = 0.0, error = -1.0;
    for (int k = 0; k < 400; ++k) {  // 40 m east, into the room
      sim.Move({0.1, 0.0, 0.0});
      ASSERT_FALSE(HasFatalFailure());
      travel += 0.1;
      if (filter.Update(sim.odom(), sim.Scan()).status != UpdateStatus::kUpdated) {
        continue;
      }
      error = PosError(filter.estimate().mean, sim.truth());
      if (filter.confidence().confident && error > 1.0) confident_while_wrong = true;
      if (min_constraint == 0.0) continue;
      // The room comes into the 12 m laser's view at x = 38.
      if (sim.truth().x < 38.0) {
        ASSERT_FALSE(filter.confidence().confident)
            << "x " << sim.truth().x << " error " << error << " constraint "
            << filter.confidence().constraint;
      }
      if (ClaimXY(filter) < kDemoThreshold) {
        ASSERT_LT(error, 0.3) << "false claim at x " << sim.truth().x;
        if (travel_to_claim < 0.0) travel_to_claim = travel;
      }
    }
    if (min_constraint == 0.0) {
      EXPECT_TRUE(confident_while_wrong)
          << "the scene no longer shows the failure the test is about";
    } else {
      EXPECT_FALSE(confident_while_wrong);
      EXPECT_GT(travel_to_claim, 0.0) << "never claimed in the room";
      EXPECT_TRUE(filter.confidence().confident);
      EXPECT_LT(error, 0.1) << "at the last update";
    }
  }
}

TEST(AmclFilterTest, UpdatesOnlyAfterEnoughMotionOrWhenForced) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;
  SetInitialPose(kStartTruth, &o);
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 24);
  EXPECT_EQ(filter.Update(sim.odom(), sim.Scan()).status,
            UpdateStatus::kUpdated);
  sim.Move({0.1, 0.0, 0.0});  // 0.1 m < update_min_d 0.2
  const std::vector<Particle> before = filter.particles();
  EXPECT_EQ(filter.Update(sim.odom(), sim.Scan()).status,
            UpdateStatus::kSkippedNoMotion);
  ASSERT_EQ(filter.particles().size(), before.size());
  EXPECT_EQ(filter.particles()[7].pose.x, before[7].pose.x);
  filter.RequestNoMotionUpdate();
  UpdateResult r = filter.Update(sim.odom(), sim.Scan());
  EXPECT_EQ(r.status, UpdateStatus::kUpdated);
  EXPECT_TRUE(r.resampled) << "second correction, resample_interval 2";
  EXPECT_EQ(filter.Update(sim.odom(), sim.Scan()).status,
            UpdateStatus::kSkippedNoMotion)
      << "the request is consumed";
  sim.Move({0.0, 0.0, 35 * kDeg});  // > update_min_a (30 deg)
  r = filter.Update(sim.odom(), sim.Scan());
  EXPECT_EQ(r.status, UpdateStatus::kUpdated);
  EXPECT_FALSE(r.resampled) << "third correction";
}

TEST(AmclFilterTest, RejectsBadInputAndKeepsLastGoodState) {
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;
  SetInitialPose(kStartTruth, &o);
  AmclFilter filter(o, grid);
  RobotSim sim(grid, kStartTruth, 25);
  filter.Update(sim.odom(), sim.Scan());
  const std::vector<Pose2> path = LoopPath();
  Drive(std::vector<Pose2>(path.begin(), path.begin() + 40), &sim, &filter);
  ASSERT_FALSE(HasFatalFailure());
  const PoseEstimate good = filter.estimate();
  const std::vector<Particle> particles = filter.particles();

  sim.Move({0.3, 0.0, 0.0});
  LaserScan bad = sim.Scan();
  bad.angles.resize(10);
  UpdateResult r = filter.Update(sim.odom(), bad);
  EXPECT_EQ(r.status, UpdateStatus::kRejectedBadScan);
  EXPECT_NE(r.message.find("angles"), std::string::npos) << r.message;
  r = filter.Update({kNaN, 0.0, 0.0}, sim.Scan());
  EXPECT_EQ(r.status, UpdateStatus::kRejectedBadOdometry);
  LaserScan no_range = sim.Scan();
  no_range.range_max = std::numeric_limits<double>::infinity();
  EXPECT_EQ(filter.Update(sim.odom(), no_range).status,
            UpdateStatus::kRejectedBadScan);
  ASSERT_EQ(filter.particles().size(), particles.size());
  for (size_t k = 0; k < particles.size(); k += 97) {
    EXPECT_EQ(filter.particles()[k].pose.x, particles[k].pose.x);
    EXPECT_EQ(filter.particles()[k].weight, particles[k].weight);
  }
  EXPECT_EQ(filter.estimate().mean.x, good.mean.x);

  // A scan with no usable return (all NaN / inf / below range_min): the
  // motion is applied, the weights are not touched.
  LaserScan blind = sim.Scan();
  for (size_t b = 0; b < blind.ranges.size(); ++b) {
    blind.ranges[b] = b % 3 == 0   ? std::numeric_limits<float>::quiet_NaN()
                      : b % 3 == 1 ? std::numeric_limits<float>::infinity()
                                   : 0.01f;
  }
  r = filter.Update(sim.odom(), blind);
  EXPECT_EQ(r.status, UpdateStatus::kMotionOnly) << r.message;
  EXPECT_TRUE(std::isfinite(filter.estimate().mean.x));

  // Partly corrupted scans are fine: the filter keeps tracking.
  for (int k = 0; k < 10; ++k) {
    sim.Move(path[40 + k]);
    ASSERT_FALSE(HasFatalFailure());
    LaserScan s = sim.Scan();
    for (size_t b = 0; b < s.ranges.size(); b += 4) {
      s.ranges[b] = (b % 8 == 0) ? std::numeric_limits<float>::quiet_NaN()
                                 : std::numeric_limits<float>::infinity();
    }
    filter.Update(sim.odom(), s);
  }
  Settle(3, &sim, &filter);
  EXPECT_LT(PosError(filter.estimate().mean, sim.truth()), 0.1);
  EXPECT_LT(YawError(filter.estimate().mean, sim.truth()), 3 * kDeg);
}

TEST(AmclFilterTest, InitialPoseOutsideMapIsAClearError) {
  // The room spans x -2..8, y -1.5..6.5.
  const OccupancyGrid grid = testing::MakeAsymmetricRoom();
  AmclOptions o;
  o.initial_pose_x = 20.0;
  try {
    AmclFilter filter(o, grid);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("outside the map"), std::string::npos) << msg;
    EXPECT_NE(msg.find("x=20"), std::string::npos) << msg;
  }
  // Global initialization does not need the pose.
  AmclFilter filter(o, grid, AmclFilter::Initialization::kGlobal);
  const std::vector<Particle> before = filter.particles();
  EXPECT_THROW(filter.SetPose({-5.0, 0.0, 0.0}, Eigen::Matrix3d::Identity()),
               std::invalid_argument);
  Eigen::Matrix3d not_psd = Eigen::Matrix3d::Identity();
  not_psd(0, 0) = -1.0;
  EXPECT_THROW(filter.SetPose({1.0, 1.0, 0.0}, not_psd), std::invalid_argument);
  Eigen::Matrix3d asym = Eigen::Matrix3d::Identity();
  asym(0, 1) = 0.5;
  EXPECT_THROW(filter.SetPose({1.0, 1.0, 0.0}, asym), std::invalid_argument);
  ASSERT_EQ(filter.particles().size(), before.size()) << "state unchanged";
  EXPECT_EQ(filter.particles()[3].pose.x, before[3].pose.x);

  // A valid SetPose draws max_particles from the Gaussian.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  cov.diagonal() << 0.04, 0.01, 0.0025;
  filter.SetPose({1.0, 2.0, 3.0}, cov);
  const PoseCluster stats = WholeSetStatistics(filter.particles());
  EXPECT_EQ(filter.particles().size(), 5000u);
  EXPECT_NEAR(stats.mean.x, 1.0, 0.01);
  EXPECT_NEAR(stats.mean.y, 2.0, 0.01);
  EXPECT_NEAR(stats.mean.yaw, 3.0, 0.01);
  EXPECT_NEAR(stats.covariance(0, 0), 0.04, 0.004);
  EXPECT_NEAR(stats.covariance(1, 1), 0.01, 0.001);
  EXPECT_NEAR(stats.covariance(2, 2), 0.0025, 0.00025);
}

TEST(AmclFilterTest, MapWithoutFreeCellsIsAClearError) {
  OccupancyGrid grid = testing::MakeFreeGrid(2.0, 2.0, 0.1);
  grid.data.assign(grid.data.size(), -1);  // all unknown
  try {
    AmclFilter filter(AmclOptions(), grid, AmclFilter::Initialization::kGlobal);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no free cells"), std::string::npos)
        << e.what();
  }
  // SetMap with such a map keeps the old map and particles.
  AmclOptions o;
  o.initial_pose_x = kStartTruth.x;
  o.initial_pose_y = kStartTruth.y;
  AmclFilter filter(o, testing::MakeAsymmetricRoom());
  const int width = filter.map().width();
  EXPECT_THROW(filter.SetMap(grid), std::invalid_argument);
  EXPECT_EQ(filter.map().width(), width);
  // A good new map re-initialises around the current estimate.
  filter.SetMap(testing::MakeWalledRoom(6.0, 5.0, 0.05));
  EXPECT_EQ(filter.map().width(), 120);
  EXPECT_LT(PosError(filter.estimate().mean, kStartTruth), 0.1);
}

TEST(AmclOptionsTest, ValidationNamesEveryOffendingParameter) {
  AmclOptions o;
  EXPECT_NO_THROW(ValidateAmclOptions(o));
  o.min_particles = 600;
  o.max_particles = 500;
  o.odom_model_type = "tank";
  o.laser_model_type = "sonar";
  o.laser_sigma_hit = -0.1;
  o.laser_z_hit = 0.0;
  o.laser_z_rand = 0.0;
  o.kld_err = 0.0;
  o.resample_interval = 0;
  o.recovery_alpha_slow = 0.2;
  o.recovery_alpha_fast = 0.1;
  o.beam_skip_threshold = 1.5;
  o.initial_cov_xx = kNaN;
  o.global_search_angular_step = 0.5;
  o.hypothesis_min_particles = -1;
  o.hypothesis_refuted_ratio = 1.0;
  o.laser_independent_beams = 4.0;  // with the 'sonar' model
  o.confidence_min_constraint = -0.5;
  try {
    ValidateAmclOptions(o);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const char* part :
         {"min_particles=600 > max_particles=500", "odom_model_type='tank'",
          "laser_model_type='sonar'", "laser_sigma_hit=-0.1",
          "laser_z_hit+laser_z_rand=0", "kld_err=0", "resample_interval=0",
          "recovery_alpha_slow=0.2 must be < recovery_alpha_fast=0.1",
          "beam_skip_threshold=1.5", "initial_cov_xx=nan",
          "laser_independent_beams=4 applies only to laser_model_type "
          "likelihood_field_prob (it is 'sonar')",
          "global_search_angular_step=0.5", "hypothesis_min_particles=-1",
          "hypothesis_refuted_ratio=1 must be in (0, 1)",
          "confidence_min_constraint=-0.5"}) {
      EXPECT_NE(msg.find(part), std::string::npos) << part << " in: " << msg;
    }
  }
  // The filter constructor validates too, before touching the map.
  EXPECT_THROW(AmclFilter(o, testing::MakeAsymmetricRoom()),
               std::invalid_argument);
  AmclOptions prob;
  prob.laser_model_type = "likelihood_field_prob";
  prob.laser_independent_beams = -1.0;
  EXPECT_THROW(ValidateAmclOptions(prob), std::invalid_argument);
  prob.laser_independent_beams = 0.5;
  EXPECT_NO_THROW(ValidateAmclOptions(prob));
}

TEST(AmclOptionsTest, SetOptionParsesRosParameterText) {
  AmclOptions o;
  SetAmclOption("min_particles", "500", &o);
  SetAmclOption("kld_err", " 0.05 ", &o);
  SetAmclOption("do_beamskip", "true", &o);
  SetAmclOption("laser_model_type", "likelihood_field_prob", &o);
  SetAmclOption("odom_alpha5", "1e-3", &o);
  EXPECT_EQ(o.min_particles, 500);
  EXPECT_DOUBLE_EQ(o.kld_err, 0.05);
  EXPECT_TRUE(o.do_beamskip);
  EXPECT_EQ(o.laser_model_type, "likelihood_field_prob");
  EXPECT_DOUBLE_EQ(o.odom_alpha5, 1e-3);
  EXPECT_THROW(SetAmclOption("min_particles", "5.5", &o),
               std::invalid_argument);
  EXPECT_THROW(SetAmclOption("kld_err", "abc", &o), std::invalid_argument);
  EXPECT_THROW(SetAmclOption("do_beamskip", "maybe", &o),
               std::invalid_argument);
  EXPECT_THROW(SetAmclOption("base_frame_id", "base_link", &o),
               std::invalid_argument);
  EXPECT_FALSE(IsAmclOptionName("base_frame_id"));
  EXPECT_TRUE(IsAmclOptionName("laser_likelihood_max_dist"));
  EXPECT_EQ(AmclOptionNames().size(), 55u);
  // Defaults are amcl's.
  const AmclOptions d;
  EXPECT_EQ(d.min_particles, 100);
  EXPECT_EQ(d.max_particles, 5000);
  EXPECT_DOUBLE_EQ(d.update_min_a, kPi / 6);
  EXPECT_DOUBLE_EQ(d.initial_cov_aa, std::pow(kPi / 12, 2));
  EXPECT_EQ(d.laser_max_beams, 30);
}

}  // namespace
}  // namespace amcl
}  // namespace minibot3d_navigation
