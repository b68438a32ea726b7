// DwaOptions: ROS names and defaults, aliases, ignored names, validation
// messages that name every bad value.
#include "minibot3d_navigation/dwa/dwa_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

std::string ValidationMessage(const DwaOptions& o) {
  try {
    ValidateDwaOptions(o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DwaOptionsTest, DefaultsAreTrajectoryPlannerRosOnesAndValid) {
  const DwaOptions o;
  EXPECT_DOUBLE_EQ(o.acc_lim_x, 2.5);
  EXPECT_DOUBLE_EQ(o.acc_lim_theta, 3.2);
  EXPECT_DOUBLE_EQ(o.max_vel_x, 0.5);
  EXPECT_DOUBLE_EQ(o.min_vel_x, 0.1);
  EXPECT_DOUBLE_EQ(o.max_vel_theta, 1.0);
  EXPECT_DOUBLE_EQ(o.min_vel_theta, -1.0);
  EXPECT_DOUBLE_EQ(o.min_in_place_vel_theta, 0.4);
  EXPECT_DOUBLE_EQ(o.escape_vel, -0.1);
  EXPECT_DOUBLE_EQ(o.sim_time, 1.0);
  EXPECT_DOUBLE_EQ(o.sim_granularity, 0.025);
  EXPECT_DOUBLE_EQ(EffectiveAngularSimGranularity(o), 0.025);
  EXPECT_EQ(o.vx_samples, 3);
  EXPECT_EQ(o.vtheta_samples, 20);
  EXPECT_DOUBLE_EQ(o.path_distance_bias, 0.6);
  EXPECT_DOUBLE_EQ(o.goal_distance_bias, 0.8);
  EXPECT_DOUBLE_EQ(o.occdist_scale, 0.01);
  EXPECT_DOUBLE_EQ(o.heading_lookahead, 0.325);
  EXPECT_DOUBLE_EQ(o.xy_goal_tolerance, 0.10);
  EXPECT_DOUBLE_EQ(o.yaw_goal_tolerance, 0.05);
  EXPECT_TRUE(o.dwa);
  EXPECT_TRUE(o.prune_plan);
  EXPECT_FALSE(o.meter_scoring);
  EXPECT_FALSE(o.holonomic_robot);
  EXPECT_DOUBLE_EQ(o.controller_frequency, 20.0);
  EXPECT_NO_THROW(ValidateDwaOptions(o));
}

TEST(DwaOptionsTest, SetsByRosNameAndAlias) {
  DwaOptions o;
  SetDwaOption("max_vel_x", "1.0", &o);
  SetDwaOption("vx_samples", " 20 ", &o);
  SetDwaOption("vth_samples", "40", &o);  // DWAPlannerROS
  SetDwaOption("acc_lim_th", "2.0", &o);
  SetDwaOption("min_rot_vel", "0.3", &o);
  SetDwaOption("backup_vel", "-0.2", &o);
  SetDwaOption("meter_scoring", "true", &o);
  SetDwaOption("use_dwa", "false", &o);
  SetDwaOption("angular_sim_granularity", "0.05", &o);
  EXPECT_DOUBLE_EQ(o.max_vel_x, 1.0);
  EXPECT_EQ(o.vx_samples, 20);
  EXPECT_EQ(o.vtheta_samples, 40);
  EXPECT_DOUBLE_EQ(o.acc_lim_theta, 2.0);
  EXPECT_DOUBLE_EQ(o.min_in_place_vel_theta, 0.3);
  EXPECT_DOUBLE_EQ(o.escape_vel, -0.2);
  EXPECT_TRUE(o.meter_scoring);
  EXPECT_FALSE(o.dwa);
  EXPECT_DOUBLE_EQ(EffectiveAngularSimGranularity(o), 0.05);
  // DWAPlannerROS's symmetric rotation limit.
  SetDwaOption("max_rot_vel", "1.5", &o);
  EXPECT_DOUBLE_EQ(o.max_vel_theta, 1.5);
  EXPECT_DOUBLE_EQ(o.min_vel_theta, -1.5);
  EXPECT_NO_THROW(ValidateDwaOptions(o));
}

TEST(DwaOptionsTest, AliasTableSetsTheSameFieldsAsSetDwaOption) {
  DwaOptions by_table, by_name;
  for (const std::string& name : DwaAliasOptionTable().Names()) {
    const std::string text = name == "use_dwa" ? "false" : name == "vth_samples" ? "7" : "0.7";
    DwaAliasOptionTable().Set(name, text, &by_table);
    if (IsSymmetricRotationName(name)) ApplySymmetricRotation(&by_table);
    SetDwaOption(name, text, &by_name);
  }
  EXPECT_DOUBLE_EQ(by_table.max_vel_theta, 0.7);
  EXPECT_DOUBLE_EQ(by_table.min_vel_theta, -0.7);
  EXPECT_DOUBLE_EQ(by_table.min_vel_theta, by_name.min_vel_theta);
  EXPECT_DOUBLE_EQ(by_table.rot_stopped_vel, by_name.rot_stopped_vel);
  EXPECT_EQ(by_table.vtheta_samples, 7);
  EXPECT_FALSE(by_table.dwa);
  for (const std::string& name : DwaAliasOptionTable().Names()) {
    EXPECT_FALSE(DwaOptionTable().Has(name)) << name;
    EXPECT_FALSE(IsIgnoredDwaOptionName(name)) << name;
  }
}

TEST(DwaOptionsTest, HolonomicOnlyNamesAreAcceptedAndIgnored) {
  DwaOptions o;
  const DwaOptions before = o;
  for (const std::string& name : DwaIgnoredOptionNames()) {
    EXPECT_TRUE(IsDwaOptionName(name)) << name;
    EXPECT_TRUE(IsIgnoredDwaOptionName(name)) << name;
    EXPECT_NO_THROW(SetDwaOption(name, "[-0.3, -0.1, 0.1, 0.3]", &o)) << name;
  }
  EXPECT_DOUBLE_EQ(o.max_vel_x, before.max_vel_x);
  EXPECT_TRUE(IsIgnoredDwaOptionName("y_vels"));
  EXPECT_TRUE(IsIgnoredDwaOptionName("max_vel_y"));
  EXPECT_FALSE(IsIgnoredDwaOptionName("max_vel_x"));
}

TEST(DwaOptionsTest, UnknownNameAndBadTextAreReported) {
  DwaOptions o;
  try {
    SetDwaOption("max_vel_xx", "1", &o);
    FAIL() << "unknown name accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_vel_xx"), std::string::npos);
  }
  try {
    SetDwaOption("vx_samples", "3.5", &o);
    FAIL() << "bad integer accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vx_samples"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("3.5"), std::string::npos);
  }
  EXPECT_THROW(SetDwaOption("dwa", "yes please", &o), std::invalid_argument);
  EXPECT_FALSE(IsDwaOptionName("max_vel_xx"));
}

TEST(DwaOptionsTest, NamesListCanonicalOptionsOnly) {
  const auto names = DwaOptionNames();
  auto has = [&names](const std::string& n) {
    for (const auto& x : names) {
      if (x == n) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("max_vel_x"));
  EXPECT_TRUE(has("controller_frequency"));
  EXPECT_TRUE(has("holonomic_robot"));
  EXPECT_FALSE(has("acc_lim_th"));  // alias
  EXPECT_FALSE(has("y_vels"));      // ignored
  for (const auto& n : names) EXPECT_TRUE(IsDwaOptionName(n)) << n;
}

TEST(DwaOptionsTest, HolonomicRobotIsRejectedWithAClearMessage) {
  DwaOptions o;
  SetDwaOption("holonomic_robot", "true", &o);
  const std::string msg = ValidationMessage(o);
  EXPECT_NE(msg.find("holonomic_robot=true"), std::string::npos) << msg;
  EXPECT_NE(msg.find("skid-steer"), std::string::npos) << msg;
  EXPECT_NE(msg.find("holonomic_robot: false"), std::string::npos) << msg;
}

TEST(DwaOptionsTest, ValidationListsEveryBadValue) {
  DwaOptions o;
  o.min_vel_x = 0.8;
  o.max_vel_x = 0.5;
  o.acc_lim_x = 0.0;
  o.acc_lim_theta = -1.0;
  o.vx_samples = 0;
  o.vtheta_samples = -3;
  o.sim_time = 0.0;
  o.sim_granularity = -0.1;
  o.xy_goal_tolerance = -0.1;
  o.escape_vel = 0.2;
  o.controller_frequency = 0.0;
  const std::string msg = ValidationMessage(o);
  for (const char* expected :
       {"min_vel_x=0.8 > max_vel_x=0.5", "acc_lim_x=0 must be > 0",
        "acc_lim_theta=-1 must be > 0", "vx_samples=0 must be >= 1",
        "vtheta_samples=-3 must be >= 1", "sim_time=0 must be > 0",
        "sim_granularity=-0.1 must be > 0",
        "xy_goal_tolerance=-0.1 must be > 0", "escape_vel=0.2 must be <= 0",
        "controller_frequency=0 must be > 0"}) {
    EXPECT_NE(msg.find(expected), std::string::npos)
        << "missing '" << expected << "' in: " << msg;
  }
}

TEST(DwaOptionsTest, DwaPlannerRosMinVelThetaMeaningGetsAHint) {
  DwaOptions o;
  SetDwaOption("min_vel_theta", "0.4", &o);  // DWAPlannerROS: min |vtheta|
  const std::string msg = ValidationMessage(o);
  EXPECT_NE(msg.find("min_vel_theta=0.4 must be < 0"), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("min_in_place_vel_theta"), std::string::npos) << msg;
}

TEST(DwaOptionsTest, RejectsNanAndRolloutShorterThanPeriod) {
  DwaOptions o;
  o.max_vel_theta = std::nan("");
  o.sim_time = 0.1;
  o.controller_frequency = 5.0;
  const std::string msg = ValidationMessage(o);
  EXPECT_NE(msg.find("max_vel_theta=nan"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sim_time=0.1 is shorter than one control period"),
            std::string::npos)
      << msg;
}

}  // namespace
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
