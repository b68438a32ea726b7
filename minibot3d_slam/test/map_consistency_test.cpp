// Map consistency between passes (map_consistency.h): a correct trajectory agrees with itself, a
// lap placed off the map is found, places seen once are not judged, bad input is named.
#include "minibot3d_slam/map_consistency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "minibot3d_testing/synthetic_world.h"

namespace minibot3d_slam {
namespace {

using minibot3d_testing::Office;
using minibot3d_testing::World;

// Laps round the office's inner block (a rectangle x = ±4, y = ±2.5), a 180° laser of 181 beams
// every 0.1 m, facing along the path. `err` is added to every pose of lap `bad_lap` (-1: none).
std::vector<PlacedScan> Laps(const World& world, int laps, int bad_lap = -1, Pose2 err = Pose2()) {
  const double corners[5][2] = {{-4, -2.5}, {4, -2.5}, {4, 2.5}, {-4, 2.5}, {-4, -2.5}};
  std::vector<PlacedScan> out;
  double t = 0.0;
  for (int lap = 0; lap < laps; ++lap) {
    for (int side = 0; side < 4; ++side) {
      const double x0 = corners[side][0], y0 = corners[side][1];
      const double x1 = corners[side + 1][0], y1 = corners[side + 1][1];
      const double len = std::hypot(x1 - x0, y1 - y0);
      const double yaw = std::atan2(y1 - y0, x1 - x0);
      for (double d = 0.0; d < len; d += 0.1) {
        const Pose2 truth{x0 + (x1 - x0) * d / len, y0 + (y1 - y0) * d / len, yaw};
        PlacedScan ps;
        ps.time = t;
        t += 0.1;
        ps.scan = world.Scan(truth);
        ps.pose = truth;
        if (lap == bad_lap) {
          ps.pose = minibot3d_common::Compose(Pose2{err.x, err.y, err.yaw}, truth);
        }
        out.push_back(ps);
      }
    }
  }
  return out;
}

TEST(MapConsistency, ACorrectTrajectoryAgreesWithItselfWhereItCameBack) {
  const ConsistencyReport r = EvaluateConsistency(Laps(Office(), 2));
  EXPECT_GT(r.scans_checked, 40);
  EXPECT_GT(r.agreed, 5000);
  EXPECT_LT(r.conflict_fraction, 0.01) << r.conflicts << " conflicts, " << r.agreed << " agreed";
  EXPECT_GT(r.scans_judged, 40);
  EXPECT_TRUE(r.inconsistent.empty()) << r.inconsistent.size() << " scans judged inconsistent";
}

TEST(MapConsistency, ALapPlacedOffTheMapConflictsWithTheOthers) {
  // The second of three laps 0.28 m off and turned by 2°, as a missed loop closure leaves it.
  const ConsistencyReport good = EvaluateConsistency(Laps(Office(), 3));
  const ConsistencyReport bad = EvaluateConsistency(Laps(Office(), 3, 1, Pose2{0.2, 0.2, 0.035}));
  EXPECT_EQ(good.conflicts, 0);
  EXPECT_GT(bad.conflict_fraction, 0.05);
  // A wall the bad lap puts nearer to the robot than the good laps saw it holds the bad lap's
  // endpoints in the good laps' free space; one it puts farther away lets the bad lap's beams run
  // through the good laps' wall, and then the good laps' endpoints are the ones in free space.
  // Only the bad lap has most of its endpoints off: every scan judged inconsistent is in it.
  const double lap_time = bad.scans / 3 * 0.1;
  int in_bad_lap = 0;
  for (const ScanConsistency& s : bad.inconsistent) {
    EXPECT_GE(s.time, lap_time - 1e-6);
    EXPECT_LT(s.time, 2 * lap_time);
    if (s.time >= lap_time - 1e-6 && s.time < 2 * lap_time) ++in_bad_lap;
  }
  EXPECT_GE(in_bad_lap, bad.scans_checked / 3 / 4);
}

TEST(MapConsistency, ALargerErrorConflictsMore) {
  double last = -1.0;
  for (double e : {0.0, 0.15, 0.3, 0.6}) {
    const ConsistencyReport r = EvaluateConsistency(Laps(Office(), 2, 1, Pose2{0.0, e, 0.0}));
    EXPECT_GT(r.conflict_fraction, last) << "shift " << e;
    last = r.conflict_fraction;
  }
}

TEST(MapConsistency, PlacesSeenOnceAreNotJudged) {
  // One lap: the ends of the lap meet within `separation` of path only at its start and end, so
  // with a separation longer than the lap nothing is another pass.
  ConsistencyOptions o;
  o.separation = 100.0;
  const ConsistencyReport r = EvaluateConsistency(Laps(Office(), 1, 0, Pose2{0.0, 0.0, 0.3}), o);
  EXPECT_EQ(r.agreed, 0);
  EXPECT_EQ(r.conflicts, 0);
  EXPECT_GT(r.not_revisited, 1000);
  EXPECT_EQ(r.scans_judged, 0);
  EXPECT_EQ(r.conflict_fraction, 0.0);
}

TEST(MapConsistency, ScansAreCheckedAsGmappingPicksTheScansItProcesses) {
  ConsistencyOptions o;
  o.every_distance = 1.0;
  o.every_angle = 10.0;
  const std::vector<PlacedScan> scans = Laps(Office(), 1);
  const ConsistencyReport r = EvaluateConsistency(scans, o);
  // 26 m of path at 0.1 m a reading: a checked scan about every 10 readings (every 1 m in a
  // straight line; the corners cut the way a little).
  EXPECT_NEAR(r.scans_checked, 26, 2);
  o.every_distance = 0.0;
  EXPECT_EQ(EvaluateConsistency(scans, o).scans_checked, static_cast<int>(scans.size()));
}

TEST(MapConsistency, BadInputIsNamed) {
  ConsistencyOptions o;
  o.resolution = 0.0;
  o.scan_conflict_fraction = 2.0;
  try {
    EvaluateConsistency({}, o);
    FAIL() << "invalid options accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("resolution=0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scan_conflict_fraction=2"), std::string::npos) << e.what();
  }
  std::vector<PlacedScan> scans = Laps(Office(), 1);
  scans[3].pose.x = std::numeric_limits<double>::quiet_NaN();
  try {
    EvaluateConsistency(scans);
    FAIL() << "a NaN pose accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("time 0.3"), std::string::npos) << e.what();
  }
  scans = Laps(Office(), 1);
  scans[2].scan.angles.pop_back();
  EXPECT_THROW(EvaluateConsistency(scans), std::invalid_argument);
  EXPECT_EQ(EvaluateConsistency({}).scans, 0);
}

TEST(MapConsistency, OptionsAreSetByName) {
  ConsistencyOptions o;
  ConsistencyOptionTable().Set("separation", "25", &o);
  ConsistencyOptionTable().Set("min_scan_endpoints", "7", &o);
  EXPECT_EQ(o.separation, 25.0);
  EXPECT_EQ(o.min_scan_endpoints, 7);
  EXPECT_THROW(ConsistencyOptionTable().Set("seperation", "25", &o), std::invalid_argument);
  EXPECT_THROW(ConsistencyOptionTable().Set("tolerance", "wide", &o), std::invalid_argument);
}

TEST(ReferenceScans, TakesTheReadingsAReferenceLogHoldsEachOnce) {
  const auto scan = [](std::vector<double> ranges) {
    LaserScan s;
    s.ranges = std::move(ranges);
    return s;
  };
  const double inf = std::numeric_limits<double>::infinity();
  // A reference that kept two of a run's readings, one of them written twice (the robot stood).
  ReferenceScans reference({scan({1.25, 2.5, inf}), scan({3.0, 3.0, 3.0}), scan({3.0, 3.0, 3.0})});
  EXPECT_EQ(reference.size(), 3);
  EXPECT_FALSE(reference.Take(scan({1.25, 2.5, 4.0})));    // a no-return is not a reading
  EXPECT_FALSE(reference.Take(scan({1.25, 2.53, inf})));   // 3 cm off: another reading
  EXPECT_FALSE(reference.Take(scan({1.25, 2.5})));         // fewer beams
  EXPECT_TRUE(reference.Take(scan({1.2504, 2.4998, inf})));  // the same to the log's precision
  EXPECT_FALSE(reference.Take(scan({1.25, 2.5, inf})));    // taken already
  EXPECT_TRUE(reference.Take(scan({3.0, 3.0, 3.0})));
  EXPECT_TRUE(reference.Take(scan({3.0, 3.0, 3.0})));
  EXPECT_FALSE(reference.Take(scan({3.0, 3.0, 3.0})));
  EXPECT_EQ(reference.taken(), 3);
}

}  // namespace
}  // namespace minibot3d_slam
