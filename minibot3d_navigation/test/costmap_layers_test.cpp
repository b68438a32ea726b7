// Tests of the layered costmap: the static layer's value mapping, obstacle
// marking and ray-traced clearing (a moved obstacle, +inf readings, the
// obstacle and raytrace ranges, point clouds' height limits), the rolling window keeping obstacles fixed in
// the world, inflation costs against costmap_2d's formula (one obstacle and a
// brute-force nearest-obstacle reference), incremental updates matching a full
// rebuild, and the clearing services.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/costmap/layered_costmap.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// costmap_2d's InflationLayer::computeCost, written out independently.
int ExpectedInflationCost(double distance_cells, double resolution, double inscribed,
                          double scaling) {
  if (distance_cells == 0) return 254;
  if (distance_cells * resolution <= inscribed) return 253;
  return static_cast<unsigned char>(252 * std::exp(-scaling * (distance_cells * resolution -
                                                               inscribed)));
}

// Cost at a world point; fails the test if it is off the costmap.
int CostAt(const Costmap2D& c, double wx, double wy) {
  int mx, my;
  if (!c.WorldToMap(wx, wy, &mx, &my)) {
    ADD_FAILURE() << "(" << wx << ", " << wy << ") is off the costmap";
    return -1;
  }
  return c.cost(mx, my);
}

// A square robot of half-size 0.1 m with no padding (inscribed radius 0.1).
CostmapOptions SmallRobotOptions() {
  CostmapOptions o;
  o.footprint = "[[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1], [0.1, -0.1]]";
  o.footprint_padding = 0.0;
  return o;
}

// A fixed 10 m x 10 m costmap with no static map.
LayeredCostmap FixedCostmap(CostmapOptions o = SmallRobotOptions()) {
  o.static_map = false;
  o.width = 10.0;
  o.height = 10.0;
  return BuildLayeredCostmap(o);
}

Observation OneHit(Point2 origin, Point2 hit) {
  Observation obs;
  obs.origin = origin;
  obs.hits.push_back(hit);
  return obs;
}

// --- Static layer ---------------------------------------------------------

TEST(StaticLayerTest, InterpretsValuesLikeCostmap2d) {
  CostmapOptions o;
  StaticLayer plain(o);  // track_unknown_space false, trinary, threshold 100
  EXPECT_EQ(plain.InterpretValue(-1), kFreeSpace);
  EXPECT_EQ(plain.InterpretValue(0), kFreeSpace);
  EXPECT_EQ(plain.InterpretValue(99), kFreeSpace);
  EXPECT_EQ(plain.InterpretValue(100), kLethalObstacle);

  o.track_unknown_space = true;
  o.trinary_costmap = false;
  o.lethal_cost_threshold = 65;
  StaticLayer scaled(o);
  EXPECT_EQ(scaled.InterpretValue(-1), kNoInformation);
  EXPECT_EQ(scaled.InterpretValue(65), kLethalObstacle);
  EXPECT_EQ(scaled.InterpretValue(100), kLethalObstacle);
  EXPECT_EQ(scaled.InterpretValue(0), 0);
  EXPECT_EQ(scaled.InterpretValue(32), static_cast<uint8_t>(32.0 / 65 * 254));
  EXPECT_EQ(scaled.InterpretValue(64), static_cast<uint8_t>(64.0 / 65 * 254));

  o.unknown_cost_value = 50;  // a map that uses 50 for unknown
  StaticLayer custom(o);
  EXPECT_EQ(custom.InterpretValue(50), kNoInformation);
  EXPECT_EQ(custom.InterpretValue(-1), kLethalObstacle);  // 255 >= 65, as costmap_2d
}

TEST(StaticLayerTest, FixedCostmapTakesTheMapGeometryAndValues) {
  CostmapOptions o = SmallRobotOptions();
  o.track_unknown_space = true;
  o.inflation_radius = 0.0;  // look at the static values alone
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  OccupancyGrid grid;
  grid.width = 4;
  grid.height = 3;
  grid.resolution = 0.1;
  grid.origin_x = -1.0;
  grid.origin_y = 2.0;
  grid.data = {0, 100, -1, 0,  //
               0, 0, 0, 0,     //
               -1, 0, 100, 0};
  costmap.SetStaticMap(grid);
  const Costmap2D& c = costmap.costmap();
  EXPECT_EQ(c.size_x(), 4);
  EXPECT_EQ(c.size_y(), 3);
  EXPECT_DOUBLE_EQ(c.resolution(), 0.1);
  EXPECT_DOUBLE_EQ(c.origin_x(), -1.0);
  EXPECT_DOUBLE_EQ(c.origin_y(), 2.0);
  costmap.UpdateMap({-10.0, -10.0, 0.0});  // robot off the map: no footprint
  const std::vector<uint8_t> expected = {0, 254, 255, 0, 0, 0, 0, 0, 255, 0, 254, 0};
  EXPECT_EQ(c.cells(), expected);
}

TEST(StaticLayerTest, RejectsMalformedMapsAndKeepsThePreviousOne) {
  StaticLayer layer{CostmapOptions()};
  OccupancyGrid grid;
  grid.width = 2;
  grid.height = 2;
  grid.data = {0, 0, 0};
  EXPECT_THROW(layer.SetMap(grid), std::invalid_argument);
  EXPECT_FALSE(layer.has_map());
  grid.data.push_back(100);
  grid.origin_theta = 0.5;
  EXPECT_THROW(layer.SetMap(grid), std::invalid_argument);
  grid.origin_theta = 0.0;
  layer.SetMap(grid);
  EXPECT_TRUE(layer.has_map());
  grid.resolution = 0.0;
  EXPECT_THROW(layer.SetMap(grid), std::invalid_argument);
  EXPECT_DOUBLE_EQ(layer.map().resolution(), 0.05);
}

TEST(LayeredCostmapTest, SetStaticMapWithoutStaticLayerIsALogicError) {
  LayeredCostmap costmap = FixedCostmap();
  EXPECT_EQ(costmap.static_layer(), nullptr);
  EXPECT_THROW(costmap.SetStaticMap(OccupancyGrid()), std::logic_error);
}

// --- Obstacle layer ---------------------------------------------------------

TEST(ObstacleLayerTest, MarksHitsAndClearsThemWhenTheObstacleMoves) {
  LayeredCostmap costmap = FixedCostmap();
  const Pose2 robot{5.0, 5.0, 0.0};
  costmap.obstacle_layer()->AddObservation(OneHit({5.0, 5.0}, {6.02, 5.02}));
  costmap.UpdateMap(robot);
  EXPECT_EQ(CostAt(costmap.costmap(), 6.02, 5.02), kLethalObstacle);
  // Inflated around it, free along the ray near the robot.
  EXPECT_EQ(CostAt(costmap.costmap(), 5.97, 5.02), kInscribedInflatedObstacle);
  EXPECT_EQ(CostAt(costmap.costmap(), 5.3, 5.02), kFreeSpace);

  // The obstacle moved 1 m further: the new ray passes through the old cell.
  costmap.obstacle_layer()->AddObservation(OneHit({5.0, 5.0}, {7.02, 5.02}));
  costmap.UpdateMap(robot);
  EXPECT_EQ(CostAt(costmap.obstacle_layer()->grid(), 6.02, 5.02), kFreeSpace);
  EXPECT_EQ(CostAt(costmap.costmap(), 7.02, 5.02), kLethalObstacle);
  // No inflation left over from the old position.
  EXPECT_EQ(CostAt(costmap.costmap(), 6.02, 5.02), kFreeSpace);
  EXPECT_EQ(CostAt(costmap.costmap(), 5.97, 5.02), kFreeSpace);
  EXPECT_EQ(costmap.obstacle_layer()->pending_observations(), 0u);
}

TEST(ObstacleLayerTest, ClearingStopsBeforeTheHitCell) {
  LayeredCostmap costmap = FixedCostmap();
  ObstacleLayer* layer = costmap.obstacle_layer();
  const Pose2 robot{5.0, 5.0, 0.0};
  layer->AddObservation(OneHit({5.0, 5.0}, {6.52, 5.02}));
  costmap.UpdateMap(robot);
  // A second, shorter reading ending in the same cell must not clear it.
  Observation obs;
  obs.origin = {5.0, 5.0};
  obs.hits.push_back({6.51, 5.03});
  obs.obstacle_range = 0.5;  // too far to mark again
  layer->AddObservation(obs);
  costmap.UpdateMap(robot);
  EXPECT_EQ(CostAt(layer->grid(), 6.52, 5.02), kLethalObstacle);
}

TEST(ObstacleLayerTest, InfReadingsClearOnlyWithInfIsValid) {
  for (bool inf_is_valid : {false, true}) {
    SCOPED_TRACE(inf_is_valid ? "inf_is_valid" : "inf dropped");
    LayeredCostmap costmap = FixedCostmap();
    ObstacleLayer* layer = costmap.obstacle_layer();
    const Pose2 robot{5.0, 5.0, 0.0};
    layer->AddObservation(OneHit({5.0, 5.0}, {6.52, 5.02}));
    costmap.UpdateMap(robot);
    ASSERT_EQ(CostAt(costmap.costmap(), 6.52, 5.02), kLethalObstacle);

    LaserScan scan;
    scan.range_min = 0.1;
    scan.range_max = 4.0;
    scan.angles = {0.0, 0.5, 1.0};
    scan.ranges = {std::numeric_limits<float>::infinity(), std::nanf(""), 5.0f};
    const Observation obs = ObservationFromScan(scan, {5.0, 5.02, 0.0}, 2.5, 3.0, inf_is_valid);
    EXPECT_TRUE(obs.hits.empty());  // NaN and beyond range_max are dropped
    ASSERT_EQ(obs.clear_endpoints.size(), inf_is_valid ? 1u : 0u);
    layer->AddObservation(obs);
    costmap.UpdateMap(robot);
    EXPECT_EQ(CostAt(costmap.costmap(), 6.52, 5.02), inf_is_valid ? kFreeSpace : kLethalObstacle);
    // The clear ray stops at raytrace_range = 3 m even though range_max is 4 m.
    if (inf_is_valid) {
      Observation far;  // 3.52 m away: marked with a longer obstacle_range
      far.origin = {5.0, 5.0};
      far.obstacle_range = 5.0;
      far.hits.push_back({8.52, 5.02});
      layer->AddObservation(far);
      costmap.UpdateMap(robot);
      ASSERT_EQ(CostAt(layer->grid(), 8.52, 5.02), kLethalObstacle);
      layer->AddObservation(obs);
      costmap.UpdateMap(robot);
      EXPECT_EQ(CostAt(layer->grid(), 8.52, 5.02), kLethalObstacle);
    }
  }
}

TEST(ObstacleLayerTest, ObstacleRangeLimitsMarkingButNotClearing) {
  LayeredCostmap costmap = FixedCostmap();
  ObstacleLayer* layer = costmap.obstacle_layer();
  Observation obs;
  obs.origin = {5.0, 5.0};
  obs.obstacle_range = 2.5;
  obs.hits = {{5.0 + 2.42, 5.02}, {5.02, 5.0 + 2.6}};
  layer->AddObservation(obs);
  costmap.UpdateMap({5.0, 5.0, 0.0});
  EXPECT_EQ(CostAt(layer->grid(), 7.42, 5.02), kLethalObstacle);
  EXPECT_EQ(CostAt(layer->grid(), 5.02, 7.6), kFreeSpace);
}

TEST(ObstacleLayerTest, ZeroRangesMakeMarkingOnlyAndClearingOnlySources) {
  LayeredCostmap costmap = FixedCostmap();
  ObstacleLayer* layer = costmap.obstacle_layer();
  layer->AddObservation(OneHit({5.0, 5.0}, {6.02, 5.02}));
  costmap.UpdateMap({5.0, 5.0, 0.0});
  Observation marking_only = OneHit({5.0, 5.0}, {7.02, 5.02});
  marking_only.raytrace_range = 0.0;
  layer->AddObservation(marking_only);
  costmap.UpdateMap({5.0, 5.0, 0.0});
  EXPECT_EQ(CostAt(layer->grid(), 6.02, 5.02), kLethalObstacle);  // not cleared
  EXPECT_EQ(CostAt(layer->grid(), 7.02, 5.02), kLethalObstacle);
  Observation clearing_only = OneHit({5.0, 5.0}, {8.02, 5.02});
  clearing_only.obstacle_range = 0.0;
  layer->AddObservation(clearing_only);
  costmap.UpdateMap({5.0, 5.0, 0.0});
  EXPECT_EQ(CostAt(layer->grid(), 6.02, 5.02), kFreeSpace);
  EXPECT_EQ(CostAt(layer->grid(), 7.02, 5.02), kFreeSpace);
  EXPECT_EQ(CostAt(layer->grid(), 8.02, 5.02), kFreeSpace);  // not marked
}

TEST(ObstacleLayerTest, PointCloudsMarkOnlyPointsBetweenTheHeightLimits) {
  // A depth camera at (5, 5) sees the floor (z = 0.01), a table top (z = 0.75), a box on the
  // floor (z = 0.2), a ceiling lamp (z = 2.5) and an invalid pixel.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> xyz = {6.02, 5.02, 0.01,  5.02, 6.02, 0.75, 7.02, 5.02, 0.2,
                                   5.02, 7.02, 2.5,   nan,  6.0,  0.3};
  const Observation obs = ObservationFromPoints(xyz, {5.0, 5.0}, 0.05, 2.0, 2.5, 3.0);
  ASSERT_EQ(obs.hits.size(), 2u);
  EXPECT_DOUBLE_EQ(obs.hits[0].y, 6.02);
  EXPECT_DOUBLE_EQ(obs.hits[1].x, 7.02);

  LayeredCostmap costmap = FixedCostmap();
  ObstacleLayer* layer = costmap.obstacle_layer();
  layer->AddObservation(OneHit({5.0, 5.0}, {6.02, 5.02}));
  costmap.UpdateMap({5.0, 5.0, 0.0});
  ASSERT_EQ(CostAt(layer->grid(), 6.02, 5.02), kLethalObstacle);
  layer->AddObservation(obs);
  costmap.UpdateMap({5.0, 5.0, 0.0});
  EXPECT_EQ(CostAt(layer->grid(), 5.02, 6.02), kLethalObstacle);
  EXPECT_EQ(CostAt(layer->grid(), 7.02, 5.02), kLethalObstacle);
  EXPECT_EQ(CostAt(layer->grid(), 5.02, 7.02), kFreeSpace);
  // The ray to the box clears the obstacle marked before on its way.
  EXPECT_EQ(CostAt(layer->grid(), 6.02, 5.02), kFreeSpace);

  EXPECT_THROW(ObservationFromPoints(xyz, {nan, 5.0}, 0.0, 2.0, 2.5, 3.0),
               std::invalid_argument);
  EXPECT_THROW(ObservationFromPoints(xyz, {5.0, 5.0}, 1.0, 0.5, 2.5, 3.0),
               std::invalid_argument);
}

TEST(ObstacleLayerTest, TrackUnknownSpaceStartsUnknownAndRaysRevealFreeSpace) {
  CostmapOptions o = SmallRobotOptions();
  o.track_unknown_space = true;
  LayeredCostmap costmap = FixedCostmap(o);
  EXPECT_EQ(costmap.costmap().cost(0, 0), kNoInformation);
  costmap.obstacle_layer()->AddObservation(OneHit({5.0, 5.0}, {5.02, 7.02}));
  costmap.UpdateMap({5.0, 5.0, 0.0});
  const Costmap2D& c = costmap.costmap();
  EXPECT_EQ(CostAt(c, 5.02, 7.02), kLethalObstacle);
  // Revealed free by the ray, then inflated.
  EXPECT_EQ(CostAt(c, 5.02, 6.98), kInscribedInflatedObstacle);
  EXPECT_EQ(CostAt(c, 5.02, 6.0), kFreeSpace);
  // Beside the obstacle nothing was seen: inflation below 253 keeps unknown.
  EXPECT_EQ(CostAt(c, 5.32, 7.02), kNoInformation);
  // ...but within the inscribed radius it becomes 253.
  EXPECT_EQ(CostAt(c, 5.12, 7.02), kInscribedInflatedObstacle);
  EXPECT_EQ(CostAt(c, 8.0, 8.0), kNoInformation);
}

TEST(ObstacleLayerTest, TheRobotsFootprintIsNeverAnObstacle) {
  LayeredCostmap costmap = FixedCostmap();
  // A reflection off the robot's own body.
  costmap.obstacle_layer()->AddObservation(OneHit({4.0, 5.0}, {5.05, 5.02}));
  costmap.UpdateMap({5.0, 5.0, 0.3});
  EXPECT_EQ(CostAt(costmap.obstacle_layer()->grid(), 5.05, 5.02), kFreeSpace);
  EXPECT_NE(CostAt(costmap.costmap(), 5.05, 5.02), kLethalObstacle);
}

TEST(ObstacleLayerTest, RejectsBadObservations) {
  ObstacleLayer layer(false);
  Observation obs;
  obs.origin = {std::nan(""), 0.0};
  EXPECT_THROW(layer.AddObservation(obs), std::invalid_argument);
  obs.origin = {0.0, 0.0};
  obs.raytrace_range = -1.0;
  EXPECT_THROW(layer.AddObservation(obs), std::invalid_argument);
  obs.raytrace_range = 3.0;
  obs.hits = {{1.0, 1.0}, {kInf, 0.0}};
  layer.AddObservation(obs);
  EXPECT_EQ(layer.pending_observations(), 1u);
  EXPECT_EQ(layer.skipped_points(), 1u);
}

// --- Rolling window ---------------------------------------------------------

TEST(RollingWindowTest, ObstaclesStayFixedInTheWorldWhileTheRobotMoves) {
  CostmapOptions o = SmallRobotOptions();
  o.rolling_window = true;
  o.static_map = false;
  o.width = 6.0;
  o.height = 6.0;
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  const Point2 obstacle{1.52, 0.47};
  costmap.obstacle_layer()->AddObservation(OneHit({0.0, 0.0}, obstacle));
  costmap.UpdateMap({0.0, 0.0, 0.0});
  const Costmap2D& c = costmap.costmap();
  EXPECT_NEAR(c.origin_x(), -3.0, 1e-9);
  EXPECT_EQ(CostAt(c, obstacle.x, obstacle.y), kLethalObstacle);

  // Drive without new observations; the obstacle stays where it is.
  for (const Pose2& robot : {Pose2{0.83, -0.31, 0.2}, Pose2{-1.27, 0.58, 1.0},
                              Pose2{-1.4, 2.1, 2.0}}) {
    costmap.UpdateMap(robot);
    EXPECT_NEAR(c.origin_x() + c.size_x_m() / 2, robot.x, c.resolution());
    EXPECT_NEAR(c.origin_y() + c.size_y_m() / 2, robot.y, c.resolution());
    EXPECT_EQ(CostAt(c, obstacle.x, obstacle.y), kLethalObstacle) << robot.x << ", " << robot.y;
    EXPECT_EQ(CostAt(c, obstacle.x - 0.05, obstacle.y), kInscribedInflatedObstacle);
    // Exactly one lethal cell in the window.
    int lethal = 0;
    for (uint8_t v : c.cells()) lethal += v == kLethalObstacle;
    EXPECT_EQ(lethal, 1);
  }
  // Leave the window far behind and come back: it was forgotten.
  costmap.UpdateMap({20.0, 0.0, 0.0});
  costmap.UpdateMap({0.0, 0.0, 0.0});
  EXPECT_EQ(CostAt(c, obstacle.x, obstacle.y), kFreeSpace);
}

// One hit seen from (5, 5) at `stamp`. In the decay tests someone is seen at t = 0, then walks off
// behind another who stands between them and the sensor: the rays towards the other never reach
// the first one's cell, so only a decay forgets it.
Observation SeenAt(double stamp, Point2 hit) {
  Observation obs = OneHit({5.0, 5.0}, hit);
  obs.stamp = stamp;
  return obs;
}

TEST(ObstacleLayerTest, ADecayForgetsWhatNoObservationMarksAgain) {
  CostmapOptions o = SmallRobotOptions();
  o.obstacle_decay_time = 2.0;
  LayeredCostmap costmap = FixedCostmap(o);
  const Pose2 robot{5.0, 5.0, 0.0};
  const Point2 person{7.02, 5.02}, other{6.02, 5.02};  // the other in front of the person
  costmap.obstacle_layer()->AddObservation(SeenAt(0.0, person));
  costmap.UpdateMap(robot);
  for (double t = 0.5; t <= 4.0; t += 0.5) {
    costmap.obstacle_layer()->AddObservation(SeenAt(t, other));
    costmap.UpdateMap(robot);
    // Marked at 0, never again: lethal before 2 s, forgotten from 2 s on; the one in front,
    // marked every time, stays.
    EXPECT_EQ(CostAt(costmap.costmap(), person.x, person.y) == kLethalObstacle, t < 2.0) << t;
    EXPECT_EQ(CostAt(costmap.costmap(), other.x, other.y), kLethalObstacle) << t;
  }
  // And its inflation went with it.
  EXPECT_EQ(CostAt(costmap.costmap(), person.x + 0.05, person.y), kFreeSpace);
}

TEST(ObstacleLayerTest, WithoutADecayTheMarkStaysAsInCostmap2d) {
  LayeredCostmap costmap = FixedCostmap();
  const Pose2 robot{5.0, 5.0, 0.0};
  costmap.obstacle_layer()->AddObservation(SeenAt(0.0, {7.02, 5.02}));
  costmap.UpdateMap(robot);
  for (double t = 0.5; t <= 60.0; t += 0.5) {
    costmap.obstacle_layer()->AddObservation(SeenAt(t, {6.02, 5.02}));
    costmap.UpdateMap(robot);
  }
  EXPECT_EQ(CostAt(costmap.costmap(), 7.02, 5.02), kLethalObstacle);
}

TEST(ObstacleLayerTest, ADecayedCellIsUnknownAgainWhenUnknownSpaceIsTracked) {
  CostmapOptions o = SmallRobotOptions();
  o.obstacle_decay_time = 1.0;
  o.track_unknown_space = true;
  LayeredCostmap costmap = FixedCostmap(o);
  const Pose2 robot{5.0, 5.0, 0.0};
  costmap.obstacle_layer()->AddObservation(SeenAt(0.0, {7.02, 5.02}));
  costmap.UpdateMap(robot);
  EXPECT_EQ(CostAt(costmap.obstacle_layer()->grid(), 7.02, 5.02), kLethalObstacle);
  costmap.obstacle_layer()->AddObservation(SeenAt(1.0, {6.02, 5.02}));
  costmap.UpdateMap(robot);
  EXPECT_EQ(CostAt(costmap.obstacle_layer()->grid(), 7.02, 5.02), kNoInformation);
}

TEST(ObstacleLayerTest, NothingDecaysWhileNoSensorReports) {
  CostmapOptions o = SmallRobotOptions();
  o.obstacle_decay_time = 1.0;
  LayeredCostmap costmap = FixedCostmap(o);
  costmap.obstacle_layer()->AddObservation(SeenAt(3.0, {7.02, 5.02}));
  for (int i = 0; i < 100; ++i) costmap.UpdateMap({5.0, 5.0, 0.0});
  EXPECT_EQ(CostAt(costmap.costmap(), 7.02, 5.02), kLethalObstacle);
}

TEST(ObstacleLayerTest, RejectsABadDecayTimeNamingIt) {
  CostmapOptions o = SmallRobotOptions();
  o.obstacle_decay_time = -1.0;
  try {
    ValidateCostmapOptions(o);
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("obstacle_decay_time=-1 must be >= 0"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(ObstacleLayer(false, std::nan("")), std::invalid_argument);
}

TEST(RollingWindowTest, AMarkDecaysWhereItWasInTheWorldWhileTheWindowMoves) {
  CostmapOptions o = SmallRobotOptions();
  o.rolling_window = true;
  o.static_map = false;
  o.width = 6.0;
  o.height = 6.0;
  o.obstacle_decay_time = 2.0;
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  const Point2 gone{1.52, 0.47}, kept{-1.48, -0.53};
  Observation first = OneHit({0.0, 0.0}, gone);
  first.hits.push_back(kept);
  costmap.obstacle_layer()->AddObservation(first);
  costmap.UpdateMap({0.0, 0.0, 0.0});
  const Costmap2D& c = costmap.costmap();
  // The window moves by whole cells as the robot drives; `kept` is seen again each time.
  double t = 0.0;
  for (const Pose2& robot : {Pose2{0.37, -0.21, 0.0}, Pose2{-0.52, 0.33, 0.0},
                              Pose2{0.11, 0.64, 0.0}, Pose2{-0.23, -0.4, 0.0}}) {
    t += 0.75;
    Observation again = OneHit({robot.x, robot.y}, kept);
    again.stamp = t;
    costmap.obstacle_layer()->AddObservation(again);
    costmap.UpdateMap(robot);
    EXPECT_EQ(CostAt(c, gone.x, gone.y) == kLethalObstacle, t < 2.0) << t;
    EXPECT_EQ(CostAt(c, kept.x, kept.y), kLethalObstacle) << t;
    int lethal = 0;
    for (uint8_t v : c.cells()) lethal += v == kLethalObstacle;
    EXPECT_EQ(lethal, t < 2.0 ? 2 : 1) << t;
  }
}

TEST(RollingWindowTest, StaticLayerIsCopiedIntoTheWindow) {
  CostmapOptions o = SmallRobotOptions();
  o.rolling_window = true;
  o.width = 2.0;
  o.height = 2.0;
  o.inflation_radius = 0.0;
  o.track_unknown_space = true;
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  OccupancyGrid grid;  // 3 m x 3 m at 0.1 m, lethal cell at (1.55, 1.25)
  grid.width = 30;
  grid.height = 30;
  grid.resolution = 0.1;
  grid.data.assign(900, 0);
  grid.data[12 * 30 + 15] = 100;
  costmap.SetStaticMap(grid);
  EXPECT_EQ(costmap.costmap().size_x(), 40);  // a rolling window keeps its size
  costmap.UpdateMap({2.3, 1.0, 0.0});
  const Costmap2D& c = costmap.costmap();
  EXPECT_EQ(CostAt(c, 1.55, 1.25), kLethalObstacle);
  EXPECT_EQ(CostAt(c, 1.52, 1.22), kLethalObstacle);  // 4 window cells per map cell
  EXPECT_EQ(CostAt(c, 1.67, 1.25), kFreeSpace);
  EXPECT_EQ(CostAt(c, 2.0, 1.25), kFreeSpace);
  EXPECT_EQ(CostAt(c, 3.2, 1.25), kNoInformation);  // off the map
  // Map cells that enter the moving window are filled in from the map.
  costmap.UpdateMap({1.3, 1.0, 0.0});
  EXPECT_EQ(CostAt(c, 0.35, 1.25), kFreeSpace);
  EXPECT_EQ(CostAt(c, 1.55, 1.25), kLethalObstacle);
  costmap.UpdateMap({0.9, 2.5, 0.0});
  EXPECT_EQ(CostAt(c, 0.35, 2.8), kFreeSpace);
  EXPECT_EQ(CostAt(c, 0.35, 3.2), kNoInformation);
  EXPECT_EQ(CostAt(c, 1.55, 1.55), kFreeSpace);
}

// --- Inflation --------------------------------------------------------------

TEST(InflationLayerTest, CostsMatchCostmap2dsFormulaAroundOneObstacle) {
  for (double inscribed_half : {0.1, 0.23}) {
    CostmapOptions o = SmallRobotOptions();
    const double h = inscribed_half;
    o.footprint = "[[" + std::to_string(h) + "," + std::to_string(h) + "],[" +
                  std::to_string(-h) + "," + std::to_string(h) + "],[" + std::to_string(-h) +
                  "," + std::to_string(-h) + "],[" + std::to_string(h) + "," +
                  std::to_string(-h) + "]]";
    o.inflation_radius = 0.55;
    o.cost_scaling_factor = 3.0;
    LayeredCostmap costmap = FixedCostmap(o);
    ASSERT_NEAR(costmap.inscribed_radius(), h, 1e-9);
    costmap.obstacle_layer()->AddObservation(OneHit({3.02, 5.02}, {5.02, 5.02}));
    costmap.UpdateMap({1.0, 1.0, 0.0});
    const Costmap2D& c = costmap.costmap();
    int ox, oy;
    ASSERT_TRUE(c.WorldToMap(5.02, 5.02, &ox, &oy));
    ASSERT_EQ(c.cost(ox, oy), kLethalObstacle);
    const int r = static_cast<int>(std::ceil(0.55 / 0.05));
    int checked_decay = 0;
    for (int dy = -15; dy <= 15; ++dy) {
      for (int dx = -15; dx <= 15; ++dx) {
        const double d = std::hypot(dx, dy);
        const int expected =
            d <= r ? ExpectedInflationCost(d, 0.05, costmap.inscribed_radius(), 3.0) : 0;
        ASSERT_EQ(c.cost(ox + dx, oy + dy), expected) << "offset (" << dx << ", " << dy
                                                      << "), distance " << d << " cells";
        checked_decay += expected > 0 && expected < 253;
      }
    }
    EXPECT_GT(checked_decay, 100);
    // A few hand-checked values for h = 0.1: 2 cells = 0.1 m -> 253; 3 cells
    // = 0.15 m -> (uint8)(252 * e^-0.15) = 216; 10 cells -> 252 * e^-1.2 = 75.
    if (h == 0.1) {
      EXPECT_EQ(c.cost(ox + 2, oy), 253);
      EXPECT_EQ(c.cost(ox, oy - 3), 216);
      EXPECT_EQ(c.cost(ox - 10, oy), 75);
      EXPECT_EQ(c.cost(ox + 6, oy + 8), 75);
      EXPECT_EQ(c.cost(ox + 12, oy), 0);
    }
  }
}

TEST(InflationLayerTest, EqualsTheCostOfTheNearestObstacleEverywhere) {
  // Random blobs and walls; compare with brute force over every lethal cell.
  const int n = 90;
  Costmap2D master(n, n, 0.05, 0.0, 0.0);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cell(0, n - 1), len(1, 25);
  for (int k = 0; k < 40; ++k) {
    const int x = cell(rng), y = cell(rng), l = len(rng);
    const bool horizontal = k % 2 == 0;
    for (int t = 0; t < l; ++t) {
      const int xx = horizontal ? x + t : x, yy = horizontal ? y : y + t;
      if (master.InBounds(xx, yy)) master.set_cost(xx, yy, kLethalObstacle);
    }
  }
  // Solid furniture: blocks of lethal cells that share their ends row to row.
  for (int k = 0; k < 6; ++k) {
    const int x = cell(rng), y = cell(rng), w = len(rng) / 2, h = len(rng);
    for (int yy = y; yy < std::min(n, y + h); ++yy) {
      for (int xx = x; xx < std::min(n, x + w); ++xx) master.set_cost(xx, yy, kLethalObstacle);
    }
  }
  for (int k = 0; k < 300; ++k) master.set_cost(cell(rng), cell(rng), kNoInformation);
  const Costmap2D before = master;

  InflationLayer layer(0.4, 5.0);
  layer.MatchSize(master);
  layer.OnFootprintChanged(MakeCircleFootprint(0.12), 0.12, 0.12);
  layer.UpdateCosts(CellBounds::Whole(master), &master);

  const int r = layer.cell_inflation_radius();
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      double best = kInf;
      for (int j = std::max(0, y - r); j <= std::min(n - 1, y + r); ++j) {
        for (int i = std::max(0, x - r); i <= std::min(n - 1, x + r); ++i) {
          if (before.cost(i, j) == kLethalObstacle) best = std::min(best, std::hypot(i - x, j - y));
        }
      }
      const int inflated = best <= r ? ExpectedInflationCost(best, 0.05, 0.12, 5.0) : 0;
      const int old = before.cost(x, y);
      const int expected =
          old == kNoInformation ? (inflated >= 253 ? inflated : 255) : std::max(old, inflated);
      ASSERT_EQ(master.cost(x, y), expected) << "cell (" << x << ", " << y << ")";
    }
  }
}

TEST(InflationLayerTest, ZeroRadiusInflatesNothing) {
  Costmap2D master(20, 20, 0.05, 0.0, 0.0);
  master.set_cost(10, 10, kLethalObstacle);
  InflationLayer layer(0.0, 10.0);
  layer.MatchSize(master);
  layer.OnFootprintChanged(MakeCircleFootprint(0.3), 0.3, 0.3);
  layer.UpdateCosts(CellBounds::Whole(master), &master);
  EXPECT_EQ(master.cost(11, 10), kFreeSpace);
  EXPECT_THROW(InflationLayer(-1.0, 10.0), std::invalid_argument);
}

// --- Update cycle and services ----------------------------------------------

TEST(LayeredCostmapTest, IncrementalUpdatesEqualAFullRebuild) {
  for (bool rolling : {false, true}) {
    SCOPED_TRACE(rolling ? "rolling window" : "fixed costmap");
    CostmapOptions o = SmallRobotOptions();
    o.rolling_window = rolling;
    o.width = 4.0;
    o.height = 3.0;
    LayeredCostmap costmap = BuildLayeredCostmap(o);
    OccupancyGrid grid;  // 8 m x 6 m room with walls and a pillar
    grid.width = 160;
    grid.height = 120;
    grid.resolution = 0.05;
    grid.data.assign(160 * 120, 0);
    for (int i = 0; i < 160; ++i) grid.data[i] = grid.data[119 * 160 + i] = 100;
    for (int j = 0; j < 120; ++j) grid.data[j * 160] = grid.data[j * 160 + 159] = 100;
    for (int j = 50; j < 56; ++j) for (int i = 80; i < 86; ++i) grid.data[j * 160 + i] = 100;
    costmap.SetStaticMap(grid);
    // Objects on a ring around the robot whose radius changes every step by a
    // few cells, so obstacles are cleared and re-marked on every side.
    const double radii[] = {1.0, 1.1, 0.95, 1.3, 1.25, 0.9, 1.02, 1.4};
    Pose2 robot{2.0, 2.0, 0.0};
    for (int step = 0; step < 24; ++step) {
      robot = {robot.x + 0.13, robot.y + 0.05, robot.yaw + 0.1};
      Observation obs;
      obs.origin = {robot.x, robot.y};
      for (int k = 0; k < 90; ++k) {
        const double a = 2 * kPi * k / 90, rho = radii[(step + k / 30) % 8];
        obs.hits.push_back({robot.x + rho * std::cos(a), robot.y + rho * std::sin(a)});
      }
      costmap.obstacle_layer()->AddObservation(obs);
      costmap.UpdateMap(robot);
      const std::vector<uint8_t> incremental = costmap.costmap().cells();
      // A footprint change re-inflates everything; the layers' data is the same.
      costmap.SetFootprint(costmap.footprint());
      costmap.UpdateMap(robot);
      ASSERT_EQ(costmap.last_updated_cells().max_i - costmap.last_updated_cells().min_i,
                costmap.costmap().size_x());
      ASSERT_EQ(costmap.costmap().cells(), incremental) << "step " << step;
    }
  }
}

TEST(LayeredCostmapTest, ResetLayersForgetsObstaclesAndRestoresTheMap) {
  CostmapOptions o = SmallRobotOptions();
  LayeredCostmap costmap = BuildLayeredCostmap(o);
  OccupancyGrid grid;
  grid.width = 100;
  grid.height = 100;
  grid.data.assign(100 * 100, 0);
  grid.data[50 * 100 + 20] = 100;
  costmap.SetStaticMap(grid);
  costmap.obstacle_layer()->AddObservation(OneHit({2.5, 2.5}, {3.52, 2.52}));
  costmap.UpdateMap({2.5, 2.5, 0.0});
  ASSERT_EQ(CostAt(costmap.costmap(), 3.52, 2.52), kLethalObstacle);
  ASSERT_EQ(CostAt(costmap.costmap(), 1.02, 2.52), kLethalObstacle);
  costmap.ResetLayers();
  costmap.UpdateMap({2.5, 2.5, 0.0});
  EXPECT_EQ(CostAt(costmap.costmap(), 3.52, 2.52), kFreeSpace);
  EXPECT_EQ(CostAt(costmap.costmap(), 1.02, 2.52), kLethalObstacle);
  EXPECT_EQ(CostAt(costmap.costmap(), 1.07, 2.52), kInscribedInflatedObstacle);
}

TEST(LayeredCostmapTest, ClearExceptAroundKeepsOnlyTheSquareAroundTheRobot) {
  LayeredCostmap costmap = FixedCostmap();
  ObstacleLayer* layer = costmap.obstacle_layer();
  Observation obs;
  obs.origin = {5.0, 5.0};
  obs.hits = {{5.62, 5.02}, {6.82, 5.02}, {5.02, 3.12}};
  layer->AddObservation(obs);
  const Pose2 robot{5.0, 5.0, 0.0};
  costmap.UpdateMap(robot);
  ASSERT_EQ(CostAt(costmap.costmap(), 6.82, 5.02), kLethalObstacle);
  costmap.ClearExceptAround(robot, 3.0);  // keeps |dx|, |dy| < 1.5 m
  EXPECT_EQ(CostAt(costmap.costmap(), 5.62, 5.02), kLethalObstacle);
  EXPECT_EQ(CostAt(costmap.costmap(), 6.82, 5.02), kFreeSpace);
  EXPECT_EQ(CostAt(costmap.costmap(), 5.02, 3.12), kFreeSpace);
  EXPECT_EQ(CostAt(layer->grid(), 6.82, 5.02), kNoInformation);
  EXPECT_THROW(costmap.ClearExceptAround(robot, -1.0), std::invalid_argument);
}

TEST(LayeredCostmapTest, BuildOrdersLayersAndRejectsBadOptions) {
  CostmapOptions o;
  LayeredCostmap with_map = BuildLayeredCostmap(o);
  ASSERT_EQ(with_map.num_layers(), 3u);
  EXPECT_EQ(with_map.layer(0)->name(), "static_layer");
  EXPECT_EQ(with_map.layer(1)->name(), "obstacle_layer");
  EXPECT_EQ(with_map.layer(2)->name(), "inflation_layer");
  // Default robot: circle of 0.46 m padded by 0.01 m.
  EXPECT_NEAR(with_map.circumscribed_radius(), 0.47, 0.01);
  EXPECT_NEAR(with_map.inscribed_radius(), 0.47 * std::cos(kPi / 16), 0.01);
  o.static_map = false;
  EXPECT_EQ(BuildLayeredCostmap(o).num_layers(), 2u);
  o.resolution = -1.0;
  EXPECT_THROW(BuildLayeredCostmap(o), std::invalid_argument);
  EXPECT_THROW(with_map.UpdateMap({std::nan(""), 0.0, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
