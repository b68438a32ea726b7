// Number formatting of the option tables' messages and docs.
#include "minibot3d_common/options.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace minibot3d_common {
namespace options {
namespace {

TEST(OptionsTest, NumIsTheShortestTextThatReadsBack) {
  EXPECT_EQ(Num(0.1), "0.1");
  EXPECT_EQ(Num(-0.5), "-0.5");
  EXPECT_EQ(Num(0.0), "0");
  EXPECT_EQ(Num(1e-6), "1e-06");
  EXPECT_EQ(Num(1234.5), "1234.5");
  EXPECT_EQ(Num(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(Num(std::numeric_limits<double>::infinity()), "inf");
}

TEST(OptionsTest, NumWritesWholeNumbersWithoutAnExponent) {
  EXPECT_EQ(Num(10.0), "10");
  EXPECT_EQ(Num(80.0), "80");
  EXPECT_EQ(Num(-200.0), "-200");
  EXPECT_EQ(Num(5000.0), "5000");
  EXPECT_EQ(Num(1e20), "1e+20");
}

TEST(OptionsTest, ProblemsNameEveryOffendingValue) {
  Problems p("node");
  p.Positive("rate", 0.0);
  p.NonEmpty("frame", "");
  p.NonEmpty("topic", "scan");
  p.InUnitInterval("ratio", 0.5);
  EXPECT_FALSE(p.empty());
  try {
    p.ThrowIfAny();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "invalid node parameters: rate=0 must be > 0; frame must not be empty");
  }
}

}  // namespace
}  // namespace options
}  // namespace minibot3d_common
