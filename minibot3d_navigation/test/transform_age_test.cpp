// CheckTransformAge (src/transform_age.h): stale transforms, and a node and tf on different clocks
// (wall against sim time, both ways) named as such with the frames involved.
#include "../src/transform_age.h"

#include <string>

#include <gtest/gtest.h>

namespace minibot3d_navigation {
namespace {

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TransformAgeTest, FreshAndStaticTransformsAreFine) {
  EXPECT_TRUE(CheckTransformAge(100.0, 99.8, "odom", "base_link", 0.5).ok);
  EXPECT_TRUE(CheckTransformAge(100.0, 100.3, "odom", "base_link", 0.5).ok);  // a little ahead
  EXPECT_TRUE(CheckTransformAge(1.7e9, 0.0, "odom", "base_link", 0.5).ok);    // static
  EXPECT_TRUE(CheckTransformAge(1.7e9 + 5.0, 1.7e9 + 4.9, "map", "base_link", 0.5).ok);
}

TEST(TransformAgeTest, StaleOnTheSameClockSaysHowOld) {
  const TransformAge r = CheckTransformAge(100.0, 98.0, "map", "base_link", 0.5);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.clocks_disagree);
  EXPECT_TRUE(Has(r.why, "map <- base_link is 2.000 s old")) << r.why;
  EXPECT_TRUE(Has(r.why, "transform_tolerance 0.500 s")) << r.why;
}

TEST(TransformAgeTest, WallClockNodeAgainstSimTimeTf) {
  // The case: move_base started before /use_sim_time was set, mapless (odom <- base_link).
  const TransformAge r = CheckTransformAge(1795501703.5, 12.25, "odom", "base_link", 0.5);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.clocks_disagree);
  EXPECT_TRUE(Has(r.why, "move_base runs on wall time while tf is stamped with sim time"))
      << r.why;
  EXPECT_TRUE(Has(r.why, "odom <- base_link is stamped 12.250 s")) << r.why;
  EXPECT_TRUE(Has(r.why, "use_sim_time")) << r.why;
  EXPECT_FALSE(Has(r.why, "localizer")) << r.why;
  EXPECT_FALSE(Has(r.why, "odom -> odom")) << r.why;
}

TEST(TransformAgeTest, SimTimeNodeAgainstWallClockTf) {
  // The reverse: move_base on sim time, a tf publisher on the wall clock. Before, a transform from
  // the "future" passed as fresh.
  const TransformAge r = CheckTransformAge(12.25, 1795501703.5, "map", "base_link", 0.5);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.clocks_disagree);
  EXPECT_TRUE(Has(r.why, "move_base runs on sim time while tf is stamped with wall time"))
      << r.why;
  EXPECT_TRUE(Has(r.why, "publishing map -> base_link")) << r.why;
}

TEST(TransformAgeTest, FarApartOnOneKindOfClockIsNotCalledWallAgainstSim) {
  const TransformAge old_tf = CheckTransformAge(1.7e9 + 500.0, 1.7e9, "odom", "base_link", 0.5);
  EXPECT_FALSE(old_tf.ok);
  EXPECT_FALSE(old_tf.clocks_disagree);
  EXPECT_TRUE(Has(old_tf.why, "500.000 s old")) << old_tf.why;
  const TransformAge ahead = CheckTransformAge(10.0, 200.0, "odom", "base_link", 0.5, "explore");
  EXPECT_FALSE(ahead.ok);
  EXPECT_FALSE(ahead.clocks_disagree);
  EXPECT_TRUE(Has(ahead.why, "190.000 s ahead of explore's clock")) << ahead.why;
}

}  // namespace
}  // namespace minibot3d_navigation
