// Tests of the costmap options: costmap_2d names and defaults, text parsing,
// validation that names every offending parameter, warnings, and the
// effective (padded) footprint.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/costmap/costmap_options.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

// The message ValidateCostmapOptions throws, or "" if it accepts.
std::string ValidationError(const CostmapOptions& o) {
  try {
    ValidateCostmapOptions(o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool AnyContains(const std::vector<std::string>& v, const std::string& s) {
  for (const std::string& x : v) {
    if (x.find(s) != std::string::npos) return true;
  }
  return false;
}

TEST(CostmapOptionsTest, DefaultsAreCostmap2dsAndValid) {
  const CostmapOptions o;
  EXPECT_EQ(o.global_frame, "map");
  EXPECT_EQ(o.robot_base_frame, "base_link");
  EXPECT_DOUBLE_EQ(o.update_frequency, 5.0);
  EXPECT_DOUBLE_EQ(o.transform_tolerance, 0.3);
  EXPECT_DOUBLE_EQ(o.resolution, 0.05);
  EXPECT_TRUE(o.static_map);
  EXPECT_FALSE(o.rolling_window);
  EXPECT_FALSE(o.track_unknown_space);
  EXPECT_EQ(o.unknown_cost_value, -1);
  EXPECT_EQ(o.lethal_cost_threshold, 100);
  EXPECT_DOUBLE_EQ(o.robot_radius, 0.46);
  EXPECT_DOUBLE_EQ(o.footprint_padding, 0.01);
  EXPECT_DOUBLE_EQ(o.obstacle_range, 2.5);
  EXPECT_DOUBLE_EQ(o.raytrace_range, 3.0);
  EXPECT_DOUBLE_EQ(o.inflation_radius, 0.55);
  EXPECT_DOUBLE_EQ(o.cost_scaling_factor, 10.0);
  EXPECT_EQ(ValidationError(o), "");
  EXPECT_TRUE(CostmapOptionWarnings(o).empty());
}

TEST(CostmapOptionsTest, SetParsesEveryTypeAndRejectsUnknownNames) {
  CostmapOptions o;
  SetCostmapOption("rolling_window", "true", &o);
  SetCostmapOption("width", "6", &o);
  SetCostmapOption("unknown_cost_value", "255", &o);
  SetCostmapOption("global_frame", " odom ", &o);
  SetCostmapOption("footprint", "[[0.2, 0.15], [-0.2, 0.15], [-0.2, -0.15], [0.2, -0.15]]", &o);
  EXPECT_TRUE(o.rolling_window);
  EXPECT_DOUBLE_EQ(o.width, 6.0);
  EXPECT_EQ(o.unknown_cost_value, 255);
  EXPECT_EQ(o.global_frame, "odom");
  EXPECT_EQ(ValidationError(o), "");

  try {
    SetCostmapOption("inflation_radis", "0.5", &o);
    FAIL() << "misspelled name accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inflation_radis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SetCostmapOption("resolution", "fine", &o), std::invalid_argument);
  EXPECT_THROW(SetCostmapOption("track_unknown_space", "yes please", &o), std::invalid_argument);

  EXPECT_TRUE(IsCostmapOptionName("cost_scaling_factor"));
  EXPECT_TRUE(IsCostmapOptionName("inf_is_valid"));
  EXPECT_FALSE(IsCostmapOptionName("observation_sources"));
  for (const std::string& n : CostmapOptionNames()) EXPECT_TRUE(IsCostmapOptionName(n)) << n;
}

TEST(CostmapOptionsTest, ObservationSourcesAreSpaceSeparatedWithTheCostmapsRanges) {
  CostmapSensorOptions sensors;
  CostmapSensorOptionTable().Set("observation_sources", " laser  rear_laser ", &sensors);
  EXPECT_EQ(ObservationSourceNames(sensors), (std::vector<std::string>{"laser", "rear_laser"}));
  EXPECT_NO_THROW(ValidateCostmapSensorOptions(sensors));
  sensors.observation_sources = "[laser, rear_laser]";  // a YAML list, not costmap_2d's form
  EXPECT_THROW(ValidateCostmapSensorOptions(sensors), std::invalid_argument);

  CostmapOptions costmap;
  costmap.obstacle_range = 4.0;
  costmap.inf_is_valid = true;
  ObservationSourceOptions source = DefaultObservationSource("laser", costmap);
  EXPECT_EQ(source.topic, "laser");
  EXPECT_DOUBLE_EQ(source.obstacle_range, 4.0);
  EXPECT_DOUBLE_EQ(source.raytrace_range, costmap.raytrace_range);
  EXPECT_TRUE(source.inf_is_valid);
  ObservationSourceOptionTable().Set("topic", "scan", &source);
  ObservationSourceOptionTable().Set("marking", "false", &source);
  EXPECT_EQ(source.topic, "scan");
  EXPECT_FALSE(source.marking);
}

TEST(CostmapOptionsTest, ValidationNamesEveryOffendingParameter) {
  CostmapOptions o;
  o.rolling_window = true;
  o.resolution = 0.0;
  o.width = 0.0;
  o.height = -3.0;
  o.raytrace_range = -1.0;
  o.obstacle_range = std::numeric_limits<double>::quiet_NaN();
  o.inflation_radius = -0.1;
  o.cost_scaling_factor = -2.0;
  o.lethal_cost_threshold = 0;
  o.unknown_cost_value = 300;
  o.update_frequency = -1.0;
  const std::string msg = ValidationError(o);
  for (const char* name : {"resolution=0", "width=0", "height=-3", "raytrace_range=-1",
                           "obstacle_range=nan", "inflation_radius=-0.1",
                           "cost_scaling_factor=-2", "lethal_cost_threshold=0",
                           "unknown_cost_value=300", "update_frequency=-1"}) {
    EXPECT_NE(msg.find(name), std::string::npos) << "missing '" << name << "' in: " << msg;
  }
}

TEST(CostmapOptionsTest, WidthOnlyMattersWithoutAMapToSizeFrom) {
  CostmapOptions o;
  o.width = 0.0;  // a fixed costmap with a static map takes the map's size
  EXPECT_EQ(ValidationError(o), "");
  o.static_map = false;
  EXPECT_NE(ValidationError(o).find("width=0"), std::string::npos);
}

TEST(CostmapOptionsTest, FootprintOrRobotRadiusIsRequired) {
  CostmapOptions o;
  o.robot_radius = 0.0;
  const std::string neither = ValidationError(o);
  EXPECT_NE(neither.find("robot_radius=0"), std::string::npos) << neither;
  EXPECT_THROW(EffectiveFootprint(o), std::invalid_argument);

  o.footprint = "[[0.1, 0.1], [0.1]]";
  const std::string bad = ValidationError(o);
  EXPECT_NE(bad.find("footprint"), std::string::npos) << bad;

  o.footprint = "[[0.3, 0.2], [-0.3, 0.2], [-0.3, -0.2], [0.3, -0.2]]";
  EXPECT_EQ(ValidationError(o), "");
}

TEST(CostmapOptionsTest, WarningsForSuspiciousButLegalSettings) {
  CostmapOptions o;
  o.inflation_radius = 0.2;  // robot radius 0.46
  o.obstacle_range = 4.0;    // > raytrace_range 3.0
  o.footprint = "[[0.3, 0.2], [-0.3, 0.2], [-0.3, -0.2], [0.3, -0.2]]";
  o.robot_radius = 0.3;      // set as well as the footprint
  EXPECT_EQ(ValidationError(o), "");
  const std::vector<std::string> w = CostmapOptionWarnings(o);
  EXPECT_EQ(w.size(), 3u);
  EXPECT_TRUE(AnyContains(w, "inflation_radius=0.2"));
  EXPECT_TRUE(AnyContains(w, "raytrace_range=3 < obstacle_range=4"));
  EXPECT_TRUE(AnyContains(w, "robot_radius=0.3"));
}

TEST(CostmapOptionsTest, EffectiveFootprintIsPadded) {
  CostmapOptions o;
  o.robot_radius = 0.2;
  o.footprint_padding = 0.05;
  const Footprint circle = EffectiveFootprint(o);
  ASSERT_EQ(circle.size(), 16u);
  // The vertex on the +x axis is pushed out along x only.
  EXPECT_NEAR(circle[0].x, 0.25, 1e-12);
  EXPECT_NEAR(circle[0].y, 0.0, 1e-12);

  o.footprint = "[[0.3, 0.2], [-0.3, 0.2], [-0.3, -0.2], [0.3, -0.2]]";
  const Footprint box = EffectiveFootprint(o);
  ASSERT_EQ(box.size(), 4u);
  EXPECT_NEAR(box[0].x, 0.35, 1e-12);
  EXPECT_NEAR(box[0].y, 0.25, 1e-12);
  EXPECT_NEAR(box[2].x, -0.35, 1e-12);
  EXPECT_NEAR(box[2].y, -0.25, 1e-12);
}

TEST(CostmapOptionsTest, CellsRoundInsteadOfTruncating) {
  EXPECT_EQ(CostmapCells(6.0, 0.05), 120);
  EXPECT_EQ(CostmapCells(0.29, 0.1), 3);
  EXPECT_EQ(CostmapCells(0.0, 0.05), 1);
}

}  // namespace
}  // namespace nav
}  // namespace minibot3d_navigation
