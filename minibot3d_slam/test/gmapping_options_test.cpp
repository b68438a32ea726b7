// Tests of the gmapping options: validation messages, setting by name, the shipped configuration.
#include "minibot3d_slam/gmapping_options.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

#include "minibot3d_slam/node_options.h"

namespace minibot3d_slam {
namespace {

std::string ValidationMessage(const GmappingOptions& o) {
  try {
    ValidateOptions(o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(GmappingOptionsTest, DefaultsAreValid) { EXPECT_NO_THROW(ValidateOptions(GmappingOptions{})); }

TEST(GmappingOptionsTest, MessageNamesEveryOffendingParameterWithItsValue) {
  GmappingOptions o;
  o.particles = 0;
  o.delta = -0.5;
  o.resampleThreshold = 1.5;
  o.maxRange = 10.0;  // below maxUrange = 80
  o.srt = -0.1;
  o.kernelSize = -1;
  o.lsigma = 0.0;
  const std::string m = ValidationMessage(o);
  for (const char* part : {"particles=0", "delta=-0.5", "resampleThreshold=1.5", "maxRange=10",
                           "srt=-0.1", "kernelSize=-1", "lsigma=0"}) {
    EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
  }
  EXPECT_EQ(m.find("sigma=0.05"), std::string::npos) << m;  // valid ones are not named
}

TEST(GmappingOptionsTest, RangesAndExtents) {
  GmappingOptions o;
  o.maxRange = 80.0;  // == maxUrange is fine
  EXPECT_NO_THROW(ValidateOptions(o));
  o.resampleThreshold = 1.0;
  EXPECT_NO_THROW(ValidateOptions(o));
  o.xmin = 5.0;
  o.xmax = 5.0;
  EXPECT_NE(ValidationMessage(o).find("xmin=5"), std::string::npos);
  o = GmappingOptions{};
  o.ymax = -200.0;
  EXPECT_NE(ValidationMessage(o).find("ymax=-200"), std::string::npos);
  o = GmappingOptions{};
  o.resampleThreshold = 0.0;
  EXPECT_NE(ValidationMessage(o).find("resampleThreshold=0"), std::string::npos);
  o = GmappingOptions{};
  o.maxUrange = 0.0;
  EXPECT_NE(ValidationMessage(o).find("maxUrange=0"), std::string::npos);
  o = GmappingOptions{};
  o.iterations = -1;
  o.lskip = -2;
  o.llsamplestep = 0.0;
  const std::string m = ValidationMessage(o);
  EXPECT_NE(m.find("iterations=-1"), std::string::npos) << m;
  EXPECT_NE(m.find("lskip=-2"), std::string::npos) << m;
  EXPECT_NE(m.find("llsamplestep=0"), std::string::npos) << m;
}

TEST(GmappingOptionsTest, SubcellMatchAndSampleProposalAreSwitches) {
  GmappingOptions o;
  EXPECT_EQ(o.subcellMatch, 1);    // on: it lowers the Intel log's error (scan_matcher.h)
  EXPECT_EQ(o.sampleProposal, 0);  // gmapping's code: the matched pose, not a draw around it
  SetOption(&o, "subcellMatch", "0");
  SetOption(&o, "sampleProposal", "1");
  EXPECT_EQ(o.subcellMatch, 0);
  EXPECT_EQ(o.sampleProposal, 1);
  EXPECT_NO_THROW(ValidateOptions(o));
  o.subcellMatch = 2;
  o.sampleProposal = -1;
  const std::string m = ValidationMessage(o);
  EXPECT_NE(m.find("subcellMatch=2 must be 0 or 1"), std::string::npos) << m;
  EXPECT_NE(m.find("sampleProposal=-1 must be 0 or 1"), std::string::npos) << m;
  EXPECT_THROW(SetOption(&o, "subcellMatch", "true"), std::invalid_argument);
}

TEST(GmappingOptionsTest, TurnSlipIsAFractionOfTheTurn) {
  GmappingOptions o;
  EXPECT_DOUBLE_EQ(o.turnSlip, 0.5);
  SetOption(&o, "turnSlip", "0");
  EXPECT_NO_THROW(ValidateOptions(o));
  o.turnSlip = 1.5;
  EXPECT_NE(ValidationMessage(o).find("turnSlip=1.5 must be in [0, 1]"), std::string::npos);
  o.turnSlip = -0.1;
  EXPECT_NE(ValidationMessage(o).find("turnSlip=-0.1 must be in [0, 1]"), std::string::npos);
}

TEST(GmappingOptionsTest, LoopClosureOptionsAreValidatedAndSetByName) {
  GmappingOptions o;
  EXPECT_EQ(o.loopClosure, 1);
  SetOption(&o, "loopClosure", "0");
  SetOption(&o, "loopSearchWindow", "6.5");
  SetOption(&o, "loopSearchAngle", "0.5");
  SetOption(&o, "loopDriftRate", "0.05");
  SetOption(&o, "loopMaxSearchWindow", "12");
  EXPECT_EQ(o.loopCorridors, 0);
  SetOption(&o, "loopCorridors", "1");
  SetOption(&o, "loopMinScore", "0.7");
  SetOption(&o, "loopSubmapScans", "30");
  SetOption(&o, "loopMinTravel", "20");
  EXPECT_EQ(o.loopClosure, 0);
  EXPECT_DOUBLE_EQ(o.loopSearchWindow, 6.5);
  EXPECT_DOUBLE_EQ(o.loopSearchAngle, 0.5);
  EXPECT_DOUBLE_EQ(o.loopDriftRate, 0.05);
  EXPECT_DOUBLE_EQ(o.loopMaxSearchWindow, 12.0);
  EXPECT_EQ(o.loopCorridors, 1);
  EXPECT_DOUBLE_EQ(o.loopMinScore, 0.7);
  EXPECT_EQ(o.loopSubmapScans, 30);
  EXPECT_DOUBLE_EQ(o.loopMinTravel, 20.0);
  EXPECT_NO_THROW(ValidateOptions(o));
  o.loopClosure = 2;
  o.loopSearchWindow = 0.0;
  o.loopSearchAngle = 4.0;
  o.loopMinScore = 1.5;
  o.loopSubmapScans = 1;
  o.loopMinTravel = -1.0;
  o.loopDriftRate = -0.1;
  o.loopMaxSearchWindow = 200.0;
  o.loopCorridors = 3;
  const std::string m = ValidationMessage(o);
  EXPECT_NE(m.find("loopClosure=2 must be 0 or 1"), std::string::npos) << m;
  EXPECT_NE(m.find("loopSearchWindow=0 must be in (0, 50] m"), std::string::npos) << m;
  EXPECT_NE(m.find("loopSearchAngle=4 must be in (0, pi] rad"), std::string::npos) << m;
  EXPECT_NE(m.find("loopMinScore=1.5 must be in (0, 1]"), std::string::npos) << m;
  EXPECT_NE(m.find("loopSubmapScans=1 must be in [2, 1000]"), std::string::npos) << m;
  EXPECT_NE(m.find("loopMinTravel=-1 must be >= 0 m"), std::string::npos) << m;
  EXPECT_NE(m.find("loopDriftRate=-0.1 must be in [0, 1] m per m"), std::string::npos) << m;
  EXPECT_NE(m.find("loopMaxSearchWindow=200 must be in [loopSearchWindow, 100] m"), std::string::npos) << m;
  EXPECT_NE(m.find("loopCorridors=3 must be 0 or 1"), std::string::npos) << m;
  EXPECT_THROW(SetOption(&o, "loopSubmapScans", "2.5"), std::invalid_argument);
  GmappingOptions w;  // the largest window below the smallest
  w.loopSearchWindow = 6.0;
  w.loopMaxSearchWindow = 5.0;
  EXPECT_NE(ValidationMessage(w).find("loopMaxSearchWindow=5 must be in [loopSearchWindow, 100] m"),
            std::string::npos)
      << ValidationMessage(w);
}

TEST(GmappingOptionsTest, ThreadsDefaultToOnePerCoreAndAreValidated) {
  GmappingOptions o;
  EXPECT_EQ(o.threads, 0);
  SetOption(&o, "threads", "2");
  EXPECT_EQ(o.threads, 2);
  EXPECT_NO_THROW(ValidateOptions(o));
  o.threads = -1;
  EXPECT_NE(ValidationMessage(o).find("threads=-1 must be in [0, 256] (0: one per CPU core)"), std::string::npos)
      << ValidationMessage(o);
  EXPECT_THROW(SetOption(&o, "threads", "two"), std::invalid_argument);
}

TEST(GmappingOptionsTest, ClearMaxRangeIsOffByDefaultValidatedAndSetByName) {
  GmappingOptions o;
  EXPECT_EQ(o.clearMaxRange, 0);  // gmapping's behaviour unless asked
  SetOption(&o, "clearMaxRange", "1");
  EXPECT_EQ(o.clearMaxRange, 1);
  EXPECT_NO_THROW(ValidateOptions(o));
  o.clearMaxRange = 2;
  const std::string m = ValidationMessage(o);
  EXPECT_NE(m.find("clearMaxRange=2 must be 0 or 1"), std::string::npos) << m;
  EXPECT_THROW(SetOption(&o, "clearMaxRange", "yes"), std::invalid_argument);
}

TEST(GmappingOptionsTest, SetOptionByGmappingName) {
  GmappingOptions o;
  SetOption(&o, "particles", "80");
  SetOption(&o, "linearUpdate", "0.25");
  SetOption(&o, "angularUpdate", " 0.1 ");
  SetOption(&o, "temporalUpdate", "-1");
  SetOption(&o, "srr", "1e-2");
  SetOption(&o, "srt", "0.3");
  SetOption(&o, "str", "0.4");
  SetOption(&o, "stt", "0.5");
  SetOption(&o, "kernelSize", "2");
  SetOption(&o, "lskip", "3");
  SetOption(&o, "iterations", "7");
  SetOption(&o, "maxUrange", "16");
  SetOption(&o, "maxRange", "20");
  SetOption(&o, "xmin", "-10");
  SetOption(&o, "occ_thresh", "0.3");
  SetOption(&o, "seed", "42");
  SetOption(&o, "minimumScore", "50");
  SetOption(&o, "delta", "0.1");
  EXPECT_EQ(o.particles, 80);
  EXPECT_DOUBLE_EQ(o.linearUpdate, 0.25);
  EXPECT_DOUBLE_EQ(o.angularUpdate, 0.1);
  EXPECT_DOUBLE_EQ(o.srr, 0.01);
  EXPECT_DOUBLE_EQ(o.srt, 0.3);
  EXPECT_DOUBLE_EQ(o.str, 0.4);
  EXPECT_DOUBLE_EQ(o.stt, 0.5);
  EXPECT_EQ(o.kernelSize, 2);
  EXPECT_EQ(o.lskip, 3);
  EXPECT_EQ(o.iterations, 7);
  EXPECT_DOUBLE_EQ(o.maxUrange, 16.0);
  EXPECT_DOUBLE_EQ(o.maxRange, 20.0);
  EXPECT_DOUBLE_EQ(o.xmin, -10.0);
  EXPECT_DOUBLE_EQ(o.occ_thresh, 0.3);
  EXPECT_EQ(o.seed, 42u);
  EXPECT_DOUBLE_EQ(o.minimumScore, 50.0);
  EXPECT_DOUBLE_EQ(o.delta, 0.1);
  for (const char* name : {"resampleThreshold", "sigma", "lstep", "astep", "lsigma", "ogain", "llsamplerange",
                           "llsamplestep", "lasamplerange", "lasamplestep", "ymin", "xmax", "ymax"}) {
    EXPECT_NO_THROW(SetOption(&o, name, "0.5")) << name;
  }
  EXPECT_DOUBLE_EQ(o.ogain, 0.5);
  EXPECT_DOUBLE_EQ(o.lasamplestep, 0.5);
}

TEST(GmappingOptionsTest, SetOptionRejectsBadValuesAndNames) {
  GmappingOptions o;
  for (const char* bad : {"2.5", "abc", "", "3x", "1e2"}) {
    try {
      SetOption(&o, "particles", bad);
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("particles"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(SetOption(&o, "kernelSize", "1.0"), std::invalid_argument);
  EXPECT_THROW(SetOption(&o, "seed", "-1"), std::invalid_argument);
  EXPECT_THROW(SetOption(&o, "delta", "0.05m"), std::invalid_argument);
  EXPECT_THROW(SetOption(&o, "delta", "nan"), std::invalid_argument);
  try {
    SetOption(&o, "maxurange", "10");  // names are case-sensitive, as in gmapping
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("maxurange"), std::string::npos) << e.what();
  }
  EXPECT_EQ(o.particles, 30);  // unchanged by the failures
}

// slam_gmapping reads every key of the shipped configuration through its two tables (so it warns
// about none of them), and every value parses and validates.
TEST(GmappingOptionsTest, ShippedConfigIsReadByTheTables) {
  const YAML::Node root = YAML::LoadFile(std::string(MINIBOT3D_SLAM_SOURCE_DIR) + "/../config/gmapping.yaml");
  GmappingOptions o;
  SlamGmappingNodeOptions node;
  int keys = 0;
  for (const auto& kv : root) {
    const std::string name = kv.first.as<std::string>();
    const std::string value = kv.second.as<std::string>();
    ++keys;
    if (SlamGmappingNodeOptionTable().Has(name)) {
      EXPECT_NO_THROW(SlamGmappingNodeOptionTable().Set(name, value, &node)) << name;
    } else {
      EXPECT_NO_THROW(SetOption(&o, name, value)) << name;
    }
  }
  EXPECT_GE(keys, 30);
  EXPECT_NO_THROW(ValidateOptions(o));
  EXPECT_NO_THROW(ValidateSlamGmappingNodeOptions(node));
  EXPECT_EQ(node.base_frame, "base_footprint");
  EXPECT_EQ(o.clearMaxRange, 1);
}

TEST(GmappingOptionsTest, NodeOptionsAreValidated) {
  EXPECT_NO_THROW(ValidateSlamGmappingNodeOptions(SlamGmappingNodeOptions{}));
  SlamGmappingNodeOptions node;
  node.throttle_scans = 0;
  node.map_update_interval = 0.0;
  node.transform_publish_period = -1.0;
  node.odom_frame = "";
  try {
    ValidateSlamGmappingNodeOptions(node);
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    for (const char* part : {"throttle_scans=0 must be >= 1", "map_update_interval=0 must be > 0",
                             "transform_publish_period=-1 must be >= 0", "odom_frame must not be empty"}) {
      EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
    }
  }
  EXPECT_THROW(ValidateMapServerOptions(MapServerOptions{""}), std::invalid_argument);
}

}  // namespace
}  // namespace minibot3d_slam
