// Tests of the CARMEN log reader (carmen_log.h) on small logs written to temporary files.
#include "minibot3d_slam/carmen_log.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

namespace minibot3d_slam {
namespace {

class TempLog {
 public:
  explicit TempLog(const std::string& content) {
    char name[] = "/tmp/carmen_log_test_XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) throw std::runtime_error("mkstemp failed");
    close(fd);
    path_ = name;
    std::ofstream(path_) << content;
  }
  ~TempLog() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// FLASER with n readings produced by `reading(i)`.
template <class F>
std::string Flaser(int n, F reading, double x, double y, double th, double ox, double oy, double oth,
                   const std::string& ts) {
  std::ostringstream s;
  s << "FLASER " << n;
  for (int i = 0; i < n; ++i) s << " " << reading(i);
  s << " " << x << " " << y << " " << th << " " << ox << " " << oy << " " << oth << " " << ts << " nohost 0.5\n";
  return s.str();
}

TEST(CarmenLogTest, ReadsEveryMessageTypeAndSkipsMalformedLines) {
  std::string log;
  log += "# comment line\n";
  log += "PARAM robot_frontlaser_offset 0.0 nohost 0\n";
  log += "PARAM robot_use_sonar off nohost 0\n";
  log += "ODOM 0.0 0.0 0.0 0 0 0 976052857.337284 nohost 0.0\n";
  log += Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 1, 2, 0.1, 1, 2, 0.1, "976052857.337530");
  log += "TRUEPOS 0 0 0 0 0 0 976052857.5 nohost 0.1\n";
  log += "FLASER 5 1.0 2.0\n";                                            // line 7: truncated
  log += Flaser(3, [](int) { return "abc"; }, 0, 0, 0, 0, 0, 0, "1.0");  // line 8: non-number
  log += "FLASER 181 1 2 3 0 0 0 0 0 0 2.0 nohost 0.1\n";                   // line 9: fewer beams
  log += "ROBOTLASER1 0 -1.5 3.0 0.5 30.0 0.01 0 7 1 2 3 4 5 6 7 0 "
         "3.1 4.2 0.7 3.0 4.0 0.5 0.1 0.0 0.4 0.3 0.0 976052858.123456 nohost 1.0\n";
  log += "ROBOTLASER1 0 -1.5 3.0 0.5 30.0\n";                              // line 11: truncated
  log += "\n";
  log += "SYNC foo\n";
  log += Flaser(181, [](int i) { return 2.0 + 0.001 * i; }, 5, 6, 0.2, 5, 6, 0.2, "976052859.000001");
  const TempLog f(log);
  const CarmenLog c = ReadCarmenLog(f.path());
  ASSERT_EQ(c.scans.size(), 3u);
  EXPECT_EQ(c.lines, 14);
  EXPECT_EQ(c.skipped.at("ODOM"), 1);
  EXPECT_EQ(c.skipped.at("TRUEPOS"), 1);
  EXPECT_EQ(c.skipped.at("SYNC"), 1);
  EXPECT_EQ(c.skipped.at("PARAM"), 1);  // robot_use_sonar is not used
  EXPECT_EQ(c.skipped.at("FLASER"), 3);
  EXPECT_EQ(c.skipped.at("ROBOTLASER1"), 1);
  // Four malformed lines, and the note that the laser poses are no rigid mounting (see below).
  ASSERT_EQ(c.warnings.size(), 5u);
  EXPECT_NE(c.warnings[4].find("robot_frontlaser_offset"), std::string::npos) << c.warnings[4];
  EXPECT_NE(c.warnings[0].find(":7:"), std::string::npos) << c.warnings[0];
  EXPECT_NE(c.warnings[1].find(":8:"), std::string::npos) << c.warnings[1];
  EXPECT_NE(c.warnings[1].find("abc"), std::string::npos) << c.warnings[1];
  EXPECT_NE(c.warnings[2].find(":9:"), std::string::npos) << c.warnings[2];
  EXPECT_NE(c.warnings[2].find("181"), std::string::npos) << c.warnings[2];
  EXPECT_NE(c.warnings[3].find(":11:"), std::string::npos) << c.warnings[3];

  // FLASER: 180 beams from −90° in 1° steps (the 181st, +90°, is not logged); odometry fields.
  const LogScan& a = c.scans[0];
  ASSERT_EQ(a.scan.ranges.size(), 180u);
  EXPECT_NEAR(a.scan.angles.front(), -M_PI / 2, 1e-12);
  EXPECT_NEAR(a.scan.angles[1] - a.scan.angles[0], M_PI / 180, 1e-12);
  EXPECT_DOUBLE_EQ(a.scan.ranges[10], 1.1);
  EXPECT_DOUBLE_EQ(a.odom.x, 1.0);
  EXPECT_DOUBLE_EQ(a.odom.yaw, 0.1);
  EXPECT_DOUBLE_EQ(a.timestamp, 976052857.337530);
  EXPECT_DOUBLE_EQ(a.scan.time, a.timestamp);
  // 181 beams cover the whole 180°.
  const LogScan& b = c.scans[2];
  ASSERT_EQ(b.scan.angles.size(), 181u);
  EXPECT_NEAR(b.scan.angles.back(), M_PI / 2, 1e-12);
  EXPECT_NEAR(b.timestamp, 976052859.000001, 1e-7);
  // ROBOTLASER1: its own angles and max range; the robot pose is the odometry and the laser pose
  // relative to it the mounting (but it differs between messages here, so it is not a rigid mount
  // and the frontlaser offset, 0, is used).
  const LogScan& r = c.scans[1];
  ASSERT_EQ(r.scan.ranges.size(), 7u);
  EXPECT_NEAR(r.scan.angles[0], -1.5, 1e-12);
  EXPECT_NEAR(r.scan.angles[6], 1.5, 1e-12);
  EXPECT_DOUBLE_EQ(r.odom.x, 3.0);
  EXPECT_DOUBLE_EQ(r.odom.yaw, 0.5);
  EXPECT_DOUBLE_EQ(r.scan.range_max, 30.0);
  EXPECT_NEAR(r.timestamp, 976052858.123456, 1e-7);
}

TEST(CarmenLogTest, RigidLaserOffsetBecomesTheMounting) {
  std::string log;
  // The laser 0.25 m ahead of the odometry pose in every message.
  for (int k = 0; k < 4; ++k) {
    const double th = 0.3 * k, ox = 1.0 * k, oy = -0.5 * k;
    log += Flaser(180, [](int) { return 3.0; }, ox + 0.25 * std::cos(th), oy + 0.25 * std::sin(th), th, ox, oy,
                  th, std::to_string(100 + k));
  }
  const TempLog f(log);
  const CarmenLog c = ReadCarmenLog(f.path());
  ASSERT_EQ(c.scans.size(), 4u);
  for (const LogScan& s : c.scans) {
    // (the log holds 6 significant digits)
    EXPECT_NEAR(s.scan.sensor_in_base.x, 0.25, 1e-4);
    EXPECT_NEAR(s.scan.sensor_in_base.y, 0.0, 1e-4);
    EXPECT_NEAR(s.scan.sensor_in_base.yaw, 0.0, 1e-4);
  }
  EXPECT_DOUBLE_EQ(c.scans[2].odom.x, 2.0);
}

TEST(CarmenLogTest, DetectsTheSaturationValueAsNoReturn) {
  std::string log;
  for (int k = 0; k < 6; ++k) {
    log += Flaser(180, [k](int i) { return i % 9 == 0 ? 81.83 : 1.0 + 0.013 * i + 0.001 * k; }, 0, 0, 0, 0, 0, 0,
                  std::to_string(10 + k));
  }
  const TempLog f(log);
  const CarmenLog c = ReadCarmenLog(f.path());
  ASSERT_EQ(c.scans.size(), 6u);
  for (const LogScan& s : c.scans) {
    EXPECT_TRUE(std::isinf(s.scan.ranges[0]));
    EXPECT_TRUE(std::isinf(s.scan.ranges[9]));
    EXPECT_DOUBLE_EQ(s.scan.ranges[1], s.scan.ranges[1]);
    EXPECT_LT(s.scan.ranges[1], 10.0);
    EXPECT_DOUBLE_EQ(s.scan.range_max, 81.83);
  }
}

TEST(CarmenLogTest, RealMaximumReadingsAreKept) {
  // Distinct long readings: no value dominates, so nothing becomes a no-return.
  std::string log;
  for (int k = 0; k < 6; ++k) {
    log += Flaser(180, [k](int i) { return 1.0 + 0.11 * i + 0.0037 * k; }, 0, 0, 0, 0, 0, 0, std::to_string(k));
  }
  const TempLog f(log);
  const CarmenLog c = ReadCarmenLog(f.path());
  for (const LogScan& s : c.scans) {
    for (double r : s.scan.ranges) EXPECT_TRUE(std::isfinite(r));
  }
}

TEST(CarmenLogTest, FrontLaserMaxParamMarksNoReturns) {
  std::string log = "PARAM robot_front_laser_max 50.0 nohost 0\n";
  log += Flaser(180, [](int i) { return i == 7 ? 50.0 : 2.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, "1.0");
  const TempLog f(log);
  const CarmenLog c = ReadCarmenLog(f.path());
  ASSERT_EQ(c.scans.size(), 1u);
  EXPECT_TRUE(std::isinf(c.scans[0].scan.ranges[7]));
  EXPECT_TRUE(std::isfinite(c.scans[0].scan.ranges[8]));
  EXPECT_DOUBLE_EQ(c.scans[0].scan.range_max, 50.0);
}

TEST(CarmenLogTest, EmptyOrMissingLogsAreErrorsNamingTheFile) {
  const TempLog empty("");
  try {
    ReadCarmenLog(empty.path());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(empty.path()), std::string::npos) << e.what();
  }
  const TempLog only_odom("ODOM 0 0 0 0 0 0 1.0 nohost 0\nFLASER 180 1 2\n");
  EXPECT_THROW(ReadCarmenLog(only_odom.path()), std::runtime_error);
  try {
    ReadCarmenLog("/nonexistent/dir/log.clf");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/log.clf"), std::string::npos) << e.what();
  }
}

// The streaming reader (OpenCarmenLog) yields the readings one at a time, in order, with what only
// the whole log tells (here the saturation value, which first appears in the last message) applied
// from the first reading on, and the same readings again after Rewind().
TEST(CarmenLogStreamTest, YieldsReadingsInOrderWithWholeLogFactsAndRewinds) {
  std::string log;
  for (int k = 0; k < 5; ++k) {
    log += Flaser(180, [k](int i) { return 1.0 + 0.01 * i + 0.001 * k; }, k, 0, 0, k, 0, 0, std::to_string(100 + k));
  }
  // A resolution PARAM halfway applies to the readings after it only.
  log += "PARAM laser_front_laser_resolution 0.5 nohost 0\n";
  log += Flaser(180, [](int i) { return i % 3 == 0 ? 81.83 : 2.0 + 0.01 * i; }, 9, 0, 0, 9, 0, 0, "200");
  const TempLog f(log);
  std::unique_ptr<LogReader> reader = OpenCarmenLog(f.path());
  EXPECT_EQ(reader->report().lines, 7);
  EXPECT_TRUE(reader->report().warnings.empty());
  for (int pass = 0; pass < 2; ++pass) {
    LogScan s;
    for (int k = 0; k < 5; ++k) {
      ASSERT_TRUE(reader->Next(&s)) << "pass " << pass << " reading " << k;
      EXPECT_DOUBLE_EQ(s.timestamp, 100 + k);
      EXPECT_DOUBLE_EQ(s.odom.x, k);
      EXPECT_DOUBLE_EQ(s.scan.ranges[3], 1.03 + 0.001 * k);
      EXPECT_DOUBLE_EQ(s.scan.range_max, 81.83);  // known before the message that shows it
      EXPECT_NEAR(s.scan.angles[1] - s.scan.angles[0], M_PI / 180, 1e-12);
    }
    ASSERT_TRUE(reader->Next(&s));
    EXPECT_DOUBLE_EQ(s.timestamp, 200);
    EXPECT_TRUE(std::isinf(s.scan.ranges[0]));
    EXPECT_DOUBLE_EQ(s.scan.ranges[1], 2.01);
    EXPECT_NEAR(s.scan.angles[1] - s.scan.angles[0], 0.5 * M_PI / 180, 1e-12);
    EXPECT_FALSE(reader->Next(&s));
    EXPECT_FALSE(reader->Next(&s));  // stays at the end
    reader->Rewind();
  }
}

// Bad input: a garbled reading and a log cut off in the middle of its last line are skipped, each
// reported with the file and the line; the readings around them still come.
TEST(CarmenLogStreamTest, GarbledAndTruncatedLinesAreReportedByFileAndLine) {
  std::string log;
  log += Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, "1.0");
  std::string garbled = Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, "2.0");
  garbled.replace(garbled.find(" 1.5 "), 5, " 1.5x7 ");  // line 2
  log += garbled;
  log += Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, "3.0");
  const std::string last = Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, "4.0");
  log += last.substr(0, last.size() / 2);  // line 4, cut off mid-line without a newline
  const TempLog f(log);
  std::unique_ptr<LogReader> reader = OpenCarmenLog(f.path());
  const std::vector<std::string>& w = reader->report().warnings;
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].rfind(f.path() + ":2: FLASER line skipped", 0), 0u) << w[0];
  EXPECT_NE(w[0].find("1.5x7"), std::string::npos) << w[0];
  EXPECT_EQ(w[1].rfind(f.path() + ":4: FLASER line skipped", 0), 0u) << w[1];
  EXPECT_NE(w[1].find("fewer readings than the declared 180"), std::string::npos) << w[1];
  EXPECT_EQ(reader->report().skipped.at("FLASER"), 2);
  LogScan s;
  ASSERT_TRUE(reader->Next(&s));
  EXPECT_DOUBLE_EQ(s.timestamp, 1.0);
  ASSERT_TRUE(reader->Next(&s));
  EXPECT_DOUBLE_EQ(s.timestamp, 3.0);
  EXPECT_FALSE(reader->Next(&s));
}

// A log that changes between Open and the reading (cut short by a crashed copy, overwritten) is an
// error naming the file and the line, not a silently shorter run.
TEST(CarmenLogStreamTest, ALogChangedAfterOpenIsAnErrorNamingFileAndLine) {
  std::string log;
  for (int k = 0; k < 3; ++k) {
    log += Flaser(180, [](int i) { return 1.0 + 0.01 * i; }, 0, 0, 0, 0, 0, 0, std::to_string(k));
  }
  const TempLog f(log);
  std::unique_ptr<LogReader> reader = OpenCarmenLog(f.path());
  const std::string shorter = log.substr(0, log.find('\n') + 1) + "FLASER 180 1 2 3\n";
  std::ofstream(f.path()) << shorter;
  LogScan s;
  ASSERT_TRUE(reader->Next(&s));
  try {
    reader->Next(&s);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(f.path() + ":2: the log changed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace minibot3d_slam
