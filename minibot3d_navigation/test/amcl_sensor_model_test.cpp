// Sensor-model and map tests on tiny hand-checkable maps: the distance field,
// the ray caster, scan preprocessing, likelihoods computed by hand, and the
// sanity property that a scan matches the true pose better than a shifted or
// rotated one.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcl_test_utils.h"
#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/sensor_model.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

using testing::FillBox;
using testing::MakeAsymmetricRoom;
using testing::MakeFreeGrid;
using testing::SimulateScan;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// 1.0 m x 0.7 m, 10 cm cells (10 x 7), wall = the column i = 9.
OccupancyGrid WallGrid() {
  OccupancyGrid g = MakeFreeGrid(1.0, 0.7, 0.1);
  FillBox(&g, 0.9, 0.0, 1.0, 0.7);
  return g;
}

TEST(AmclMapTest, DistanceFieldCountsCellsToNearestObstacle) {
  MapModel map(WallGrid(), 2.0);
  for (int j = 0; j < 7; ++j) {
    EXPECT_DOUBLE_EQ(map.Distance(9, j), 0.0);
    EXPECT_NEAR(map.Distance(8, j), 0.1, 1e-6) << "next to the wall: 1 cell";
    EXPECT_NEAR(map.Distance(7, j), 0.2, 1e-6);
    EXPECT_NEAR(map.Distance(0, j), 0.9, 1e-6);
  }
  EXPECT_TRUE(map.IsOccupied(9, 3));
  EXPECT_TRUE(map.IsFree(8, 3));
  EXPECT_EQ(map.free_cells().size(), 9u * 7u);
}

TEST(AmclMapTest, DistanceFieldIsEuclideanAndCapped) {
  OccupancyGrid g = MakeFreeGrid(0.5, 0.5, 0.1);
  g.data[2 * 5 + 2] = 100;  // single obstacle at cell (2, 2)
  MapModel map(g, 0.25);
  EXPECT_NEAR(map.Distance(3, 3), std::sqrt(2.0) * 0.1, 1e-5);
  EXPECT_NEAR(map.Distance(4, 2), 0.2, 1e-5);
  EXPECT_NEAR(map.Distance(4, 3), std::sqrt(5.0) * 0.1, 1e-5);
  EXPECT_NEAR(map.Distance(4, 4), 0.25, 1e-6) << "sqrt(8)*0.1 capped at 0.25";
  EXPECT_DOUBLE_EQ(map.DistanceAtGridPoint(-0.01, 0.2), 0.25) << "off-map";
  EXPECT_DOUBLE_EQ(map.DistanceAtGridPoint(kNaN, 0.2), 0.25);

  MapModel empty(MakeFreeGrid(0.5, 0.5, 0.1), 1.5);
  EXPECT_DOUBLE_EQ(empty.Distance(2, 2), 1.5) << "no obstacle at all";
}

TEST(AmclMapTest, CellTransformsHonourOriginAndYaw) {
  OccupancyGrid g = MakeFreeGrid(1.0, 1.0, 0.1, 1.0, 2.0, kPi / 2);
  MapModel map(g, 1.0);
  double wx, wy;
  map.CellCenterToWorld(3, 1, &wx, &wy);
  // grid-frame centre (0.35, 0.15) rotated by +90 deg: (-0.15, 0.35).
  EXPECT_NEAR(wx, 0.85, 1e-12);
  EXPECT_NEAR(wy, 2.35, 1e-12);
  int i = -1, j = -1;
  ASSERT_TRUE(map.WorldToCell(wx, wy, &i, &j));
  EXPECT_EQ(i, 3);
  EXPECT_EQ(j, 1);
  EXPECT_FALSE(map.WorldToCell(1.05, 2.5, &i, &j)) << "behind the origin";
}

TEST(AmclMapTest, RejectsBrokenMapsWithNamedErrors) {
  OccupancyGrid occupied = MakeFreeGrid(0.3, 0.3, 0.1);
  occupied.data.assign(9, 100);
  occupied.data[4] = -1;
  try {
    MapModel map(occupied, 2.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no free cells"), std::string::npos)
        << e.what();
  }
  OccupancyGrid wrong_size = MakeFreeGrid(0.3, 0.3, 0.1);
  wrong_size.data.pop_back();
  EXPECT_THROW(MapModel(wrong_size, 2.0), std::invalid_argument);
  OccupancyGrid bad_value = MakeFreeGrid(0.3, 0.3, 0.1);
  bad_value.data[0] = 101;
  EXPECT_THROW(MapModel(bad_value, 2.0), std::invalid_argument);
  OccupancyGrid bad_res = MakeFreeGrid(0.3, 0.3, 0.1);
  bad_res.resolution = 0.0;
  EXPECT_THROW(MapModel(bad_res, 2.0), std::invalid_argument);
}

TEST(AmclMapTest, RayCastStopsAtWallsAndMapEdge) {
  MapModel map(WallGrid(), 2.0);
  // From (0.25, 0.35) east: wall face at x = 0.9.
  EXPECT_NEAR(map.CalcRange({0.25, 0.35, 0.0}, 5.0), 0.65, 1e-9);
  // West: the map edge at x = 0 (off-map is not free).
  EXPECT_NEAR(map.CalcRange({0.25, 0.35, kPi}, 5.0), 0.25, 1e-9);
  // North-east at 45 deg: top edge y = 0.7 reached first.
  EXPECT_NEAR(map.CalcRange({0.25, 0.35, kPi / 4}, 5.0),
              0.35 * std::sqrt(2.0), 1e-9);
  EXPECT_DOUBLE_EQ(map.CalcRange({0.25, 0.35, 0.0}, 0.3), 0.3) << "max range";
  EXPECT_DOUBLE_EQ(map.CalcRange({0.95, 0.35, 0.0}, 5.0), 0.0) << "in a wall";
}

TEST(AmclMapTest, RayCastAgreesWithIndependentRayMarch) {
  const OccupancyGrid g = MakeAsymmetricRoom();
  MapModel map(g, 2.0);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 200; ++k) {
    const Pose2 ray = map.SampleFreePose(&rng);
    const double expected = testing::MarchRange(g, ray, 12.0);
    EXPECT_NEAR(map.CalcRange(ray, 12.0), expected, 0.005)
        << ray.x << " " << ray.y << " " << ray.yaw;
  }
}

TEST(AmclScanTest, PreprocessingMirrorsAmclNode) {
  AmclOptions o;
  o.laser_max_beams = 100;
  LaserScan scan;
  scan.range_min = 0.15;
  scan.range_max = 12.0;
  scan.ranges = {0.05f, static_cast<float>(kInf), static_cast<float>(-kInf),
                 static_cast<float>(kNaN), 3.0f, 20.0f};
  scan.angles = MakeBeamAngles(-0.5, 0.2, 6);
  PreparedScan ps;
  std::string err;
  ASSERT_TRUE(PrepareScan(scan, o, &ps, &err)) << err;
  ASSERT_EQ(ps.beams.size(), 5u);
  EXPECT_EQ(ps.nan_count, 1);
  EXPECT_EQ(ps.subsampled_count, 6);
  const bool expect_max[] = {true, true, true, false, true};
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(ps.beams[k].is_max, expect_max[k]) << k;
    if (expect_max[k]) {
      EXPECT_DOUBLE_EQ(ps.beams[k].range, 12.0);
    }
  }
  EXPECT_DOUBLE_EQ(ps.beams[3].range, 3.0);
  EXPECT_DOUBLE_EQ(ps.beams[3].bearing, -0.5 + 4 * 0.2);

  o.laser_max_range = 2.5;  // tighter than the scan: 3.0 becomes max range
  o.laser_min_range = 0.5;
  ASSERT_TRUE(PrepareScan(scan, o, &ps, &err)) << err;
  EXPECT_DOUBLE_EQ(ps.range_max, 2.5);
  EXPECT_DOUBLE_EQ(ps.range_min, 0.5);
  EXPECT_TRUE(ps.beams[3].is_max);
}

TEST(AmclScanTest, SubsamplesEvenlyLikeAmcl) {
  AmclOptions o;  // laser_max_beams 30
  LaserScan scan;
  scan.range_max = 10.0;
  scan.ranges.assign(360, 1.0f);
  scan.angles = MakeBeamAngles(-kPi, kPi / 180, 360);
  PreparedScan ps;
  std::string err;
  ASSERT_TRUE(PrepareScan(scan, o, &ps, &err)) << err;
  ASSERT_EQ(ps.beams.size(), 30u);  // stride (360-1)/(30-1) = 12
  for (int k = 0; k < 30; ++k) {
    EXPECT_DOUBLE_EQ(ps.beams[k].bearing, scan.angles[12 * k]);
  }
}

TEST(AmclScanTest, RejectsMalformedScans) {
  AmclOptions o;
  LaserScan good;
  good.range_max = 10.0;
  good.ranges = {1.0f, 2.0f};
  good.angles = {0.0, 0.1};
  PreparedScan ps;
  std::string err;
  ASSERT_TRUE(PrepareScan(good, o, &ps, &err));

  LaserScan s = good;
  s.angles.pop_back();
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
  EXPECT_NE(err.find("2 ranges but 1 angles"), std::string::npos) << err;
  s = good;
  s.ranges.clear();
  s.angles.clear();
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
  s = good;
  s.range_max = 0.0;
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
  s = good;
  s.range_max = kInf;
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
  s = good;
  s.sensor_in_base.yaw = kNaN;
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
  s = good;
  s.angles[1] = kNaN;
  EXPECT_FALSE(PrepareScan(s, o, &ps, &err));
}

// A single-particle evaluation helper.
double LogLikelihood(SensorModel* model, const LaserScan& scan,
                     const AmclOptions& o, const Pose2& pose,
                     bool converged = false) {
  PreparedScan ps;
  std::string err;
  EXPECT_TRUE(PrepareScan(scan, o, &ps, &err)) << err;
  std::vector<Particle> particles{{pose, 1.0}};
  std::vector<double> ll;
  model->ComputeLogLikelihoods(ps, particles, converged, &ll);
  return ll.at(0);
}

// Robot at (0.25, 0.35) facing east in WallGrid; beam end points at known
// distances from the wall: 0.85 -> 0.1, 0.65 -> 0.3, (0.25, 0.55) -> 0.7,
// off-map -> max_dist 2.0; one max-range and one NaN reading are ignored.
LaserScan HandScan() {
  LaserScan scan;
  scan.range_min = 0.05;
  scan.range_max = 4.0;
  scan.ranges = {0.6f, 0.4f, 4.0f, static_cast<float>(kNaN), 0.2f, 0.5f};
  scan.angles = {0.0, 0.0, 0.3, 0.2, kPi / 2, kPi};
  return scan;
}

double HandPz(double d, const AmclOptions& o, double range_max) {
  return o.laser_z_hit *
             std::exp(-d * d / (2 * o.laser_sigma_hit * o.laser_sigma_hit)) +
         o.laser_z_rand / range_max;
}

TEST(AmclSensorModelTest, LikelihoodFieldMatchesHandComputation) {
  auto map = std::make_shared<MapModel>(WallGrid(), 2.0);
  AmclOptions o;
  o.laser_max_beams = 100;
  auto model = CreateSensorModel(o, map);
  EXPECT_EQ(model->name(), "likelihood_field");
  double p = 1.0;
  for (double d : {0.1, 0.3, 0.7, 2.0}) p += std::pow(HandPz(d, o, 4.0), 3);
  const Pose2 robot{0.25, 0.35, 0.0};
  EXPECT_NEAR(LogLikelihood(model.get(), HandScan(), o, robot), std::log(p),
              1e-6);

  // The laser pose in the base frame is applied: a laser mounted 0.1 m ahead
  // and turned around (as on minibot3d) sees the same from 0.1 m further back.
  LaserScan flipped = HandScan();
  flipped.sensor_in_base = {0.1, 0.0, kPi};
  for (double& a : flipped.angles) a = NormalizeAngle(a + kPi);
  EXPECT_NEAR(LogLikelihood(model.get(), flipped, o, {0.15, 0.35, 0.0}),
              std::log(p), 1e-6);
}

TEST(AmclSensorModelTest, LikelihoodFieldProbIsProductOfBeams) {
  auto map = std::make_shared<MapModel>(WallGrid(), 2.0);
  AmclOptions o;
  o.laser_max_beams = 100;
  o.laser_model_type = "likelihood_field_prob";
  auto model = CreateSensorModel(o, map);
  double log_p = 0.0;
  for (double d : {0.1, 0.3, 0.7, 2.0}) log_p += std::log(HandPz(d, o, 4.0));
  EXPECT_NEAR(LogLikelihood(model.get(), HandScan(), o, {0.25, 0.35, 0.0}),
              log_p, 1e-6);

  // Tempered: the four used beams weigh as laser_independent_beams; more
  // than are used leaves the product as it is.
  for (double k : {0.5, 2.0, 10.0}) {
    o.laser_independent_beams = k;
    auto tempered = CreateSensorModel(o, map);
    EXPECT_NEAR(
        LogLikelihood(tempered.get(), HandScan(), o, {0.25, 0.35, 0.0}),
        std::min(1.0, k / 4.0) * log_p, 1e-6)
        << k;
  }
}

TEST(AmclSensorModelTest, BeamModelMatchesHandComputation) {
  auto map = std::make_shared<MapModel>(WallGrid(), 2.0);
  AmclOptions o;
  o.laser_model_type = "beam";
  auto model = CreateSensorModel(o, map);
  const double rmax = 4.0, expected = 0.65, denom = 2 * 0.2 * 0.2;
  auto one_beam = [&](double r) {
    LaserScan s;
    s.range_max = rmax;
    s.ranges = {static_cast<float>(r)};
    s.angles = {0.0};
    return LogLikelihood(model.get(), s, o, {0.25, 0.35, 0.0});
  };
  auto cube_log = [](double pz) { return std::log(1.0 + pz * pz * pz); };
  // Exact hit (0.6625 is exact in float, so z = 0 and no short term).
  EXPECT_NEAR(map->CalcRange({0.2375, 0.35, 0.0}, rmax), 0.6625, 1e-12);
  LaserScan exact;
  exact.range_max = rmax;
  exact.ranges = {0.6625f};
  exact.angles = {0.0};
  EXPECT_NEAR(LogLikelihood(model.get(), exact, o, {0.2375, 0.35, 0.0}),
              cube_log(0.95 + 0.05 / rmax), 1e-9);
  // Short reading: hit + short (exponential) + random.
  const double zs = 0.4 - expected;
  EXPECT_NEAR(one_beam(0.4),
              cube_log(0.95 * std::exp(-zs * zs / denom) +
                       0.1 * 0.1 * std::exp(-0.1 * 0.4) + 0.05 / rmax),
              1e-5);
  // Long reading: no short term.
  const double zl = 0.9 - expected;
  EXPECT_NEAR(one_beam(0.9),
              cube_log(0.95 * std::exp(-zl * zl / denom) + 0.05 / rmax), 1e-5);
  // Max-range reading: z_max instead of z_rand.
  const double zm = rmax - expected;
  EXPECT_NEAR(one_beam(rmax),
              cube_log(0.95 * std::exp(-zm * zm / denom) + 0.05), 1e-6);
  EXPECT_GT(one_beam(0.66), one_beam(0.4));
  EXPECT_GT(one_beam(0.66), one_beam(0.9));
  EXPECT_GT(one_beam(0.4), one_beam(0.9)) << "short readings are explained";
}

class AlignedScanTest : public ::testing::TestWithParam<std::string> {};

TEST_P(AlignedScanTest, TruePoseBeatsShiftedAndRotatedPoses) {
  const OccupancyGrid g = MakeAsymmetricRoom();
  auto map = std::make_shared<MapModel>(g, 2.0);
  AmclOptions o;
  o.laser_model_type = GetParam();
  o.laser_max_beams = 60;
  auto model = CreateSensorModel(o, map);
  std::mt19937_64 rng(11);
  const Pose2 truth{2.0, 1.5, 0.3};
  const LaserScan scan =
      SimulateScan(g, truth, {0.02, 0.0, kPi}, 360, 12.0, 0.01, &rng);
  const double best = LogLikelihood(model.get(), scan, o, truth);
  const Pose2 others[] = {{2.2, 1.5, 0.3}, {2.0, 1.3, 0.3}, {1.9, 1.6, 0.3},
                           {2.0, 1.5, 0.3 + 5 * kPi / 180},
                           {2.0, 1.5, 0.3 - 5 * kPi / 180}};
  for (const Pose2& p : others) {
    EXPECT_GT(best, LogLikelihood(model.get(), scan, o, p))
        << GetParam() << " at " << p.x << " " << p.y << " " << p.yaw;
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, AlignedScanTest,
                         ::testing::Values("likelihood_field",
                                           "likelihood_field_prob", "beam"));

// Beam skipping: with a converged set, beams blocked by an unmapped object
// (no particle sees their end point near a mapped obstacle) are ignored, so
// the likelihood equals that of the scan without those beams.
TEST(AmclSensorModelTest, BeamSkippingIgnoresBeamsNoParticleExplains) {
  const OccupancyGrid g = MakeAsymmetricRoom();
  auto map = std::make_shared<MapModel>(g, 2.0);
  AmclOptions o;
  o.laser_model_type = "likelihood_field_prob";
  o.laser_max_beams = 30;
  o.do_beamskip = true;
  const Pose2 truth{2.0, 1.5, 0.3};
  std::mt19937_64 rng(5);
  LaserScan scan = SimulateScan(g, truth, {}, 30, 12.0, 0.0, &rng);

  // Block 6 beams at mid-range, where the end point is far from any wall.
  LaserScan blocked = scan, without = scan;
  int n_blocked = 0;
  for (size_t b = 0; b < scan.ranges.size() && n_blocked < 6; ++b) {
    const double half = 0.5 * scan.ranges[b];
    const double a = truth.yaw + scan.angles[b];
    int i, j;
    if (!map->WorldToCell(truth.x + half * std::cos(a),
                          truth.y + half * std::sin(a), &i, &j) ||
        map->Distance(i, j) < 1.0) {
      continue;
    }
    blocked.ranges[b] = static_cast<float>(half);
    without.ranges[b] = static_cast<float>(kNaN);
    ++n_blocked;
  }
  ASSERT_EQ(n_blocked, 6);

  std::normal_distribution<double> n(0.0, 0.02);
  std::vector<Particle> particles(200);
  for (Particle& p : particles) {
    p.pose = {truth.x + n(rng), truth.y + n(rng), truth.yaw + 0.5 * n(rng)};
    p.weight = 1.0 / 200;
  }
  auto eval = [&](const AmclOptions& opts, const LaserScan& s, bool converged) {
    auto model = CreateSensorModel(opts, map);
    PreparedScan ps;
    std::string err;
    EXPECT_TRUE(PrepareScan(s, opts, &ps, &err)) << err;
    std::vector<double> ll;
    model->ComputeLogLikelihoods(ps, particles, converged, &ll);
    return ll;
  };
  AmclOptions no_skip = o;
  no_skip.do_beamskip = false;
  const auto skipped = eval(o, blocked, true);
  const auto reference = eval(no_skip, without, false);
  const auto not_converged = eval(o, blocked, false);
  for (size_t k = 0; k < particles.size(); ++k) {
    EXPECT_NEAR(skipped[k], reference[k], 1e-9);
    EXPECT_LT(not_converged[k], reference[k] - 1.0) << "blocked beams count";
  }
  // 6 of 30 skipped >= 20 %: likely converged to a wrong pose, so all beams
  // are integrated again.
  AmclOptions strict = o;
  strict.beam_skip_error_threshold = 0.2;
  const auto all = eval(strict, blocked, true);
  const auto all_reference = eval(no_skip, blocked, false);
  for (size_t k = 0; k < particles.size(); ++k) {
    EXPECT_NEAR(all[k], all_reference[k], 1e-9);
  }
}

TEST(AmclSensorModelTest, UsableBeamsAndFactoryErrors) {
  auto map = std::make_shared<MapModel>(WallGrid(), 2.0);
  AmclOptions o;
  LaserScan all_max;
  all_max.range_max = 4.0;
  all_max.ranges = {4.0f, static_cast<float>(kInf), 9.0f};
  all_max.angles = {0.0, 0.1, 0.2};
  PreparedScan ps;
  std::string err;
  ASSERT_TRUE(PrepareScan(all_max, o, &ps, &err));
  EXPECT_EQ(CreateSensorModel(o, map)->UsableBeamCount(ps), 0);
  o.laser_model_type = "beam";
  EXPECT_EQ(CreateSensorModel(o, map)->UsableBeamCount(ps), 3);

  o.laser_model_type = "sonar";
  EXPECT_THROW(CreateSensorModel(o, map), std::invalid_argument);
  o.laser_model_type = "likelihood_field";
  o.laser_sigma_hit = -0.1;
  try {
    CreateSensorModel(o, map);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("laser_sigma_hit=-0.1"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace amcl
}  // namespace minibot3d_navigation
