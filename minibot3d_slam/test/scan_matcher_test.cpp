// Tests of the gmapping-style scan matcher (src/scan_matcher.h) in a synthetic office.
#include "scan_matcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "minibot3d_testing/synthetic_world.h"

namespace minibot3d_slam {
namespace {

using minibot3d_testing::Office;
using minibot3d_testing::World;

// A map of the office built from scans at a few known poses.
Grid MappedOffice(const ScanMatcher& matcher, const World& world) {
  Grid grid(0.05);
  for (const Pose2& p : {Pose2{-4.0, -2.5, 0.3}, Pose2{-4.0, 2.5, -0.4}, Pose2{4.5, -2.5, 2.0},
                         Pose2{4.5, 0.5, 3.0}, Pose2{0.0, 2.5, -1.0}, Pose2{0.0, -2.5, 1.2}}) {
    matcher.Register(matcher.Prepare(world.Scan(p)), p, &grid);
  }
  return grid;
}

double AngleDiff(double a, double b) { return std::fabs(NormalizeAngle(a - b)); }

TEST(ScanMatcherTest, RecoversKnownOffset) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const World world = Office();
  const Grid grid = MappedOffice(matcher, world);
  const Pose2 truth{-3.0, -1.8, 0.7};
  const PreparedScan scan = matcher.Prepare(world.Scan(truth));
  for (const Pose2& off : {Pose2{0.1, 0.0, 0.05}, Pose2{-0.08, 0.06, -0.05}, Pose2{0.0, -0.1, 0.03}}) {
    const Pose2 guess{truth.x + off.x, truth.y + off.y, truth.yaw + off.yaw};
    Pose2 found;
    const double score = matcher.Optimize(grid, scan, guess, &found);
    EXPECT_NEAR(found.x, truth.x, 0.02) << "offset " << off.x << " " << off.y << " " << off.yaw;
    EXPECT_NEAR(found.y, truth.y, 0.02);
    EXPECT_LT(AngleDiff(found.yaw, truth.yaw), 0.01);
    EXPECT_GT(score, matcher.Score(grid, scan, guess));
  }
}

// Sub-cell matching: scans taken at poses a fraction of a cell (and of a degree) away from the
// guess are recovered to a fifth of a cell and 0.23° by Refine alone and after the hill climber
// (which alone ends up to 0.9 cell off here). The office's walls lie off the cell boundaries (see
// synthetic_world.h); its map holds six scans, so its mean endpoints leave a bias of a few
// millimetres at some poses.
TEST(ScanMatcherTest, RefineRecoversFractionalCellOffsets) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const World world = Office();
  const Grid grid = MappedOffice(matcher, world);
  const double cell = o.delta;
  for (const Pose2& truth : {Pose2{-3.0, -1.8, 0.7}, Pose2{2.5, 2.8, -2.5}, Pose2{-1.0, 2.4, 0.1}}) {
    const PreparedScan scan = matcher.Prepare(world.Scan(truth));
    for (const Pose2& off : {Pose2{0.37 * cell, -0.21 * cell, 0.004},
                             Pose2{-0.62 * cell, 0.45 * cell, -0.006}, Pose2{0.08 * cell, 0.71 * cell, 0.0}}) {
      SCOPED_TRACE(::testing::Message() << "truth " << truth.x << " " << truth.y << " " << truth.yaw
                                        << ", offset " << off.x << " " << off.y << " " << off.yaw);
      const Pose2 guess{truth.x + off.x, truth.y + off.y, truth.yaw + off.yaw};
      const Pose2 refined = matcher.Refine(grid, scan, guess);
      EXPECT_LT(std::hypot(refined.x - truth.x, refined.y - truth.y), 0.2 * cell);
      EXPECT_LT(AngleDiff(refined.yaw, truth.yaw), 0.004);
      Pose2 climbed;
      matcher.Optimize(grid, scan, guess, &climbed);
      const Pose2 both = matcher.Refine(grid, scan, climbed);
      EXPECT_LT(std::hypot(both.x - truth.x, both.y - truth.y), 0.2 * cell);
      EXPECT_LT(AngleDiff(both.yaw, truth.yaw), 0.004);
    }
  }
}

TEST(ScanMatcherTest, RefineKeepsThePoseWithoutEnoughMatches) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const Grid empty(0.05);
  const PreparedScan scan = matcher.Prepare(Office().Scan(Pose2{0.0, 2.5, 0.0}));
  const Pose2 start{0.01, 2.49, 0.02};
  const Pose2 out = matcher.Refine(empty, scan, start);
  EXPECT_EQ(out.x, start.x);
  EXPECT_EQ(out.y, start.y);
  EXPECT_EQ(out.yaw, start.yaw);
}

TEST(ScanMatcherTest, ScoreAndLikelihoodPeakAtTheTruth) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const World world = Office();
  const Grid grid = MappedOffice(matcher, world);
  const Pose2 truth{2.5, 2.8, -2.5};
  const PreparedScan scan = matcher.Prepare(world.Scan(truth));
  int matched_truth = 0, matched_off = 0;
  const double l_truth = matcher.LogLikelihood(grid, scan, truth, &matched_truth);
  const Pose2 off{truth.x + 0.15, truth.y, truth.yaw + 0.05};
  const double l_off = matcher.LogLikelihood(grid, scan, off, &matched_off);
  EXPECT_GT(l_truth, l_off);
  EXPECT_GT(matcher.Score(grid, scan, truth), matcher.Score(grid, scan, off));
  // Nearly every beam of the true pose finds its wall.
  EXPECT_GT(matched_truth, static_cast<int>(0.8 * static_cast<double>(scan.match_range.size())));
  EXPECT_LT(matched_off, matched_truth);
}

TEST(ScanMatcherTest, EmptyMapMatchesNothing) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const Grid empty(0.05);
  const PreparedScan scan = matcher.Prepare(Office().Scan(Pose2{0.0, 2.5, 0.0}));
  int matched = -1;
  const double l = matcher.LogLikelihood(empty, scan, Pose2{}, &matched);
  EXPECT_EQ(matched, 0);
  // Each beam without a match costs gmapping's null likelihood -0.5 / lsigma.
  EXPECT_NEAR(l, -0.5 / o.lsigma * static_cast<double>(scan.match_range.size()), 1e-9);
  EXPECT_EQ(matcher.Score(empty, scan, Pose2{}), 0.0);
}

TEST(ScanMatcherTest, SampleAroundFitsAGaussianAtTheMode) {
  GmappingOptions o;
  const ScanMatcher matcher(o);
  const World world = Office();
  const Grid grid = MappedOffice(matcher, world);
  const Pose2 truth{-3.0, 2.0, -0.3};
  const PreparedScan scan = matcher.Prepare(world.Scan(truth));
  const ProposalFit fit = matcher.SampleAround(grid, scan, truth);
  EXPECT_NEAR(fit.mean.x, truth.x, o.llsamplerange);
  EXPECT_NEAR(fit.mean.y, truth.y, o.llsamplerange);
  EXPECT_LE(AngleDiff(fit.mean.yaw, truth.yaw), o.lasamplerange);
  // A covariance: symmetric, non-negative diagonal, bounded by the sampled range.
  EXPECT_NEAR(fit.covariance(0, 1), fit.covariance(1, 0), 1e-15);
  for (int i = 0; i < 3; ++i) EXPECT_GE(fit.covariance(i, i), 0.0);
  EXPECT_LE(fit.covariance(0, 0), o.llsamplerange * o.llsamplerange);
  // log of the mean likelihood over the grid cannot exceed the best sample's.
  EXPECT_LE(fit.log_weight, matcher.LogLikelihood(grid, scan, truth) + 1e-9 +
                                std::fabs(matcher.LogLikelihood(grid, scan, truth)));
  EXPECT_GT(fit.log_weight, matcher.LogLikelihood(grid, scan, Pose2{truth.x + 0.2, truth.y, truth.yaw}));
  // Without a sampling range, the proposal is the mode itself with zero covariance.
  o.llsamplerange = 0.0;
  o.lasamplerange = 0.0;
  const ScanMatcher point(o);
  const ProposalFit single = point.SampleAround(grid, scan, truth);
  EXPECT_DOUBLE_EQ(single.mean.x, truth.x);
  EXPECT_DOUBLE_EQ(single.covariance.norm(), 0.0);
  EXPECT_NEAR(single.log_weight, point.LogLikelihood(grid, scan, truth), 1e-9);
}

// Optimize and SampleAround remember per beam and orientation which cells are admissible matches
// (scan_matcher.cpp, WindowCache); their results must equal evaluating every pose afresh, bit for
// bit, for every kernel size (up to 3 through the cache's patches, above without them).
TEST(ScanMatcherTest, CachedEvaluationEqualsFreshEvaluation) {
  const World world = Office();
  for (int kernel = 0; kernel <= 4; ++kernel) {
    GmappingOptions o;
    o.kernelSize = kernel;
    const ScanMatcher matcher(o);
    const Grid grid = MappedOffice(matcher, world);
    for (const Pose2& truth : {Pose2{-3.0, -1.8, 0.7}, Pose2{2.5, 2.8, -2.5}, Pose2{0.1, -0.2, 1.6}}) {
      const PreparedScan scan = matcher.Prepare(world.Scan(truth));
      for (const Pose2& off : {Pose2{0.12, -0.07, 0.06}, Pose2{-0.15, 0.1, -0.04}}) {
        const Pose2 guess{truth.x + off.x, truth.y + off.y, truth.yaw + off.yaw};
        Pose2 found;
        const double score = matcher.Optimize(grid, scan, guess, &found);
        EXPECT_EQ(score, matcher.Score(grid, scan, found)) << "kernelSize " << kernel;

        const ProposalFit fit = matcher.SampleAround(grid, scan, found);
        // The same fit from LogLikelihood at every sampled pose, as SampleAround computes it.
        const int nl = static_cast<int>(std::floor(o.llsamplerange / o.llsamplestep + 1e-9));
        const int na = static_cast<int>(std::floor(o.lasamplerange / o.lasamplestep + 1e-9));
        std::vector<double> l;
        double lmax = -std::numeric_limits<double>::infinity();
        for (int i = -nl; i <= nl; ++i) {
          for (int j = -nl; j <= nl; ++j) {
            for (int t = -na; t <= na; ++t) {
              const Pose2 p{found.x + i * o.llsamplestep, found.y + j * o.llsamplestep,
                            NormalizeAngle(found.yaw + t * o.lasamplestep)};
              l.push_back(matcher.LogLikelihood(grid, scan, p));
              lmax = std::max(lmax, l.back());
            }
          }
        }
        double wsum = 0.0;
        for (double x : l) wsum += std::exp(x - lmax);
        EXPECT_EQ(fit.log_weight, lmax + std::log(wsum / static_cast<double>(l.size())))
            << "kernelSize " << kernel;
      }
    }
  }
}

// One beam of each kind, range_min 0.1, range_max 20: 1.0, NaN, +inf, 0, 0.05 (below
// range_min), 7.0, 20.0 (at range_max), 25.0 (beyond), 2.0, -inf.
LaserScan EveryKindOfReading() {
  LaserScan s;
  s.range_min = 0.1;
  s.range_max = 20.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  s.ranges = {1.0, nan, inf, 0.0, 0.05, 7.0, 20.0, 25.0, 2.0, -inf};
  for (std::size_t i = 0; i < s.ranges.size(); ++i) s.angles.push_back(0.1 * static_cast<double>(i));
  return s;
}

TEST(ScanMatcherTest, PrepareClassifiesBeams) {
  GmappingOptions o;
  o.maxUrange = 5.0;
  const LaserScan s = EveryKindOfReading();
  const PreparedScan p = ScanMatcher(o).Prepare(s);
  // 1.0, 7.0 (cut to 5, free only) and 2.0 remain; NaN, ±inf, 0, below range_min, at or beyond
  // range_max are no-returns.
  ASSERT_EQ(p.map_range.size(), 3u);
  EXPECT_DOUBLE_EQ(p.map_range[1], 5.0);
  EXPECT_EQ(p.map_hit[1], 0);
  EXPECT_EQ(p.map_hit[0], 1);
  ASSERT_EQ(p.match_range.size(), 2u);  // beams beyond maxUrange are not matched
  EXPECT_DOUBLE_EQ(p.match_range[1], 2.0);
  // lskip = 1 keeps every second matchable beam.
  o.lskip = 1;
  EXPECT_EQ(ScanMatcher(o).Prepare(s).match_range.size(), 1u);
  // maxRange below the sensor's range_max turns 7.0 into a no-return.
  o.lskip = 0;
  o.maxRange = 6.0;
  EXPECT_EQ(ScanMatcher(o).Prepare(s).map_range.size(), 2u);
}

TEST(ScanMatcherTest, ClearMaxRangeTurnsNoReturnsIntoFreeBeams) {
  GmappingOptions o;
  o.maxUrange = 5.0;
  o.clearMaxRange = 1;
  const LaserScan s = EveryKindOfReading();
  const PreparedScan p = ScanMatcher(o).Prepare(s);
  // +inf, 20.0 (at range_max) and 25.0 now clear out to maxUrange and mark nothing; NaN, -inf, 0
  // and below range_min still update nothing.
  ASSERT_EQ(p.map_range.size(), 6u);
  const std::vector<std::uint32_t> beams = {0, 2, 5, 6, 7, 8};
  const std::vector<double> ranges = {1.0, 5.0, 5.0, 5.0, 5.0, 2.0};
  const std::vector<int> hits = {1, 0, 0, 0, 0, 1};
  for (std::size_t k = 0; k < beams.size(); ++k) {
    EXPECT_EQ(p.map_beam[k], beams[k]) << k;
    EXPECT_DOUBLE_EQ(p.map_range[k], ranges[k]) << k;
    EXPECT_EQ(p.map_hit[k], hits[k]) << k;
  }
  ASSERT_EQ(p.match_range.size(), 2u);  // only real returns are matched
  // With maxUrange beyond the sensor's reach a no-return clears only as far as that reach.
  o.maxUrange = 30.0;
  o.maxRange = 0.0;
  const PreparedScan q = ScanMatcher(o).Prepare(s);
  ASSERT_EQ(q.map_range.size(), 6u);
  EXPECT_DOUBLE_EQ(q.map_range[1], 20.0);
  EXPECT_EQ(q.map_hit[1], 0);
}

// Down a corridor longer than the lidar reaches, the beams along it return nothing. gmapping drops
// them, so one scan leaves the corridor ahead unknown from where the side walls' beams stop
// crossing it (a few metres at a 1° beam spacing); with clearMaxRange they clear it to maxUrange.
TEST(ScanMatcherTest, ClearMaxRangeMapsALongCorridorAhead) {
  World corridor;
  corridor.walls.push_back({-1.0, -0.7513, 60.0, -0.7513});
  corridor.walls.push_back({-1.0, 0.7487, 60.0, 0.7487});
  corridor.walls.push_back({-1.0, -0.7513, -1.0, 0.7487});
  const Pose2 robot{0.0137, -0.0213, 0.0};
  const LaserScan scan = corridor.Scan(robot, 361, 2 * M_PI * 360 / 361, 12.0);
  ASSERT_TRUE(std::isinf(scan.ranges[180])) << "the beam straight ahead must see no end";
  auto unknown_ahead = [&](int clear_max_range) {
    GmappingOptions o;
    o.maxUrange = 11.5;
    o.clearMaxRange = clear_max_range;
    const ScanMatcher matcher(o);
    Grid grid(0.05);
    matcher.Register(matcher.Prepare(scan), robot, &grid);
    // Cells along the corridor's centre line from 1 m to 11 m ahead that no beam crossed.
    int unknown = 0;
    for (double x = 1.0; x <= 11.0; x += 0.05) {
      if (grid.At(grid.CellX(x), grid.CellY(robot.y)).visits == 0) ++unknown;
    }
    return unknown;
  };
  EXPECT_GT(unknown_ahead(0), 100) << "the test proves nothing: the corridor ahead is mapped anyway";
  EXPECT_EQ(unknown_ahead(1), 0);
}

}  // namespace
}  // namespace minibot3d_slam
