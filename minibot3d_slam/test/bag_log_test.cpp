// Tests of the streaming bag reader (bag_log.h) on a small bag written here (no roscore needed).
#include "minibot3d_slam/bag_log.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

namespace minibot3d_slam {
namespace {

class TempBag {
 public:
  TempBag() {
    char name[] = "/tmp/bag_log_test_XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) throw std::runtime_error("mkstemp failed");
    close(fd);
    path_ = std::string(name) + ".bag";
    std::remove(name);
  }
  ~TempBag() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

geometry_msgs::TransformStamped Transform(const std::string& parent, const std::string& child, double t,
                                          double x, double yaw) {
  geometry_msgs::TransformStamped s;
  s.header.stamp = ros::Time(t);
  s.header.frame_id = parent;
  s.child_frame_id = child;
  s.transform.translation.x = x;
  s.transform.rotation.z = std::sin(yaw / 2);
  s.transform.rotation.w = std::cos(yaw / 2);
  return s;
}

// A bag of 1 s: odom → base_footprint at 20 Hz moving along x at 1 m/s, base_footprint → laser
// 0.2 m ahead (static), and scans at 5 Hz from 1.125 s on, each written before the transform after
// its stamp (the reader must wait for it), plus one scan before any transform.
void WriteBag(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage fixed;
  fixed.transforms.push_back(Transform("base_footprint", "laser", 1.0, 0.2, 0.0));
  bag.write("/tf_static", ros::Time(1.0), fixed);
  auto scan = [&](double t) {
    sensor_msgs::LaserScan s;
    s.header.stamp = ros::Time(t);
    s.header.frame_id = "laser";
    s.angle_min = -1.0;
    s.angle_increment = 0.5;
    s.range_min = 0.1;
    s.range_max = 10.0;
    s.ranges = {1.0f, static_cast<float>(t), INFINITY, 10.0f, 2.0f};
    bag.write("/scan", ros::Time(t), s);
  };
  scan(0.5);  // before the first odometry transform: cannot be placed
  for (int i = 0; i <= 20; ++i) {
    const double t = 1.0 + 0.05 * i;
    tf2_msgs::TFMessage m;
    m.transforms.push_back(Transform("odom", "base_footprint", t, t - 1.0, 0.1));
    bag.write("/tf", ros::Time(t), m);
    if (i % 4 == 2) scan(t + 0.025);
  }
  bag.close();
}

TEST(BagLogStreamTest, YieldsPlacedScansInOrderAndRewinds) {
  const TempBag f;
  WriteBag(f.path());
  std::unique_ptr<LogReader> reader = OpenBagLog(f.path(), BagLogOptions{});
  for (int pass = 0; pass < 2; ++pass) {
    LogScan s;
    for (int k = 0; k < 5; ++k) {
      ASSERT_TRUE(reader->Next(&s)) << "pass " << pass << " scan " << k;
      const double t = 1.125 + 0.2 * k;
      EXPECT_NEAR(s.timestamp, t, 1e-6);
      EXPECT_NEAR(s.scan.time, t, 1e-6);
      EXPECT_NEAR(s.odom.x, t - 1.0, 1e-6);  // interpolated between two transforms
      EXPECT_NEAR(s.odom.yaw, 0.1, 1e-6);
      EXPECT_NEAR(s.scan.sensor_in_base.x, 0.2, 1e-9);
      ASSERT_EQ(s.scan.ranges.size(), 5u);
      EXPECT_NEAR(s.scan.ranges[1], t, 1e-6);
      EXPECT_TRUE(std::isinf(s.scan.ranges[2]));  // no return
      EXPECT_TRUE(std::isinf(s.scan.ranges[3]));  // at range_max
      EXPECT_NEAR(s.scan.angles[4], 1.0, 1e-9);
    }
    EXPECT_FALSE(reader->Next(&s));
    reader->Rewind();
  }
  // The scan before any odometry is skipped, counted and reported once, not once per pass.
  EXPECT_EQ(reader->report().skipped.at("scan without tf"), 1);
  ASSERT_EQ(reader->report().warnings.size(), 1u);
  EXPECT_EQ(reader->report().warnings[0].rfind(f.path() + ": scan at 0.5", 0), 0u) << reader->report().warnings[0];
}

// With odometry from a nav_msgs/Odometry topic instead of /tf.
TEST(BagLogStreamTest, OdometryTopicPlacesScans) {
  const TempBag f;
  {
    rosbag::Bag bag(f.path(), rosbag::bagmode::Write);
    tf2_msgs::TFMessage fixed;
    fixed.transforms.push_back(Transform("base_footprint", "laser", 1.0, 0.2, 0.0));
    bag.write("/tf_static", ros::Time(1.0), fixed);
    for (int i = 0; i <= 100; ++i) {
      const double t = 1.0 + 0.1 * i;
      nav_msgs::Odometry o;
      o.header.stamp = ros::Time(t);
      o.pose.pose.position.y = 2.0 * (t - 1.0);
      o.pose.pose.orientation.w = 1.0;
      bag.write("/odom", ros::Time(t), o);
      sensor_msgs::LaserScan s;
      s.header.stamp = ros::Time(t + 0.05);
      s.header.frame_id = "laser";
      s.angle_increment = 0.1;
      s.range_max = 10.0;
      s.ranges = {1.0f, 2.0f};
      bag.write("/scan", ros::Time(t + 0.05), s);
    }
  }
  BagLogOptions o;
  o.odom_topic = "/odom";
  std::unique_ptr<LogReader> reader = OpenBagLog(f.path(), o);
  LogScan s;
  int n = 0;
  while (reader->Next(&s)) {
    EXPECT_NEAR(s.odom.y, 2.0 * (s.timestamp - 1.0), 1e-6) << n;
    ++n;
  }
  EXPECT_EQ(n, 100);  // the last scan is after the last odometry message
  EXPECT_EQ(reader->report().skipped.at("scan without tf"), 1);
}

TEST(BagLogStreamTest, MissingBagOrScanTopicIsAnErrorNamingTheBag) {
  try {
    OpenBagLog("/nonexistent/dir/drive.bag", BagLogOptions{});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/drive.bag"), std::string::npos) << e.what();
  }
  const TempBag f;
  WriteBag(f.path());
  BagLogOptions o;
  o.scan_topic = "/base_scan";
  try {
    OpenBagLog(f.path(), o);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(f.path()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/base_scan"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace minibot3d_slam
