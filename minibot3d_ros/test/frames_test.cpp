// A robot's frame names (frame_names.h) without a master: every case of frame_names_cases.txt, the
// table test_frames.py also runs through the Python nodes' resolver, so both resolve alike.
#include "minibot3d_ros/frame_names.h"

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_ros {
namespace {

namespace options = minibot3d_common::options;

struct Case {
  int line = 0;
  std::string prefix, shared, frame, resolved;
};

std::vector<Case> ReadCases() {
  std::ifstream in(MINIBOT3D_FRAME_CASES);
  EXPECT_TRUE(in.good()) << MINIBOT3D_FRAME_CASES;
  std::vector<Case> cases;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (options::Trim(line).empty() || options::Trim(line)[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, '|')) f.push_back(options::Trim(field));
    if (f.size() == 3) f.push_back("");  // an empty last field
    EXPECT_EQ(f.size(), 4u) << "line " << n << ": " << line;
    if (f.size() != 4) continue;
    cases.push_back(Case{n, f[0], f[1], f[2], f[3]});
  }
  return cases;
}

TEST(FramesTest, EveryCaseOfTheTable) {
  const std::vector<Case> cases = ReadCases();
  ASSERT_GE(cases.size(), 20u);
  for (const Case& c : cases) {
    FrameOptions o;
    FrameOptionTable().Set("frame_prefix", c.prefix, &o);
    FrameOptionTable().Set("shared_frames", c.shared, &o);
    SCOPED_TRACE("line " + std::to_string(c.line) + ": prefix '" + c.prefix + "', shared '" +
                 c.shared + "', frame '" + c.frame + "'");
    if (c.resolved == "!") {
      EXPECT_THROW(FrameNames{o}, std::invalid_argument);
      continue;
    }
    EXPECT_EQ(FrameNames(o).Resolve(c.frame), c.resolved);
  }
}

TEST(FramesTest, DefaultsShareTheMapAndPrefixNothing) {
  const FrameNames none;
  EXPECT_EQ(none.prefix(), "");
  EXPECT_EQ(none.Resolve("odom"), "odom");
  FrameOptions o;
  EXPECT_EQ(o.shared_frames, std::vector<std::string>{"map"});
  o.frame_prefix = "robot3";
  const FrameNames r(o);
  EXPECT_EQ(r.prefix(), "robot3");
  EXPECT_EQ(r.Resolve("map"), "map");
  EXPECT_EQ(r.Resolve("base_link"), "robot3/base_link");
}

TEST(FramesTest, ARefusedValueIsNamed) {
  FrameOptions o;
  o.frame_prefix = "robot one";
  try {
    FrameNames n(o);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("frame_prefix"), std::string::npos) << e.what();
  }
  o.frame_prefix = "robot1";
  o.shared_frames = {"map", "my world"};
  try {
    FrameNames n(o);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shared_frames"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace minibot3d_ros
