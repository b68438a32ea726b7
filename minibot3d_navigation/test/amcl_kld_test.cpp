// KLD-sampling (Fox 2003) tests: the sample-count bound against values
// computed by hand, the histogram binning, the adaptive set size produced by
// the filter's resampling, and the bin-connectivity clustering.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "amcl_test_utils.h"
#include "minibot3d_navigation/amcl/amcl_filter.h"
#include "minibot3d_navigation/amcl/kld_sampling.h"
#include "minibot3d_navigation/amcl/pose_clusters.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

constexpr double kDeg = kPi / 180.0;

// n = (k-1)/(2 eps) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3, rounded up,
// with eps = 0.01, z = 0.99 (amcl defaults), evaluated by hand:
//   k = 2:   50 * (1 - 0.222222 + 0.466690)^3   =   96.365 -> 97
//   k = 10:  450 * (1 - 0.024691 + 0.155564)^3  =  650.808 -> 651
//   k = 100: 4950 * (1 - 0.002245 + 0.046905)^3 = 5643.252 -> 5644
TEST(AmclKldTest, SampleCountFollowsFoxBound) {
  const int lo = 1, hi = 1000000;
  EXPECT_EQ(KldSampleCount(2, 0.01, 0.99, lo, hi), 97);
  EXPECT_EQ(KldSampleCount(10, 0.01, 0.99, lo, hi), 651);
  EXPECT_EQ(KldSampleCount(100, 0.01, 0.99, lo, hi), 5644);
  // eps = 0.05, z = 2.326 (delta = 0.01): k = 10 -> 90 * 1.3206^3 = 216.94.
  EXPECT_EQ(KldSampleCount(10, 0.05, 2.326, lo, hi), 217);
  // k = 1: (k - 1) = 0, the bound is 0, so the minimum applies.
  EXPECT_EQ(KldSampleCount(1, 0.01, 0.99, 100, 5000), 100);
  EXPECT_EQ(KldSampleCount(0, 0.01, 0.99, 100, 5000), 100);
}

TEST(AmclKldTest, SampleCountIsClampedToMinAndMax) {
  // amcl defaults: min_particles 100, max_particles 5000.
  EXPECT_EQ(KldSampleCount(2, 0.01, 0.99, 100, 5000), 100);   // 97 -> min
  EXPECT_EQ(KldSampleCount(10, 0.01, 0.99, 100, 5000), 651);  // inside
  EXPECT_EQ(KldSampleCount(100, 0.01, 0.99, 100, 5000), 5000);  // 5644 -> max
  EXPECT_EQ(KldSampleCount(1000000, 0.01, 0.99, 100, 5000), 5000);
  // Monotone in k.
  int prev = 0;
  for (int k = 1; k < 200; ++k) {
    const int n = KldSampleCount(k, 0.01, 0.99, 1, 1 << 30);
    EXPECT_GE(n, prev);
    prev = n;
  }
}

TEST(AmclKldTest, BinsAreHalfMetreByTenDegrees) {
  const PoseBin b = BinOfPose({1.26, -0.2, 0.0});
  EXPECT_EQ(b.ix, 2);
  EXPECT_EQ(b.iy, -1);
  EXPECT_EQ(b.iyaw, 18);  // (0 + 180 deg) / 10 deg
  EXPECT_EQ(BinOfPose({0, 0, kPi - 1e-9}).iyaw, 35);
  EXPECT_EQ(BinOfPose({0, 0, -kPi}).iyaw, 0);
  EXPECT_EQ(BinOfPose({0, 0, 3 * kPi - 1e-6}).iyaw, 35) << "yaw is wrapped";
  const PoseBin r = BinFromKey(BinKey(b));
  EXPECT_EQ(r.ix, b.ix);
  EXPECT_EQ(r.iy, b.iy);
  EXPECT_EQ(r.iyaw, b.iyaw);
}

TEST(AmclKldTest, CountsDistinctOccupiedBins) {
  std::vector<uint64_t> scratch;
  for (int k : {1, 2, 10, 100}) {
    std::vector<Particle> particles;
    for (int b = 0; b < k; ++b) {
      // Three particles per bin: bin centres along x and through yaw.
      const double x = 0.25 + 0.5 * (b % 10);
      const double yaw = -kPi + (b / 10 + 0.5) * 10 * kDeg;
      for (int r = 0; r < 3; ++r) {
        particles.push_back({{x + 0.05 * r, 0.1, yaw + r * kDeg}, 1.0});
      }
    }
    EXPECT_EQ(CountOccupiedBins(particles, &scratch), k);
  }
}

// --- Adaptive set size produced by the filter's resampling ---

AmclOptions ResampleEveryUpdate() {
  AmclOptions o;
  o.resample_interval = 1;
  return o;
}

LaserScan RoomScan(const Pose2& truth) {
  std::mt19937_64 rng(1);
  return testing::SimulateScan(testing::MakeAsymmetricRoom(), truth, {}, 180,
                               12.0, 0.0, &rng);
}

TEST(AmclKldTest, FilterShrinksToMinParticlesInOneBin) {
  const AmclOptions o = ResampleEveryUpdate();
  AmclFilter filter(o, testing::MakeAsymmetricRoom());
  // Centre of bin (4, 2, 20): every particle stays inside it.
  const Pose2 centre{2.25, 1.25, -kPi + 20.5 * 10 * kDeg};
  filter.SetPose(centre, Eigen::Matrix3d::Identity() * 1e-10);
  EXPECT_EQ(filter.particles().size(), 5000u) << "initialisation: max";
  const UpdateResult r = filter.Update({0, 0, 0}, RoomScan(centre));
  ASSERT_EQ(r.status, UpdateStatus::kUpdated);
  ASSERT_TRUE(r.resampled);
  EXPECT_EQ(filter.particles().size(), 100u);
}

TEST(AmclKldTest, FilterKeepsMaxParticlesWhenSpreadOut) {
  AmclOptions o = ResampleEveryUpdate();
  o.global_search = false;  // stay uniform (the search would seed a few places)
  AmclFilter filter(o, testing::MakeAsymmetricRoom(),
                    AmclFilter::Initialization::kGlobal);
  const UpdateResult r = filter.Update({0, 0, 0}, RoomScan({2.0, 1.5, 0.3}));
  ASSERT_TRUE(r.resampled);
  EXPECT_EQ(filter.particles().size(), 5000u);
}

TEST(AmclKldTest, FilterSetSizeSatisfiesBoundForItsOwnBins) {
  AmclOptions o = ResampleEveryUpdate();
  o.max_particles = 20000;
  AmclFilter filter(o, testing::MakeAsymmetricRoom());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  cov.diagonal() << 0.3 * 0.3, 0.3 * 0.3, std::pow(15 * kDeg, 2);
  const Pose2 truth{2.0, 1.5, 0.3};
  filter.SetPose(truth, cov);
  filter.Update({0, 0, 0}, RoomScan(truth));
  std::vector<uint64_t> scratch;
  const int k = CountOccupiedBins(filter.particles(), &scratch);
  const int required = KldSampleCount(k, o.kld_err, o.kld_z, o.min_particles,
                                      o.max_particles);
  const int n = static_cast<int>(filter.particles().size());
  EXPECT_GT(k, 1);
  EXPECT_GE(n, required) << "k = " << k;
  EXPECT_LE(n, required * 5 / 4 + 10) << "not grossly oversampled, k = " << k;
  EXPECT_GT(n, o.min_particles);
  EXPECT_LT(n, o.max_particles);
}

// --- Clustering on the same bins ---

TEST(AmclClusterTest, SeparatesHypothesesAndSortsByWeight) {
  std::vector<Particle> particles;
  for (int k = 0; k < 60; ++k) {
    particles.push_back({{1.0 + 0.01 * (k % 5), 1.0, 0.1}, 0.7 / 60});
  }
  for (int k = 0; k < 40; ++k) {
    // Three in four drawn by augmented MCL (Particle::injected).
    particles.push_back({{5.0, 5.0 + 0.01 * (k % 4), kPi / 2}, 0.3 / 40, k % 4 != 0});
  }
  const auto clusters = ClusterParticles(particles);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_NEAR(clusters[0].weight, 0.7, 1e-12);
  EXPECT_EQ(clusters[0].injected_weight, 0.0);
  EXPECT_NEAR(clusters[1].injected_weight, 0.3 * 0.75, 1e-12);
  EXPECT_EQ(clusters[0].particle_count, 60);
  EXPECT_NEAR(clusters[0].mean.x, 1.02, 1e-12);
  EXPECT_NEAR(clusters[0].mean.yaw, 0.1, 1e-12);
  EXPECT_NEAR(clusters[1].weight, 0.3, 1e-12);
  EXPECT_NEAR(clusters[1].mean.y, 5.015, 1e-12);
  EXPECT_NEAR(clusters[1].mean.yaw, kPi / 2, 1e-12);
  // x deviations -0.02..0.02 in 5 equal groups: variance 0.0002.
  EXPECT_NEAR(clusters[0].covariance(0, 0), 0.0002, 1e-12);
  EXPECT_NEAR(clusters[0].covariance(1, 1), 0.0, 1e-12);
}

TEST(AmclClusterTest, NeighbouringBinsJoinAndYawWrapsAroundPi) {
  std::vector<Particle> particles;
  // A chain of touching bins along x, yaw straddling +-pi.
  for (int k = 0; k < 40; ++k) {
    const double yaw = (k % 2 == 0) ? kPi - 0.02 : -kPi + 0.02;
    particles.push_back({{0.1 + 0.05 * k, 0.2, yaw}, 1.0 / 40});
  }
  const auto clusters = ClusterParticles(particles);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_NEAR(std::fabs(clusters[0].mean.yaw), kPi, 1e-9);
  EXPECT_NEAR(clusters[0].covariance(2, 2), 0.02 * 0.02, 1e-12)
      << "circular, not the +-pi spread";
  EXPECT_NEAR(clusters[0].weight, 1.0, 1e-12);
}

}  // namespace
}  // namespace amcl
}  // namespace minibot3d_navigation
